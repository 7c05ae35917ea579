#include "operator_client/video/arrival_report.h"

#include <algorithm>
#include <climits>

namespace mostar::client {

void ArrivalReport::Add(uint64_t sequence, SteadyTime arrival, size_t bytes) {
  if ((last_sequence_ && sequence <= *last_sequence_) ||
      pending_.size() >= 4 * VideoFeedback::kMaxArrivals) {
    ++not_recorded_;
    return;
  }
  last_sequence_ = sequence;
  pending_.push_back({sequence, arrival.time_since_epoch().count(),
                      static_cast<uint32_t>(std::min<size_t>(bytes, UINT32_MAX))});
}

std::vector<VideoFrameArrival> ArrivalReport::TakeDue(SteadyTime now) {
  std::vector<VideoFrameArrival> report;
  if (pending_.empty()) return report;
  if (last_report_ && now - *last_report_ < period_ &&
      pending_.size() < VideoFeedback::kMaxArrivals) {
    return report;
  }
  const size_t n = std::min(pending_.size(), VideoFeedback::kMaxArrivals);
  report.assign(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(n));
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(n));
  last_report_ = now;
  return report;
}

}  // namespace mostar::client
