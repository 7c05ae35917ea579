// The AR feature builder for the options in force, rebuilt only when they change (the
// calibration panel edits them live; building precomputes the distance circles). Pure.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "operator_client/fusion/ar_features.h"

namespace mostar::ui {

// The options the overlay is built with: `ar` with the calibration's laser height and, while
// calibrating, rays and vertical lines on (they help to match the overlay to the image).
fusion::ArFeatureOptions OverlayArOptions(const fusion::ArFeatureOptions& ar, double laser_height_m,
                                          bool calibrating);

// Field-by-field equality (ArFeatureOptions has no operator==).
bool SameArOptions(const fusion::ArFeatureOptions& a, const fusion::ArFeatureOptions& b);

// The potential-outlier label of each beam (thesis 6.2) as `builder` segments `scan`: the labels
// edge processing confirms or not (thesis 8.4). The console takes them from the overlay's
// builder, so a live slopeTh edit moves them together with the drawn discontinuities.
std::vector<bool> PotentialOutliers(const fusion::ArFeatureBuilder& builder, const LaserScan& scan);

class ArBuilderCache {
 public:
  // `configured`: the options from the configuration; must be valid (asserted).
  explicit ArBuilderCache(const fusion::ArFeatureOptions& configured);

  // The builder for `options`, built only when they differ from the last call's. While they
  // are invalid: the configured builder, with the reason in `error` (on every such call).
  const fusion::ArFeatureBuilder& For(const fusion::ArFeatureOptions& options, std::string* error);
  const fusion::ArFeatureBuilder& configured() const { return configured_; }
  int builds() const { return builds_; }  // builders made by For() so far

 private:
  const fusion::ArFeatureBuilder configured_;
  fusion::ArFeatureOptions requested_;               // the last options asked for
  std::optional<fusion::ArFeatureBuilder> current_;  // for requested_; nullopt: invalid
  std::string error_;                                // why requested_ is invalid
  bool asked_ = false;
  int builds_ = 0;
};

}  // namespace mostar::ui
