#include "operator_client/ui/stereo_hint.h"

namespace mostar::ui {

std::optional<StereoOffsetHint> StereoHintGate::Hint(uint64_t sequence,
                                                     const vision::StereoOffsetEstimate& estimate,
                                                     float suggested_right_offset_y_px) const {
  if (!estimate.valid) return std::nullopt;
  if (stale_through_ && sequence <= *stale_through_) return std::nullopt;
  StereoOffsetHint hint;
  hint.suggested_right_offset_y_px = suggested_right_offset_y_px;
  hint.residual_px = estimate.vertical_offset_px;
  hint.spread_px = estimate.spread_px;
  hint.samples = estimate.samples;
  return hint;
}

}  // namespace mostar::ui
