#include "robot_server/sim/bumper_contacts.h"

#include <gtest/gtest.h>

#include <cmath>

#include "robot_server/sim/sim_test_helpers.h"

namespace mostar::sim {
namespace {

using testing::OpenFloor;

// The default footprint: radius 0.34 m around (-0.22, 0): its front at x = 0.12 m.
TEST(BumperContactsTest, AWallTouchingTheFrontPressesTheFrontSegmentOnly) {
  const DriveParams drive;
  const World touching(OpenFloor("wall { x0_m: 0.125 y0_m: -3 x1_m: 0.125 y1_m: 3 }"));
  EXPECT_EQ(BumperContacts(touching, Pose2D{}, drive, 16), 1u);
  // 3 cm away: not pressed.
  const World near(OpenFloor("wall { x0_m: 0.15 y0_m: -3 x1_m: 0.15 y1_m: 3 }"));
  EXPECT_EQ(BumperContacts(near, Pose2D{}, drive, 16), 0u);
}

TEST(BumperContactsTest, ThePressedSegmentTurnsWithTheRobotAndFollowsTheSide) {
  const DriveParams drive;
  // A wall behind the footprint (its rear at x = -0.56): segment 8.
  const World behind(OpenFloor("wall { x0_m: -0.565 y0_m: -3 x1_m: -0.565 y1_m: 3 }"));
  EXPECT_EQ(BumperContacts(behind, Pose2D{}, drive, 16), 1u << 8);
  // A post touching the left side (footprint centre at y = 0, radius 0.34): segment 4. Turned
  // by 90 degrees (footprint centre now at y = -0.22), the same post meets the front segment 0
  // when it is placed ahead of the turned robot instead.
  const World left(OpenFloor("cylinder { x_m: -0.22 y_m: 0.395 radius_m: 0.05 height_m: 1 }"));
  EXPECT_EQ(BumperContacts(left, Pose2D{}, drive, 16), 1u << 4);
  const World ahead_of_turned(
      OpenFloor("cylinder { x_m: 0 y_m: 0.175 radius_m: 0.05 height_m: 1 }"));
  EXPECT_EQ(BumperContacts(ahead_of_turned, Pose2D{0, 0, M_PI / 2}, drive, 16), 1u);
}

TEST(BumperContactsTest, OpenFloorPressesNothing) {
  EXPECT_EQ(BumperContacts(World(OpenFloor("")), Pose2D{}, DriveParams{}, 16), 0u);
}

}  // namespace
}  // namespace mostar::sim
