#include "robot_server/drive/odometry.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mostar::drive {
namespace {

using std::chrono::milliseconds;

// Feeds an integrator with counters that advance by fixed ticks per 20 ms step.
class EncoderScript {
 public:
  EncoderScript(uint32_t left_start, uint32_t right_start, int bits)
      : left_(left_start), right_(right_start), mask_((uint64_t{1} << bits) - 1) {}
  EncoderReading Step(int64_t left_ticks, int64_t right_ticks) {
    left_ = static_cast<uint32_t>((int64_t{left_} + left_ticks) & static_cast<int64_t>(mask_));
    right_ = static_cast<uint32_t>((int64_t{right_} + right_ticks) & static_cast<int64_t>(mask_));
    time_ += milliseconds(20);
    return Now();
  }
  EncoderReading Now() const {
    EncoderReading r;
    r.stamp = FromUnixNanos(1'700'000'000'000'000'000) + time_;
    r.steady_stamp = SteadyTime(std::chrono::seconds(5)) + time_;
    r.left_count = left_;
    r.right_count = right_;
    return r;
  }

 private:
  uint32_t left_;
  uint32_t right_;
  uint64_t mask_;
  Duration time_{0};
};

OdometryOptions Morduc() {
  OdometryOptions o;
  o.wheel_radius_m = 0.1;
  o.track_width_m = 0.5;
  o.ticks_per_turn = 500;
  o.counter_bits = 16;
  return o;
}

TEST(WrappedTickDeltaTest, HandlesWrapInBothDirections) {
  EXPECT_EQ(WrappedTickDelta(65530, 4, 16), 10);
  EXPECT_EQ(WrappedTickDelta(4, 65530, 16), -10);
  EXPECT_EQ(WrappedTickDelta(0xFFFFFFF0u, 0x10u, 32), 32);
  EXPECT_EQ(WrappedTickDelta(0x10u, 0xFFFFFFF0u, 32), -32);
  EXPECT_EQ(WrappedTickDelta(100, 100, 12), 0);
  // Upper bits beyond the counter width are ignored.
  EXPECT_EQ(WrappedTickDelta(0x0001FFFFu, 0x00000003u, 16), 4);
}

TEST(OdometryIntegratorTest, FirstReadingIsOnlyAReference) {
  OdometryIntegrator odom(Morduc());
  EncoderScript script(1000, 2000, 16);
  EXPECT_FALSE(odom.AddReading(script.Now()));
  EXPECT_EQ(odom.odometry().pose.x_m, 0.0);
  EXPECT_EQ(odom.stats().readings, 0u);
}

TEST(OdometryIntegratorTest, StraightLineOneWheelTurn) {
  OdometryIntegrator odom(Morduc());
  EncoderScript script(0, 0, 16);
  odom.AddReading(script.Now());
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(odom.AddReading(script.Step(25, 25)));
  const Odometry& o = odom.odometry();
  const double turn_m = 2 * M_PI * 0.1;
  EXPECT_NEAR(o.pose.x_m, turn_m, 1e-12);
  EXPECT_NEAR(o.pose.y_m, 0.0, 1e-12);
  EXPECT_NEAR(o.pose.theta_rad, 0.0, 1e-12);
  EXPECT_NEAR(o.linear_mps, turn_m / 20 / 0.02, 1e-9);
  EXPECT_NEAR(o.angular_radps, 0.0, 1e-12);
  // Variance along the path grows with distance; lateral variance follows heading variance.
  EXPECT_NEAR(o.pose_variance[0], 0.5 * 1e-4 * turn_m, 1e-12);
  EXPECT_GT(o.pose_variance[1], 0.0);
  EXPECT_GT(o.pose_variance[2], 0.0);
}

TEST(OdometryIntegratorTest, ReverseDrivesBackwards) {
  OdometryIntegrator odom(Morduc());
  EncoderScript script(100, 100, 16);
  odom.AddReading(script.Now());
  for (int i = 0; i < 5; ++i) odom.AddReading(script.Step(-20, -20));
  EXPECT_LT(odom.odometry().pose.x_m, 0.0);
  EXPECT_LT(odom.odometry().linear_mps, 0.0);
}

TEST(OdometryIntegratorTest, RotationInPlaceKeepsPosition) {
  OdometryIntegrator odom(Morduc());
  EncoderScript script(0, 0, 16);
  odom.AddReading(script.Now());
  const double mpt = Morduc().metres_per_tick();
  for (int i = 0; i < 20; ++i) odom.AddReading(script.Step(-10, 10));
  const Odometry& o = odom.odometry();
  EXPECT_NEAR(o.pose.x_m, 0.0, 1e-12);
  EXPECT_NEAR(o.pose.y_m, 0.0, 1e-12);
  EXPECT_NEAR(o.pose.theta_rad, 20 * 20 * mpt / 0.5, 1e-12);
  EXPECT_NEAR(o.angular_radps, 20 * mpt / 0.5 / 0.02, 1e-9);
  EXPECT_NEAR(o.linear_mps, 0.0, 1e-12);
  EXPECT_GT(o.pose_variance[2], 0.0);  // wheels rolled: heading uncertainty grows
}

TEST(OdometryIntegratorTest, CircleClosesAndHasTheRightRadius) {
  OdometryIntegrator odom(Morduc());
  EncoderScript script(0, 0, 16);
  odom.AddReading(script.Now());
  // 10 and 20 ticks per step: radius = b/2 * (20 + 10) / (20 - 10) = 0.75 m, 250 steps a lap.
  for (int i = 0; i < 125; ++i) odom.AddReading(script.Step(10, 20));
  EXPECT_NEAR(odom.odometry().pose.x_m, 0.0, 1e-9);
  EXPECT_NEAR(odom.odometry().pose.y_m, 1.5, 1e-9);
  EXPECT_NEAR(std::abs(odom.odometry().pose.theta_rad), M_PI, 1e-9);
  const double half_lap_variance = odom.odometry().pose_variance[2];
  for (int i = 0; i < 125; ++i) odom.AddReading(script.Step(10, 20));
  EXPECT_NEAR(odom.odometry().pose.x_m, 0.0, 1e-9);
  EXPECT_NEAR(odom.odometry().pose.y_m, 0.0, 1e-9);
  EXPECT_NEAR(odom.odometry().pose.theta_rad, 0.0, 1e-9);
  EXPECT_GT(odom.odometry().pose_variance[2], half_lap_variance);
}

TEST(OdometryIntegratorTest, CounterWrapAroundForwardAndBackward) {
  for (int bits : {16, 32}) {
    const uint32_t top = static_cast<uint32_t>((uint64_t{1} << bits) - 8);
    OdometryOptions options = Morduc();
    options.counter_bits = bits;
    OdometryIntegrator forward(options);
    EncoderScript up(top, top, bits);
    forward.AddReading(up.Now());
    for (int i = 0; i < 4; ++i) forward.AddReading(up.Step(5, 5));  // crosses 2^bits
    EXPECT_NEAR(forward.odometry().pose.x_m, 20 * options.metres_per_tick(), 1e-12) << bits;

    OdometryIntegrator backward(options);
    EncoderScript down(3, 3, bits);
    backward.AddReading(down.Now());
    for (int i = 0; i < 4; ++i) backward.AddReading(down.Step(-5, -5));  // crosses 0
    EXPECT_NEAR(backward.odometry().pose.x_m, -20 * options.metres_per_tick(), 1e-12) << bits;
    EXPECT_EQ(backward.stats().glitches, 0u);
  }
}

TEST(OdometryIntegratorTest, IgnoresOutOfOrderReadings) {
  OdometryIntegrator odom(Morduc());
  EncoderScript script(0, 0, 16);
  odom.AddReading(script.Now());
  const EncoderReading first = script.Step(10, 10);
  odom.AddReading(first);
  EXPECT_FALSE(odom.AddReading(first));
  EXPECT_EQ(odom.stats().out_of_order, 1u);
  EXPECT_EQ(odom.stats().readings, 1u);
}

TEST(OdometryIntegratorTest, RefusesAnImplausibleJumpAndCountsIt) {
  OdometryIntegrator odom(Morduc());
  EncoderScript script(0, 0, 16);
  odom.AddReading(script.Now());
  // 3 m/s for 20 ms is 0.06 m = 48 ticks; 10000 ticks is a glitch.
  EXPECT_FALSE(odom.AddReading(script.Step(10000, 10000)));
  EXPECT_EQ(odom.stats().glitches, 1u);
  EXPECT_EQ(odom.odometry().pose.x_m, 0.0);
  // The glitched reading is the new reference: normal motion continues from it.
  EXPECT_TRUE(odom.AddReading(script.Step(10, 10)));
  EXPECT_NEAR(odom.odometry().pose.x_m, 10 * Morduc().metres_per_tick(), 1e-12);
}

TEST(OdometryIntegratorTest, VarianceGrowsMonotonicallyWithDistance) {
  OdometryIntegrator odom(Morduc());
  EncoderScript script(0, 0, 16);
  odom.AddReading(script.Now());
  std::array<double, 3> last{};
  for (int i = 0; i < 50; ++i) {
    odom.AddReading(script.Step(20, 22));
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(odom.odometry().pose_variance[k], last[k]);
      last[k] = odom.odometry().pose_variance[k];
    }
  }
  // Standing still adds nothing.
  for (int i = 0; i < 10; ++i) odom.AddReading(script.Step(0, 0));
  for (int k = 0; k < 3; ++k) EXPECT_EQ(odom.odometry().pose_variance[k], last[k]);
}

TEST(OdometryIntegratorTest, ResetRestartsFromAPose) {
  OdometryIntegrator odom(Morduc());
  EncoderScript script(0, 0, 16);
  odom.AddReading(script.Now());
  odom.AddReading(script.Step(30, 30));
  odom.Reset(Pose2D{1.0, 2.0, 0.5});
  EXPECT_FALSE(odom.AddReading(script.Step(30, 30)));  // new reference
  EXPECT_EQ(odom.odometry().pose.x_m, 1.0);
  EXPECT_EQ(odom.odometry().pose_variance[0], 0.0);
}

TEST(OdometryOptionsTest, ValidationNamesTheField) {
  OdometryOptions o = Morduc();
  std::string error;
  EXPECT_TRUE(o.IsValid(&error));
  o.counter_bits = 40;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("counter_bits"), std::string::npos);
}

}  // namespace
}  // namespace mostar::drive
