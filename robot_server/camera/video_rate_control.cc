#include "robot_server/camera/video_rate_control.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace mostar::camera {

VideoRateControl::VideoRateControl(const VideoRateControlOptions& options) : options_(options) {}

void VideoRateControl::SetClassTarget(double bits_per_s) {
  std::lock_guard<std::mutex> lock(mutex_);
  class_target_ = bits_per_s;
  for (auto& [id, viewer] : viewers_) viewer.controller.SetMaxBitsPerSecond(bits_per_s);
}

void VideoRateControl::OnFrameSent(uint64_t sequence, SteadyTime now, uint32_t bytes) {
  std::lock_guard<std::mutex> lock(mutex_);
  sent_.Add(sequence, now, bytes);
}

void VideoRateControl::OnFeedback(const VideoFeedback& feedback, SteadyTime now) {
  for (size_t i = 1; i < feedback.arrivals.size(); ++i) {
    if (feedback.arrivals[i].sequence <= feedback.arrivals[i - 1].sequence) {
      std::lock_guard<std::mutex> lock(mutex_);
      ++refused_;
      return;
    }
  }
  std::lock_guard<std::mutex> lock(mutex_);
  ++reports_;
  auto it = viewers_.find(feedback.sender_id);
  if (it == viewers_.end()) {
    if (viewers_.size() >= options_.max_viewers) {
      auto stalest = std::min_element(viewers_.begin(), viewers_.end(), [](auto& a, auto& b) {
        return a.second.last_report < b.second.last_report;
      });
      viewers_.erase(stalest);
    }
    LinkRateOptions link = options_.link;
    if (class_target_ > 0) link.max_bits_per_s = std::max(class_target_, link.min_bits_per_s);
    it = viewers_.emplace(feedback.sender_id, Viewer{LinkRateController(link), now}).first;
  }
  it->second.last_report = now;
  it->second.controller.OnFeedback(feedback.arrivals, sent_, now);
}

double VideoRateControl::Target(double class_target, SteadyTime now) {
  std::lock_guard<std::mutex> lock(mutex_);
  double target = class_target > 0 ? class_target : 0;
  bool heard = false;
  double silent_cap = 0;  // lowest target of the viewers silent beyond the timeout (0: none)
  for (auto& [id, viewer] : viewers_) {
    if (now - viewer.last_report > options_.silent_cap) continue;
    const double t = viewer.controller.OnSilence(sent_, now);
    if (now - viewer.last_report > options_.viewer_timeout) {
      silent_cap = silent_cap > 0 ? std::min(silent_cap, t) : t;
      continue;
    }
    heard = true;
    target = target > 0 ? std::min(target, t) : t;
  }
  // Nobody has told the link yet (start, or every viewer quiet after an outage): start low
  // rather than fill a link of unknown size (see unreported_fraction), and below what starved
  // the viewers that went quiet.
  if (!heard) {
    if (target > 0) target *= options_.unreported_fraction;
    if (silent_cap > 0) target = target > 0 ? std::min(target, silent_cap) : silent_cap;
  }
  return target;
}

bool VideoRateControl::ShouldSkipFrame(SteadyTime now) {
  std::lock_guard<std::mutex> lock(mutex_);
  bool skip = false;
  for (const auto& [id, viewer] : viewers_) {
    if (now - viewer.last_report > options_.viewer_timeout) continue;
    if (viewer.controller.ShouldSkipFrame(sent_, now)) skip = true;
  }
  if (!skip) {
    skipping_since_.reset();
    return false;
  }
  if (!skipping_since_) skipping_since_ = now;
  if (now - *skipping_since_ >= options_.max_skip) {
    skipping_since_.reset();  // this frame goes out and measures the link
    return false;
  }
  return true;
}

VideoRateStats VideoRateControl::Stats(SteadyTime now) {
  std::lock_guard<std::mutex> lock(mutex_);
  VideoRateStats stats;
  stats.reports = reports_;
  stats.repair_deadline_ms = ToSeconds(auto_deadline_) * 1e3;
  stats.reports_refused = refused_;
  for (const auto& [id, viewer] : viewers_) {
    if (now - viewer.last_report > options_.viewer_timeout) continue;
    ++stats.viewers;
    const LinkRateStats& s = viewer.controller.stats();
    stats.target_bits_per_s = stats.target_bits_per_s > 0
                                  ? std::min(stats.target_bits_per_s, s.target_bits_per_s)
                                  : s.target_bits_per_s;
    stats.queue_ms = std::max(stats.queue_ms, s.predicted_queue_ms);
    stats.report_lag_ms = std::max(stats.report_lag_ms, s.report_lag_ms);
  }
  return stats;
}

std::optional<Duration> VideoRateControl::RepairDeadlineUpdate(SteadyTime now) {
  if (!options_.auto_repair_deadline) return std::nullopt;
  std::lock_guard<std::mutex> lock(mutex_);
  double lag_ms = 0;
  for (const auto& [id, viewer] : viewers_) {
    if (now - viewer.last_report > options_.viewer_timeout) continue;
    lag_ms = std::max(lag_ms, viewer.controller.stats().report_lag_ms);
  }
  if (lag_ms <= 0) return std::nullopt;
  const auto floor = options_.link.repair_hold + options_.auto_deadline_margin;
  auto wanted = std::chrono::duration_cast<Duration>(
      options_.link.repair_hold + std::chrono::microseconds(static_cast<int64_t>(1.5e3 * lag_ms)) +
      options_.auto_deadline_margin);
  wanted = std::clamp<Duration>(wanted, floor, options_.max_repair_deadline);
  wanted = std::chrono::ceil<std::chrono::milliseconds>(wanted);
  if (auto_deadline_ > Duration::zero()) {
    const double now_ms = ToSeconds(auto_deadline_) * 1e3;
    const double wanted_ms = ToSeconds(wanted) * 1e3;
    if (std::abs(wanted_ms - now_ms) <= options_.auto_deadline_change * now_ms) return std::nullopt;
    if (auto_deadline_set_ && now - *auto_deadline_set_ < options_.auto_deadline_interval) {
      return std::nullopt;
    }
  }
  auto_deadline_ = wanted;
  auto_deadline_set_ = now;
  return wanted;
}

std::string VideoRateControl::RepairDeadlineWarning(SteadyTime now) {
  if (options_.repair_deadline <= Duration::zero()) return "";
  std::lock_guard<std::mutex> lock(mutex_);
  const double deadline_ms = ToSeconds(options_.repair_deadline) * 1e3;
  const double hold_ms = ToSeconds(options_.link.repair_hold) * 1e3;
  for (const auto& [id, viewer] : viewers_) {
    if (now - viewer.last_report > options_.viewer_timeout) continue;
    const double lag_ms = viewer.controller.stats().report_lag_ms;
    if (lag_ms <= 0 || hold_ms + lag_ms < deadline_ms) continue;
    char line[320];
    std::snprintf(line, sizeof(line),
                  "the video repair deadline (%.0f ms) is shorter than a repair takes on %s's "
                  "link (repair period %.0f ms + round trip about %.0f ms): lost fragments are "
                  "given up, not repaired; raise dds.video_repair_deadline_ms above %.0f ms",
                  deadline_ms, id.substr(0, 64).c_str(), hold_ms, lag_ms, hold_ms + lag_ms + 50);
    return line;
  }
  return "";
}

std::string VideoRateControl::Describe(SteadyTime now) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::string out;
  for (const auto& [id, viewer] : viewers_) {
    if (now - viewer.last_report > options_.viewer_timeout) continue;
    const LinkRateStats& s = viewer.controller.stats();
    char line[256];
    std::snprintf(line, sizeof(line),
                  "%s%s: target %.2f Mbit/s, received %.2f Mbit/s, queue %.0f ms (%s), "
                  "%llu decreases (%llu in silence), %llu held back, report lag %.0f ms",
                  out.empty() ? "" : "; ", id.substr(0, 64).c_str(), s.target_bits_per_s / 1e6,
                  s.throughput_bits_per_s / 1e6, s.predicted_queue_ms, LinkUsageName(s.usage),
                  static_cast<unsigned long long>(s.decreases),
                  static_cast<unsigned long long>(s.silence_decreases),
                  static_cast<unsigned long long>(s.held_back), s.report_lag_ms);
    out += line;
  }
  return out;
}

}  // namespace mostar::camera
