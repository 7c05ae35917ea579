#include "robot_server/sim/diff_drive.h"

#include <gtest/gtest.h>

#include <cmath>

#include "robot_server/sim/sim_test_helpers.h"
#include "robot_server/sim/world.h"

namespace mostar::sim {
namespace {

DiffDrive FreeDrive(const DriveParams& params = DriveParams()) {
  return DiffDrive(params, Pose2D{}, nullptr);
}

// Distance rolled by a wheel for an unwrapped count.
double CountsToMetres(const DriveParams& p, int64_t counts) {
  return static_cast<double>(counts) / p.CountsPerTurn() * 2 * M_PI * p.wheel_radius_m;
}

TEST(DiffDriveTest, AccelerationIsLimited) {
  DiffDrive drive = FreeDrive();
  drive.SetCommand(0.5, 0.0);
  drive.Advance(FromMilliseconds(100));
  EXPECT_NEAR(drive.linear_mps(), 0.08, 1e-9);  // 0.8 m/s^2 * 0.1 s
  drive.Advance(FromSeconds(2));
  EXPECT_NEAR(drive.linear_mps(), 0.5, 1e-9);
}

TEST(DiffDriveTest, CommandIsClampedToTheLimits) {
  DiffDrive drive = FreeDrive();
  drive.SetCommand(5.0, -9.0);
  drive.Advance(FromSeconds(3));
  EXPECT_NEAR(drive.linear_mps(), 0.6, 1e-9);
  EXPECT_NEAR(drive.angular_radps(), -1.2, 1e-9);
}

TEST(DiffDriveTest, NonFiniteCommandStops) {
  DiffDrive drive = FreeDrive();
  drive.SetCommand(NAN, INFINITY);
  drive.Advance(FromSeconds(1));
  EXPECT_EQ(drive.linear_mps(), 0.0);
  EXPECT_EQ(drive.world_from_base().x_m, 0.0);
}

TEST(DiffDriveTest, PartialStepsAreCarriedOver) {
  DiffDrive a = FreeDrive(), b = FreeDrive();
  a.SetCommand(0.3, 0.2);
  b.SetCommand(0.3, 0.2);
  for (int i = 0; i < 400; ++i) a.Advance(FromMilliseconds(2.5));
  b.Advance(FromSeconds(1));
  EXPECT_EQ(a.elapsed(), b.elapsed());
  EXPECT_DOUBLE_EQ(a.world_from_base().x_m, b.world_from_base().x_m);
}

TEST(DiffDriveTest, StraightTicksMatchTheDistanceDriven) {
  const DriveParams p;
  DiffDrive drive = FreeDrive(p);
  drive.SetCommand(0.4, 0.0);
  drive.Advance(FromSeconds(5));
  const EncoderTicks t = drive.encoders();
  const double distance = drive.world_from_base().x_m;
  EXPECT_GT(distance, 1.5);
  EXPECT_NEAR(CountsToMetres(p, t.left_total), distance, CountsToMetres(p, 1));
  EXPECT_NEAR(CountsToMetres(p, t.right_total), distance, CountsToMetres(p, 1));
  // 500 pulses per turn of a 0.08 m wheel: about 995 counts per metre.
  EXPECT_NEAR(static_cast<double>(t.left_total) / distance, 500 / (2 * M_PI * 0.08), 1.0);
}

TEST(DiffDriveTest, TurningInPlaceCountsOppositeWays) {
  const DriveParams p;
  DiffDrive drive = FreeDrive(p);
  drive.SetCommand(0.0, 1.0);
  drive.Advance(FromSeconds(2));
  const EncoderTicks t = drive.encoders();
  EXPECT_LT(t.left_total, 0);
  EXPECT_GT(t.right_total, 0);
  const double wheel_arc = p.track_width_m / 2 * drive.world_from_base().theta_rad;
  EXPECT_NEAR(CountsToMetres(p, t.right_total), wheel_arc, 2 * CountsToMetres(p, 1));
}

TEST(DiffDriveTest, CounterWrapsAtItsWidth) {
  DriveParams p;
  p.encoder_counter_bits = 8;
  DiffDrive drive = FreeDrive(p);
  drive.SetCommand(-0.5, 0.0);  // backwards: negative totals wrap to the top of the range
  drive.Advance(FromSeconds(3));
  const EncoderTicks t = drive.encoders();
  ASSERT_LT(t.left_total, -256);
  EXPECT_LT(t.left, 256u);
  EXPECT_EQ(t.left, static_cast<uint64_t>(((t.left_total % 256) + 256) % 256));
}

TEST(DiffDriveTest, QuadratureCountsFourEdgesPerPulse) {
  DriveParams x1, x4;
  x4.encoder_quadrature_x4 = true;
  DiffDrive a = FreeDrive(x1), b = FreeDrive(x4);
  a.SetCommand(0.3, 0.0);
  b.SetCommand(0.3, 0.0);
  a.Advance(FromSeconds(2));
  b.Advance(FromSeconds(2));
  EXPECT_NEAR(static_cast<double>(b.encoders().left_total),
              4.0 * static_cast<double>(a.encoders().left_total), 4.0);
}

// Dead reckoning from the encoder counts alone follows the true path.
TEST(DiffDriveTest, OdometryFromTicksFollowsTheTruePath) {
  const DriveParams p;
  DiffDrive drive = FreeDrive(p);
  const double m_per_count = CountsToMetres(p, 1);
  double x = p.axle_x_m, y = 0, theta = 0;  // axle pose, integrated from counts
  EncoderTicks last = drive.encoders();
  const struct {
    double v, w, seconds;
  } legs[] = {{0.5, 0.0, 3}, {0.3, 0.6, 4}, {0.0, -1.0, 2}, {0.4, -0.3, 5}, {-0.2, 0.0, 2}};
  for (const auto& leg : legs) {
    drive.SetCommand(leg.v, leg.w);
    for (int i = 0; i < leg.seconds * 50; ++i) {
      drive.Advance(FromMilliseconds(20));
      const EncoderTicks now = drive.encoders();
      const double dl = static_cast<double>(now.left_total - last.left_total) * m_per_count;
      const double dr = static_cast<double>(now.right_total - last.right_total) * m_per_count;
      last = now;
      const double ds = (dl + dr) / 2, dtheta = (dr - dl) / p.track_width_m;
      x += ds * std::cos(theta + dtheta / 2);
      y += ds * std::sin(theta + dtheta / 2);
      theta += dtheta;
    }
  }
  const Pose2D truth = drive.world_from_base();
  const double tx = truth.x_m + p.axle_x_m * std::cos(truth.theta_rad);
  const double ty = truth.y_m + p.axle_x_m * std::sin(truth.theta_rad);
  EXPECT_NEAR(x, tx, 0.02);
  EXPECT_NEAR(y, ty, 0.02);
  EXPECT_NEAR(std::remainder(theta - truth.theta_rad, 2 * M_PI), 0.0, 0.01);
}

TEST(DiffDriveTest, CollisionStopsTheRobotAndIsCounted) {
  const World world(testing::OpenFloor("wall { x0_m: 2 y0_m: -5 x1_m: 2 y1_m: 5 }"));
  const DriveParams p;
  DiffDrive drive(p, Pose2D{},
                  [&](double x, double y, double r) { return world.CircleCollides(x, y, r); });
  drive.SetCommand(0.5, 0.0);
  drive.Advance(FromSeconds(10));
  EXPECT_TRUE(drive.in_collision());
  EXPECT_EQ(drive.collision_count(), 1u);
  EXPECT_EQ(drive.linear_mps(), 0.0);
  const double front = drive.world_from_base().x_m + p.footprint_center_x_m + p.footprint_radius_m;
  EXPECT_LT(front, 2.0);
  EXPECT_GT(front, 1.98);
  const int64_t ticks = drive.encoders().left_total;
  drive.Advance(FromSeconds(1));
  EXPECT_EQ(drive.encoders().left_total, ticks);  // wheels do not turn while blocked
  // Backing off frees the robot; driving in again is a second contact.
  drive.SetCommand(-0.3, 0.0);
  drive.Advance(FromSeconds(1));
  EXPECT_FALSE(drive.in_collision());
  drive.SetCommand(0.3, 0.0);
  drive.Advance(FromSeconds(5));
  EXPECT_EQ(drive.collision_count(), 2u);
}

}  // namespace
}  // namespace mostar::sim
