#include "robot_server/camera/video_rate_control.h"

#include <algorithm>

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
  for (const auto& [id, viewer] : viewers_) {
    if (now - viewer.last_report > options_.viewer_timeout) continue;
    const double t = viewer.controller.stats().target_bits_per_s;
    target = target > 0 ? std::min(target, t) : t;
  }
  return target;
}

bool VideoRateControl::ShouldSkipFrame(SteadyTime now) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [id, viewer] : viewers_) {
    if (now - viewer.last_report > options_.viewer_timeout) continue;
    if (viewer.controller.ShouldSkipFrame(sent_, now)) return true;
  }
  return false;
}

VideoRateStats VideoRateControl::Stats(SteadyTime now) {
  std::lock_guard<std::mutex> lock(mutex_);
  VideoRateStats stats;
  stats.reports = reports_;
  stats.reports_refused = refused_;
  for (const auto& [id, viewer] : viewers_) {
    if (now - viewer.last_report > options_.viewer_timeout) continue;
    ++stats.viewers;
    const LinkRateStats& s = viewer.controller.stats();
    stats.target_bits_per_s = stats.target_bits_per_s > 0
                                  ? std::min(stats.target_bits_per_s, s.target_bits_per_s)
                                  : s.target_bits_per_s;
    stats.queue_ms = std::max(stats.queue_ms, s.predicted_queue_ms);
  }
  return stats;
}

}  // namespace mostar::camera
