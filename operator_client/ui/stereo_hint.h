// NESC's vertical offset estimate (vision/nesc.h) turned into the calibration panel's
// suggestion, shown only when it was measured with the geometry in force. Pure.
#pragma once

#include <cstdint>
#include <optional>

#include "operator_client/vision/nesc.h"

namespace mostar::ui {

// What the panel shows and what its Apply button sets.
struct StereoOffsetHint {
  float suggested_right_offset_y_px = 0.f;  // the right eye's offset that cancels the residual
  double residual_px = 0.0;                 // > 0: right image content lower than expected
  double spread_px = 0.0;
  int samples = 0;
};

// An estimate is measured on one pair with the eyes' geometry of the moment it was submitted;
// once the offsets or the calibration change, estimates of pairs submitted before are stale
// (applying one would apply the same correction twice).
class StereoHintGate {
 public:
  // The geometry changed after the pair `last_submitted_sequence` was handed to the edge worker.
  void GeometryChanged(uint64_t last_submitted_sequence) {
    stale_through_ = last_submitted_sequence;
  }
  // The hint of the estimate of pair `sequence`, with `suggested_right_offset_y_px` computed for
  // it (render::SuggestedRightOffsetY); nullopt when the estimate is invalid or stale.
  std::optional<StereoOffsetHint> Hint(uint64_t sequence,
                                       const vision::StereoOffsetEstimate& estimate,
                                       float suggested_right_offset_y_px) const;

 private:
  std::optional<uint64_t> stale_through_;
};

}  // namespace mostar::ui
