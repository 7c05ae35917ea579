#include "robot_server/camera/bitrate_controller.h"

#include <algorithm>
#include <cmath>

namespace mostar::camera {

bool BitrateControllerOptions::IsValid(std::string* error) const {
  if (target_bits_per_s < 0) {
    *error = "target_bits_per_s must be >= 0 (0 = unlimited)";
    return false;
  }
  if (min_quality < 1 || max_quality > 100 || min_quality > max_quality) {
    *error = "need 1 <= min_quality <= max_quality <= 100";
    return false;
  }
  if (initial_quality < min_quality || initial_quality > max_quality) {
    *error = "initial_quality must be within [min_quality, max_quality]";
    return false;
  }
  if (scales.empty()) {
    *error = "scales must not be empty";
    return false;
  }
  for (size_t i = 0; i < scales.size(); ++i) {
    if (!(scales[i] > 0 && scales[i] <= 1) || (i > 0 && scales[i] >= scales[i - 1])) {
      *error = "scales must be decreasing and within (0, 1]";
      return false;
    }
  }
  if (max_frame_rate_divisor < 1) {
    *error = "max_frame_rate_divisor must be >= 1";
    return false;
  }
  if (!(headroom > 0 && headroom <= 1)) {
    *error = "headroom must be within (0, 1]";
    return false;
  }
  if (control_interval_pairs < 1) {
    *error = "control_interval_pairs must be >= 1";
    return false;
  }
  if (window <= Duration::zero()) {
    *error = "window must be > 0";
    return false;
  }
  if (!(congested_skip_fraction > 0 && congested_skip_fraction <= 1)) {
    *error = "congested_skip_fraction must be within (0, 1]";
    return false;
  }
  if (!(min_link_bits_per_s > 0)) {
    *error = "min_link_bits_per_s must be > 0";
    return false;
  }
  return true;
}

std::vector<double> DefaultScaleLadder(int width_px) {
  constexpr double kMinWidthPx = 320;
  std::vector<double> scales = {1.0};
  for (double half = 1.0; half * width_px > kMinWidthPx;) {
    if (0.75 * half * width_px < kMinWidthPx) break;
    scales.push_back(0.75 * half);
    half *= 0.5;
    if (half * width_px < kMinWidthPx) break;
    scales.push_back(half);
  }
  return scales;
}

BitrateController::BitrateController(const BitrateControllerOptions& options)
    : options_(options), quality_(options.initial_quality) {
  stats_.target_bits_per_s = options_.target_bits_per_s;
  stats_.quality = quality_;
  stats_.scale = LevelScale(0);
}

void BitrateController::SetTargetBitsPerSecond(double bits_per_s) {
  options_.target_bits_per_s = std::max(0.0, bits_per_s);
  stats_.target_bits_per_s = options_.target_bits_per_s;
}

int BitrateController::LevelCount() const {
  return static_cast<int>(options_.scales.size()) + options_.max_frame_rate_divisor - 1;
}

double BitrateController::LevelScale(int level) const {
  const int last = static_cast<int>(options_.scales.size()) - 1;
  return options_.scales[static_cast<size_t>(std::min(level, last))];
}

int BitrateController::LevelDivisor(int level) const {
  const int last = static_cast<int>(options_.scales.size()) - 1;
  return level <= last ? 1 : 1 + level - last;
}

double BitrateController::EffectiveTarget() const {
  const double target = options_.target_bits_per_s;
  const double link = link_bits_per_s_;
  if (target <= 0) return link;
  if (link <= 0) return target;
  return std::min(target, link);
}

EncodeSettings BitrateController::Current() const {
  EncodeSettings settings;
  settings.jpeg.quality = quality_;
  settings.jpeg.scale = LevelScale(level_);
  settings.frame_rate_divisor = LevelDivisor(level_);
  return settings;
}

BitrateStats BitrateController::Stats() const { return stats_; }

void BitrateController::OnPairEncoded(SteadyTime now, size_t bytes, bool sent) {
  window_.push_back({now, bytes, sent});
  while (!window_.empty() && now - window_.front().time > options_.window) window_.pop_front();

  // Rates over the window: pairs after the first one, over the time they span.
  size_t sent_bytes = 0, skipped = 0;
  for (size_t i = 0; i < window_.size(); ++i) {
    if (!window_[i].sent) ++skipped;
    if (i == 0) continue;
    if (window_[i].sent) sent_bytes += window_[i].bytes;
  }
  // Offered: recent pair size (EWMA, follows quality changes within a few pairs) x pair rate.
  // Achieved: what the window really sent.
  mean_pair_bytes_ = mean_pair_bytes_ <= 0
                         ? static_cast<double>(bytes)
                         : 0.5 * mean_pair_bytes_ + 0.5 * static_cast<double>(bytes);
  const double span_s = ToSeconds(window_.back().time - window_.front().time);
  if (window_.size() >= 2 && span_s > 0) {
    stats_.pair_rate_hz = static_cast<double>(window_.size() - 1) / span_s;
    stats_.offered_bits_per_s = 8.0 * mean_pair_bytes_ * stats_.pair_rate_hz;
    stats_.achieved_bits_per_s = 8.0 * static_cast<double>(sent_bytes) / span_s;
  }
  stats_.skipped_fraction = static_cast<double>(skipped) / static_cast<double>(window_.size());

  if (++pairs_since_control_ >= options_.control_interval_pairs) {
    pairs_since_control_ = 0;
    Control(now);
  }
  stats_.quality = quality_;
  stats_.scale = LevelScale(level_);
  stats_.frame_rate_divisor = LevelDivisor(level_);
  stats_.level = level_;
  stats_.link_bits_per_s = link_bits_per_s_;
}

void BitrateController::Control(SteadyTime now) {
  if (window_.size() < 3 || stats_.offered_bits_per_s <= 0) return;

  // Ack-clock link estimate: congested when many pairs are skipped at the source.
  const bool enough = window_.size() >= 10;
  if (enough && stats_.skipped_fraction > options_.congested_skip_fraction) {
    link_bits_per_s_ = std::max(options_.min_link_bits_per_s, stats_.achieved_bits_per_s);
  } else if (link_bits_per_s_ > 0 && stats_.skipped_fraction == 0) {
    // Probe upward: the link may have more room than the last congestion showed.
    link_bits_per_s_ = std::min(link_bits_per_s_ * 1.05, 1e12);
  }

  const double target = EffectiveTarget();
  const bool unlimited = target <= 0;
  const double ratio =
      unlimited ? 1e9 : options_.headroom * target / stats_.offered_bits_per_s;  // > 1: room

  if (ratio < 1.0) {
    const int step = std::clamp(static_cast<int>(std::lround(25.0 * (1.0 - ratio))), 1, 10);
    quality_ = std::max(options_.min_quality, quality_ - step);
  } else if (ratio > 1.15) {
    const int step = std::clamp(static_cast<int>(std::lround(4.0 * (ratio - 1.0))), 1, 3);
    quality_ = std::min(options_.max_quality, quality_ + step);
  }

  // Ladder steps need their condition to hold for half a hold period, and a hold period
  // since the last step.
  const bool hold_over = !has_level_change_ || now - last_level_change_ >= options_.level_hold;
  const bool want_down = quality_ == options_.min_quality && ratio < 0.95;
  if (!want_down) down_since_.reset();
  if (want_down && !down_since_) down_since_ = now;
  if (!hold_over) return;
  if (want_down && now - *down_since_ >= options_.level_hold / 2 && level_ + 1 < LevelCount()) {
    down_since_.reset();
    ++level_;
    last_level_change_ = now;
    has_level_change_ = true;
    window_.clear();  // rates of the old level do not describe the new one
    mean_pair_bytes_ = 0;
    return;
  }
  if (quality_ == options_.max_quality && level_ > 0) {
    // Predict the bitrate one level up (pixels ~ scale^2, pairs ~ 1/divisor); the quality
    // restarts at its minimum there, so the prediction made at maximum quality is pessimistic.
    const double up_scale = LevelScale(level_ - 1);
    const double scale = LevelScale(level_);
    const double predicted = stats_.offered_bits_per_s * (up_scale * up_scale) / (scale * scale) *
                             LevelDivisor(level_) / LevelDivisor(level_ - 1);
    if (unlimited || options_.headroom * target > 1.05 * predicted) {
      --level_;
      down_since_.reset();
      quality_ = unlimited ? options_.max_quality : options_.min_quality;
      last_level_change_ = now;
      has_level_change_ = true;
      window_.clear();
      mean_pair_bytes_ = 0;
    }
  }
}

}  // namespace mostar::camera
