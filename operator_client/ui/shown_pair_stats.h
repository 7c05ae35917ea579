// For the client's report: per shown pair, its capture-to-display age and the render time of the
// frame that showed it (ms), kept up to kMaxSamples (later ones are counted, not kept).
#pragma once

#include <cstddef>
#include <vector>

namespace mostar::ui {

class ShownPairStats {
 public:
  static constexpr size_t kMaxSamples = 100000;

  void Add(double display_age_ms, double frame_time_ms);
  // Nearest-rank percentile (0..100) of the kept samples; 0 when none.
  double DisplayAgePercentileMs(double percentile) const;
  double FrameTimePercentileMs(double percentile) const;
  double last_display_age_ms() const { return last_display_age_ms_; }
  size_t added() const { return added_; }
  // How a shown pair's overlay was drawn: moved to its capture time, or faded (not moved).
  void CountOverlay(bool moved, bool faded) {
    overlays_moved_ += moved;
    overlays_faded_ += faded;
  }
  size_t overlays_moved() const { return overlays_moved_; }
  size_t overlays_faded() const { return overlays_faded_; }

 private:
  std::vector<double> display_ages_ms_;
  std::vector<double> frame_times_ms_;
  double last_display_age_ms_ = 0;
  size_t added_ = 0;
  size_t overlays_moved_ = 0;
  size_t overlays_faded_ = 0;
};

}  // namespace mostar::ui
