#include "robot_server/camera/stereo_pairer.h"

#include <cstdlib>
#include <utility>

namespace mostar::camera {
namespace {

Duration Abs(Duration d) { return d < Duration::zero() ? -d : d; }

}  // namespace

bool StereoPairerOptions::IsValid(std::string* error) const {
  if (max_skew <= Duration::zero()) {
    *error = "max_skew must be > 0";
    return false;
  }
  if (max_pending < 1) {
    *error = "max_pending must be >= 1";
    return false;
  }
  if (drift_window_pairs < 2) {
    *error = "drift_window_pairs must be >= 2";
    return false;
  }
  return true;
}

StereoPairer::StereoPairer(const StereoPairerOptions& options) : options_(options) {}

void StereoPairer::AddLeft(TimedImage frame) {
  if (last_left_ && frame.stamp < *last_left_) {
    ++stats_.dropped_left;
    return;
  }
  last_left_ = frame.stamp;
  Add(std::move(frame), &left_, &stats_.dropped_left);
}

void StereoPairer::AddRight(TimedImage frame) {
  if (last_right_ && frame.stamp < *last_right_) {
    ++stats_.dropped_right;
    return;
  }
  last_right_ = frame.stamp;
  Add(std::move(frame), &right_, &stats_.dropped_right);
}

void StereoPairer::Add(TimedImage frame, std::deque<TimedImage>* queue, uint64_t* dropped) {
  queue->push_back(std::move(frame));
  Match();
  while (queue->size() > options_.max_pending) {
    queue->pop_front();
    ++*dropped;
  }
}

void StereoPairer::Match() {
  while (!left_.empty() && !right_.empty()) {
    const Time l = left_.front().stamp;
    const Time r = right_.front().stamp;
    const Duration skew = l - r;
    if (skew > options_.max_skew) {
      // Right is older than left by more than the tolerance: later lefts are even later.
      right_.pop_front();
      ++stats_.dropped_right;
      continue;
    }
    if (-skew > options_.max_skew) {
      left_.pop_front();
      ++stats_.dropped_left;
      continue;
    }
    // Within tolerance; prefer a closer partner already waiting behind either front.
    if (right_.size() > 1 && Abs(l - right_[1].stamp) < Abs(skew)) {
      right_.pop_front();
      ++stats_.dropped_right;
      continue;
    }
    if (left_.size() > 1 && Abs(left_[1].stamp - r) < Abs(skew)) {
      left_.pop_front();
      ++stats_.dropped_left;
      continue;
    }
    StereoImagePair pair;
    pair.sequence = next_sequence_++;
    pair.stamp = r + skew / 2;
    pair.left = std::move(left_.front().image);
    pair.right = std::move(right_.front().image);
    left_.pop_front();
    right_.pop_front();
    ++stats_.pairs;
    RecordSkew(pair.stamp, skew);
    ready_.push_back(std::move(pair));
    while (ready_.size() > options_.max_pending) {
      ready_.pop_front();
      ++stats_.dropped_pairs;
    }
  }
}

void StereoPairer::RecordSkew(Time pair_stamp, Duration skew) {
  stats_.last_skew = skew;
  skews_.emplace_back(pair_stamp, skew);
  while (skews_.size() > options_.drift_window_pairs) skews_.pop_front();
  // Least-squares slope of skew (ns) against time (s), relative to the first sample.
  const double n = static_cast<double>(skews_.size());
  const Time t0 = skews_.front().first;
  double sum_t = 0, sum_s = 0, sum_tt = 0, sum_ts = 0;
  for (const auto& [t, s] : skews_) {
    const double ts = ToSeconds(t - t0);
    const double sv = static_cast<double>(s.count());
    sum_t += ts;
    sum_s += sv;
    sum_tt += ts * ts;
    sum_ts += ts * sv;
  }
  stats_.mean_skew = Duration(static_cast<int64_t>(sum_s / n));
  const double denominator = n * sum_tt - sum_t * sum_t;
  stats_.drift_ns_per_s = (skews_.size() >= 2 && denominator > 1e-12)
                              ? (n * sum_ts - sum_t * sum_s) / denominator
                              : 0.0;
}

std::optional<StereoImagePair> StereoPairer::PopPair() {
  if (ready_.empty()) return std::nullopt;
  StereoImagePair pair = std::move(ready_.front());
  ready_.pop_front();
  return pair;
}

void StereoPairer::Reset() {
  left_.clear();
  right_.clear();
  ready_.clear();
  skews_.clear();
  last_left_.reset();
  last_right_.reset();
}

}  // namespace mostar::camera
