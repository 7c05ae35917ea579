#include "robot_server/sim/sonar_raycast.h"

#include <gtest/gtest.h>

#include <cmath>

#include "robot_server/sim/laser_raycast.h"
#include "robot_server/sim/sim_test_helpers.h"

namespace mostar::sim {
namespace {

using testing::OpenFloor;

SonarMount Ahead() {
  SonarMount m;
  m.frame_id = "sonar_0";
  return m;  // at the base origin, looking along +x
}

// What the laser measures straight ahead, for comparison (noise-free; scan plane 0.35 m,
// horizontal; +Inf = no echo).
float LaserAhead(const World& world) {
  LaserParams p;
  p.noise_sigma_m = 0;
  LaserRaycaster laser(world, p, 1);
  return laser.Scan(Pose2D{}, Time(), nullptr).ranges_m[p.BeamCount() / 2];
}

TEST(SonarRaycastTest, AWallAheadEchoesAtItsDistance) {
  const World world(OpenFloor("wall { x0_m: 2 y0_m: -5 x1_m: 2 y1_m: 5 }"));
  EXPECT_NEAR(SonarFirstEcho(world, Pose2D{}, Ahead(), SonarCone{}), 2.0, 1e-3);
}

TEST(SonarRaycastTest, GlassThatTheLaserPassesEchoes) {
  const World world(
      OpenFloor("wall { x0_m: 4 y0_m: -5 x1_m: 4 y1_m: 5 }\n"
                "box { x_m: 1.5 y_m: 0 size_x_m: 0.02 size_y_m: 2 height_m: 2 "
                "material { laser: TRANSPARENT } }"));
  EXPECT_NEAR(LaserAhead(world), 4.0, 1e-3);
  EXPECT_NEAR(SonarFirstEcho(world, Pose2D{}, Ahead(), SonarCone{}), 1.49, 1e-3);
}

TEST(SonarRaycastTest, ABlackCabinetWithoutLaserEchoEchoes) {
  const World world(
      OpenFloor("box { x_m: 1.25 y_m: 0 size_x_m: 0.5 size_y_m: 1 height_m: 0.8 "
                "material { laser: NO_ECHO colour { r: 5 g: 5 b: 5 } } }"));
  EXPECT_TRUE(std::isinf(LaserAhead(world)));
  EXPECT_NEAR(SonarFirstEcho(world, Pose2D{}, Ahead(), SonarCone{}), 1.0, 1e-3);
}

TEST(SonarRaycastTest, ALowObstacleUnderTheLaserPlaneButInTheConeEchoes) {
  // 0.25 m high, the laser at 0.35 m passes over it; the sonar at 0.30 m with a 20 degree cone.
  const World world(OpenFloor("box { x_m: 1.2 y_m: 0 size_x_m: 0.4 size_y_m: 1 height_m: 0.25 }"));
  EXPECT_TRUE(std::isinf(LaserAhead(world)));
  const float echo = SonarFirstEcho(world, Pose2D{}, Ahead(), SonarCone{});
  EXPECT_GT(echo, 1.0);
  EXPECT_LT(echo, 1.1);
}

TEST(SonarRaycastTest, OnlyTheConeSeesNothingBesideItAndTheFloorGivesNoEcho) {
  SonarCone cone;
  // A post 1 m ahead and 0.4 m to the side: 22 degrees off the axis, inside the 55 degree cone.
  const World inside(OpenFloor("cylinder { x_m: 1 y_m: 0.4 radius_m: 0.05 height_m: 1 }"));
  EXPECT_LT(SonarFirstEcho(inside, Pose2D{}, Ahead(), cone), 1.1);
  // 1 m to the side: 45 degrees off, outside.
  const World outside(OpenFloor("cylinder { x_m: 1 y_m: 1 radius_m: 0.05 height_m: 1 }"));
  EXPECT_TRUE(std::isinf(SonarFirstEcho(outside, Pose2D{}, Ahead(), cone)));
  // The floor is hit by the lower rays within a metre, yet there is no echo.
  cone.vertical_fov_rad = 0.8;
  EXPECT_TRUE(std::isinf(SonarFirstEcho(World(OpenFloor("")), Pose2D{}, Ahead(), cone)));
}

TEST(SonarRaycastTest, MountAndRobotPoseAreComposedAndTheRangeIsClamped) {
  const World world(OpenFloor("wall { x0_m: -5 y0_m: 2 x1_m: 5 y1_m: 2 }"));
  SonarMount left;
  left.y_m = 0.3;
  left.yaw_rad = M_PI / 2;  // looks to the robot's left
  EXPECT_NEAR(SonarFirstEcho(world, Pose2D{}, left, SonarCone{}), 1.7, 1e-3);
  // The robot turned by -90 degrees: the left sensor now looks along +x, parallel to the wall;
  // only the cone's edge meets it, 2 m / sin(27.5 deg) away.
  EXPECT_NEAR(SonarFirstEcho(world, Pose2D{0, 0, -M_PI / 2}, left, SonarCone{}),
              2.0 / std::sin(0.48), 0.05);
  // 1.69 m in front of the wall, the sensor 0.3 m further: 1 cm, below the minimum range.
  EXPECT_FLOAT_EQ(SonarFirstEcho(world, Pose2D{0, 1.69, 0}, left, SonarCone{}), 0.03f);
  SonarCone short_window;
  short_window.max_range_m = 1.5;
  EXPECT_TRUE(std::isinf(SonarFirstEcho(world, Pose2D{}, left, short_window)));
}

}  // namespace
}  // namespace mostar::sim
