#include "robot_server/server_options.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <climits>

namespace mostar::server {
namespace {

std::string Cwd() {
  char cwd[PATH_MAX];
  return getcwd(cwd, sizeof(cwd)) ? cwd : "";
}

TEST(ServerOptionsTest, SimFlagSelectsTheSimulatorWithAnAbsoluteScene) {
  ServerConfig config;
  config.set_source(ServerConfig::HARDWARE);
  config.set_scene_file("scenes/corridor.pbtxt");
  ServerFlags flags;
  flags.scene = "my_scene.pbtxt";
  ApplyFlags(flags, &config);
  EXPECT_EQ(config.source(), ServerConfig::SIM);
  EXPECT_EQ(config.scene_file(), Cwd() + "/my_scene.pbtxt");
}

TEST(ServerOptionsTest, SourceFlagOverridesTheFileAndNoFlagChangesNothing) {
  ServerConfig config;
  config.set_source(ServerConfig::SIM);
  config.set_scene_file("scenes/corridor.pbtxt");
  const std::string before = config.SerializeAsString();
  ApplyFlags(ServerFlags{}, &config);
  EXPECT_EQ(config.SerializeAsString(), before);
  ServerFlags flags;
  flags.source = "test_pattern";
  ApplyFlags(flags, &config);
  EXPECT_EQ(config.source(), ServerConfig::TEST_PATTERN);
  EXPECT_EQ(config.scene_file(), "scenes/corridor.pbtxt") << "file paths stay file-relative";
}

TEST(ServerOptionsTest, InsecureFlagTurnsTheConfigurationsInsecureOnNeverOff) {
  ServerConfig config;
  EXPECT_FALSE(config.dds().insecure()) << "secure by default";
  ApplyFlags(ServerFlags{}, &config);
  EXPECT_FALSE(config.dds().insecure());
  ServerFlags flags;
  flags.insecure = true;
  ApplyFlags(flags, &config);
  EXPECT_TRUE(config.dds().insecure());
  ApplyFlags(ServerFlags{}, &config);
  EXPECT_TRUE(config.dds().insecure()) << "a file's insecure: true stays without the flag";
}

TEST(ServerOptionsTest, ReplaySensorsReplaysCameraAndLaserOfOneFileAtOneRate) {
  ServerConfig config;
  ServerFlags flags;
  flags.replay_sensors = "/data/run.mostar";
  flags.replay_rate = 0.5;
  flags.replay_loop = true;
  ApplyFlags(flags, &config);
  EXPECT_EQ(config.camera().backend(), camera::CameraConfig::REPLAY);
  EXPECT_EQ(config.camera().replay().file(), "/data/run.mostar");
  EXPECT_EQ(config.laser().replay().file(), "/data/run.mostar");
  EXPECT_DOUBLE_EQ(config.camera().replay().rate(), 0.5);
  EXPECT_DOUBLE_EQ(config.laser().replay().rate(), 0.5);
  EXPECT_TRUE(config.camera().replay().loop());
  EXPECT_TRUE(config.laser().replay().loop());
  EXPECT_FALSE(config.camera().replay().deliver_at_capture_time());
  // The configuration's pacing of the replayed camera stays.
  ServerConfig at_capture;
  at_capture.mutable_camera()->mutable_replay()->set_deliver_at_capture_time(true);
  ApplyFlags(flags, &at_capture);
  EXPECT_EQ(at_capture.camera().replay().file(), "/data/run.mostar");
  EXPECT_TRUE(at_capture.camera().replay().deliver_at_capture_time());
}

TEST(ServerOptionsTest, TheHardwareRobotKeepsItsEstopLatchTheSimulatedOneWhenAsked) {
  ServerConfig config;
  std::string dir, error;
  config.set_source(ServerConfig::HARDWARE);
  ASSERT_TRUE(EstopStateDirectory(config, "/etc/mostar", &dir, &error)) << error;
  EXPECT_EQ(dir, "/var/lib/mostar");
  for (const auto source : {ServerConfig::SIM, ServerConfig::TEST_PATTERN}) {
    config.set_source(source);
    ASSERT_TRUE(EstopStateDirectory(config, "/etc/mostar", &dir, &error)) << error;
    EXPECT_EQ(dir, "") << "not persisted by default";
  }
  config.set_state_dir("state");  // relative to the configuration file
  ASSERT_TRUE(EstopStateDirectory(config, "/etc/mostar", &dir, &error)) << error;
  EXPECT_EQ(dir, "/etc/mostar/state");
  ServerFlags flags;
  flags.state_dir = "run/state";  // relative to the working directory
  ApplyFlags(flags, &config);
  ASSERT_TRUE(EstopStateDirectory(config, "/etc/mostar", &dir, &error)) << error;
  EXPECT_EQ(dir, Cwd() + "/run/state");
  // An empty directory: not persisted for a simulated robot, refused for the hardware one.
  config.set_state_dir("");
  ASSERT_TRUE(EstopStateDirectory(config, "/etc/mostar", &dir, &error)) << error;
  EXPECT_EQ(dir, "");
  config.set_source(ServerConfig::HARDWARE);
  EXPECT_FALSE(EstopStateDirectory(config, "/etc/mostar", &dir, &error));
  EXPECT_NE(error.find("state_dir"), std::string::npos) << error;
}

TEST(ServerOptionsTest, ControllerOptionsComeFromTheConfigurationAndAreValid) {
  ServerConfig config;
  config.set_robot_id("morduc");
  config.set_health_period_s(0.25);
  config.set_lease_period_s(2);
  config.set_holder_timeout_s(3);
  config.mutable_dds()->set_write_stall_exit_s(12);
  drive::DriveSettings settings;
  settings.roles.Set("alice", {drive::Role::kPilot, 1});
  settings.safety.max_linear_mps = 0.4;
  const RobotControllerOptions options =
      ControllerOptionsFrom(config, settings, {CameraIntrinsicsInfo{}});
  EXPECT_EQ(options.robot_id, "morduc");
  EXPECT_EQ(options.health_period, std::chrono::milliseconds(250));
  EXPECT_EQ(options.lease_period, std::chrono::seconds(2));
  EXPECT_EQ(options.holder_timeout, std::chrono::seconds(3));
  EXPECT_EQ(options.write_stall_limit, std::chrono::seconds(12));
  EXPECT_TRUE(options.roles.Known("alice"));
  EXPECT_DOUBLE_EQ(options.safety.max_linear_mps, 0.4);
  EXPECT_EQ(options.intrinsics.size(), 1u);
  std::string error;
  EXPECT_TRUE(options.IsValid(&error)) << error;
}

TEST(ServerOptionsTest, DefaultConfigurationGivesValidControllerOptions) {
  std::string error;
  EXPECT_TRUE(ControllerOptionsFrom(ServerConfig{}, drive::DriveSettings{}, {}).IsValid(&error))
      << error;
}

}  // namespace
}  // namespace mostar::server
