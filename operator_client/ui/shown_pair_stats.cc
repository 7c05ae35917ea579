#include "operator_client/ui/shown_pair_stats.h"

#include "common/stats/percentile.h"

namespace mostar::ui {

void ShownPairStats::Add(double display_age_ms, double frame_time_ms) {
  last_display_age_ms_ = display_age_ms;
  ++added_;
  if (display_ages_ms_.size() >= kMaxSamples) return;
  display_ages_ms_.push_back(display_age_ms);
  frame_times_ms_.push_back(frame_time_ms);
}

double ShownPairStats::DisplayAgePercentileMs(double percentile) const {
  return Percentile(display_ages_ms_, percentile / 100.0).value_or(0.0);
}

double ShownPairStats::FrameTimePercentileMs(double percentile) const {
  return Percentile(frame_times_ms_, percentile / 100.0).value_or(0.0);
}

}  // namespace mostar::ui
