#include "operator_client/ui/stereo_hint.h"

#include <gtest/gtest.h>

namespace mostar::ui {
namespace {

vision::StereoOffsetEstimate Estimate(double residual_px) {
  vision::StereoOffsetEstimate e;
  e.valid = true;
  e.vertical_offset_px = residual_px;
  e.spread_px = 0.5;
  e.samples = 30;
  return e;
}

TEST(StereoHintGateTest, ShowsAValidEstimateWithItsSuggestion) {
  const StereoHintGate gate;
  const std::optional<StereoOffsetHint> hint = gate.Hint(7, Estimate(4.8), -4.8f);
  ASSERT_TRUE(hint.has_value());
  EXPECT_FLOAT_EQ(hint->suggested_right_offset_y_px, -4.8f);
  EXPECT_DOUBLE_EQ(hint->residual_px, 4.8);
  EXPECT_EQ(hint->samples, 30);
}

TEST(StereoHintGateTest, HidesInvalidEstimates) {
  const StereoHintGate gate;
  EXPECT_FALSE(gate.Hint(7, vision::StereoOffsetEstimate{}, 0.f).has_value());
}

TEST(StereoHintGateTest, EstimatesOfPairsSubmittedBeforeAChangeAreStale) {
  StereoHintGate gate;
  gate.GeometryChanged(10);
  EXPECT_FALSE(gate.Hint(9, Estimate(4.8), -4.8f).has_value());
  EXPECT_FALSE(gate.Hint(10, Estimate(4.8), -4.8f).has_value());
  EXPECT_TRUE(gate.Hint(11, Estimate(0.2), -5.0f).has_value());
}

}  // namespace
}  // namespace mostar::ui
