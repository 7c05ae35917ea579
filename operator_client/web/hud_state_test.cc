#include "operator_client/web/hud_state.h"

#include <gtest/gtest.h>

namespace mostar::web {
namespace {

const SteadyTime kNow = SteadyTime(std::chrono::seconds(1000));
const Time kWallNow = FromUnixNanos(1700000000000000000);

client::RobotSnapshot Healthy() {
  client::RobotSnapshot robot;
  RobotHealth health;
  health.robot_id = "morduc-sim";
  health.watchdog_state = WatchdogState::kDriving;
  health.lease_holder = "operator";
  DeviceHealth laser;
  laser.name = "laser";
  laser.state = DeviceState::kWarn;
  laser.message = "slow";
  health.devices = {laser, DeviceHealth{}};
  robot.health = health;
  robot.last_health_received = kNow - std::chrono::milliseconds(300);
  robot.last_scan_received = kNow - std::chrono::milliseconds(40);
  robot.scan_rate_hz = 37.5;
  return robot;
}

HudInputs FreshVideo() {
  HudInputs inputs;
  inputs.newest_pair_stamp = kWallNow - std::chrono::milliseconds(90);
  inputs.newest_pair_received = kNow - std::chrono::milliseconds(20);
  inputs.video_fps = 29.5;
  return inputs;
}

TEST(MakeHudTest, AHealthyLinkShowsAgesPilotWatchdogAndWarnings) {
  const HudState hud = MakeHud(Healthy(), FreshVideo(), kWallNow, kNow);
  EXPECT_EQ(hud.link, "ok");
  EXPECT_NEAR(hud.frame_age_ms, 90, 1e-6);
  EXPECT_NEAR(hud.scan_age_ms, 40, 1e-6);
  EXPECT_NEAR(hud.health_age_ms, 300, 1e-6);
  EXPECT_EQ(hud.pilot, "operator");
  EXPECT_EQ(hud.watchdog, WatchdogStateName(WatchdogState::kDriving));
  EXPECT_EQ(hud.robot_id, "morduc-sim");
  ASSERT_EQ(hud.warnings.size(), 1u);
  EXPECT_EQ(hud.warnings[0],
            std::string("laser ") + DeviceStateName(DeviceState::kWarn) + ": slow");
  EXPECT_FALSE(hud.estop_engaged);
}

TEST(MakeHudTest, TheLeaseWinsOverTheHealthsHolder) {
  client::RobotSnapshot robot = Healthy();
  ControlLease lease;
  lease.holder_id = "operator-2";
  robot.lease = lease;
  EXPECT_EQ(MakeHud(robot, FreshVideo(), kWallNow, kNow).pilot, "operator-2");
}

TEST(MakeHudTest, StaleStreamsNameTheLinkState) {
  client::RobotSnapshot robot = Healthy();
  HudInputs inputs = FreshVideo();
  inputs.newest_pair_received = kNow - kStaleAfter;
  EXPECT_EQ(MakeHud(robot, inputs, kWallNow, kNow).link, "no video");
  inputs = FreshVideo();
  robot.last_scan_received = kNow - std::chrono::seconds(5);
  EXPECT_EQ(MakeHud(robot, inputs, kWallNow, kNow).link, "no scans");
  robot.last_health_received = kNow - std::chrono::seconds(4);
  EXPECT_EQ(MakeHud(robot, inputs, kWallNow, kNow).link, "no contact");
}

TEST(MakeHudTest, NothingReceivedYet) {
  const HudState hud = MakeHud(client::RobotSnapshot{}, HudInputs{}, kWallNow, kNow);
  EXPECT_EQ(hud.link, "no contact");
  EXPECT_EQ(hud.frame_age_ms, -1);
  EXPECT_EQ(hud.scan_age_ms, -1);
  EXPECT_EQ(hud.watchdog, "");
  EXPECT_EQ(hud.pilot, "");
}

TEST(MakeHudTest, EstopIsShown) {
  client::RobotSnapshot robot = Healthy();
  robot.health->estop_engaged = true;
  EXPECT_TRUE(MakeHud(robot, FreshVideo(), kWallNow, kNow).estop_engaged);
}

}  // namespace
}  // namespace mostar::web
