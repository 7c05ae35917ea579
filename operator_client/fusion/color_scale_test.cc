#include "operator_client/fusion/color_scale.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mostar::fusion {
namespace {

void ExpectColor(const Rgba& c, float r, float g, float b) {
  EXPECT_FLOAT_EQ(c.r, r);
  EXPECT_FLOAT_EQ(c.g, g);
  EXPECT_FLOAT_EQ(c.b, b);
}

TEST(DistanceColorTest, PureRedAtAndBelowTheMinimum) {
  ExpectColor(DistanceColor(0.5f, 0.5f, 3.0f), 1.f, 0.f, 0.f);
  ExpectColor(DistanceColor(0.1f, 0.5f, 3.0f), 1.f, 0.f, 0.f);
  ExpectColor(DistanceColor(0.0f, 0.5f, 3.0f), 1.f, 0.f, 0.f);
}

TEST(DistanceColorTest, PureGreenAtAndAboveTheMaximum) {
  ExpectColor(DistanceColor(3.0f, 0.5f, 3.0f), 0.f, 1.f, 0.f);
  ExpectColor(DistanceColor(30.f, 0.5f, 3.0f), 0.f, 1.f, 0.f);
  ExpectColor(DistanceColor(INFINITY, 0.5f, 3.0f), 0.f, 1.f, 0.f);
}

TEST(DistanceColorTest, YellowAtTheMidpointAndLinearInBetween) {
  ExpectColor(DistanceColor(1.75f, 0.5f, 3.0f), 1.f, 1.f, 0.f);
  ExpectColor(DistanceColor(1.125f, 0.5f, 3.0f), 1.f, 0.5f, 0.f);  // a quarter of the way
  ExpectColor(DistanceColor(2.375f, 0.5f, 3.0f), 0.5f, 1.f, 0.f);  // three quarters
}

TEST(DistanceColorTest, RedNeverIncreasesAndGreenNeverDecreasesWithDistance) {
  Rgba previous = DistanceColor(0.f, 1.f, 2.f);
  for (float d = 0.f; d <= 3.f; d += 0.01f) {
    const Rgba c = DistanceColor(d, 1.f, 2.f);
    EXPECT_LE(c.r, previous.r);
    EXPECT_GE(c.g, previous.g);
    EXPECT_GE(c.r + c.g, 1.f - 1e-6f);  // always on the red-yellow-green edge
    previous = c;
  }
}

TEST(DistanceColorTest, CarriesAlphaAndGreysOutNaN) {
  EXPECT_FLOAT_EQ(DistanceColor(1.f, 0.5f, 3.f, 0.25f).a, 0.25f);
  const Rgba nan = DistanceColor(NAN, 0.5f, 3.f);
  EXPECT_FLOAT_EQ(nan.r, 0.5f);
  EXPECT_FLOAT_EQ(nan.g, 0.5f);
  EXPECT_FLOAT_EQ(nan.b, 0.5f);
}

}  // namespace
}  // namespace mostar::fusion
