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

TEST(MakeHudTest, ShowsTheBumperBeltAsTheConsoleDoes) {
  client::RobotSnapshot robot = Healthy();
  HudInputs inputs = FreshVideo();
  inputs.footprint_radius_m = 0.3;
  HudState hud = MakeHud(robot, inputs, kWallNow, kNow);
  EXPECT_TRUE(hud.bumper_segments.empty());  // no state yet
  EXPECT_FALSE(hud.bumper_alert);
  EXPECT_DOUBLE_EQ(hud.footprint_radius_m, 0.3);
  BumperState bumpers;
  bumpers.segment_count = 16;
  bumpers.pressed = 1u << 1;
  bumpers.latched = 1u << 8;
  robot.bumpers = bumpers;
  robot.last_bumpers_received = kNow - std::chrono::milliseconds(100);
  hud = MakeHud(robot, inputs, kWallNow, kNow);
  ASSERT_EQ(hud.bumper_segments.size(), 16u);
  EXPECT_EQ(hud.bumper_segments[0], "idle");
  EXPECT_EQ(hud.bumper_segments[1], "pressed");
  EXPECT_EQ(hud.bumper_segments[8], "latched");
  EXPECT_TRUE(hud.bumper_alert);
  EXPECT_FALSE(hud.bumper_stale);
  EXPECT_NE(hud.bumper_status.find("BUMPER"), std::string::npos) << hud.bumper_status;
  robot.last_bumpers_received = kNow - std::chrono::seconds(10);
  EXPECT_TRUE(MakeHud(robot, inputs, kWallNow, kNow).bumper_stale);
}

}  // namespace
}  // namespace mostar::web
