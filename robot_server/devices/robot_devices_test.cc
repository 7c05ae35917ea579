#include "robot_server/devices/robot_devices.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>

#include "common/record/recording_writer.h"
#include "common/record/test_records.h"
#include "common/time/fake_clock.h"
#include "robot_server/replay/replay_laser_scanner.h"
#include "robot_server/replay/replay_sonar.h"
#include "robot_server/server_options.h"
#include "robot_server/sim/sim_test_helpers.h"

namespace mostar::server {
namespace {

TEST(RobotDevicesTest, TestPatternSourceHasPatternMotorsLaserAndCamera) {
  ServerConfig config;
  config.set_source(ServerConfig::TEST_PATTERN);
  drive::DriveSettings settings;
  RobotDevices devices;
  std::string error;
  ASSERT_TRUE(MakeRobotDevices(config, "", &SystemClock::Instance(), &settings, &devices, &error))
      << error;
  EXPECT_EQ(devices.motors(), devices.pattern_robot.get());
  ASSERT_NE(devices.laser(), nullptr);
  EXPECT_NE(dynamic_cast<testpattern::TestPatternLaser*>(devices.laser()), nullptr);
  EXPECT_NE(devices.camera, nullptr);
  EXPECT_TRUE(devices.intrinsics.empty());
  EXPECT_EQ(settings.odometry.counter_bits, 16);
}

TEST(RobotDevicesTest, SimSourceWithoutASceneIsRefusedWithTheFix) {
  ServerConfig config;
  config.set_source(ServerConfig::SIM);
  drive::DriveSettings settings;
  RobotDevices devices;
  std::string error;
  EXPECT_FALSE(MakeRobotDevices(config, "", &SystemClock::Instance(), &settings, &devices, &error));
  EXPECT_NE(error.find("--sim FILE or scene_file"), std::string::npos) << error;
}

TEST(RobotDevicesTest, AMissingReplayFileIsRefusedNamingTheKey) {
  ServerConfig config;
  config.set_source(ServerConfig::TEST_PATTERN);
  config.mutable_laser()->mutable_replay()->set_file("no_such_recording.mostar");
  drive::DriveSettings settings;
  RobotDevices devices;
  std::string error;
  EXPECT_FALSE(MakeRobotDevices(config, "/nonexistent", &SystemClock::Instance(), &settings,
                                &devices, &error));
  EXPECT_EQ(error.rfind("laser.replay.file: ", 0), 0u) << error;
  EXPECT_NE(error.find("/nonexistent/no_such_recording.mostar"), std::string::npos) << error;
}

TEST(RobotDevicesTest, SensorReplayIsRefusedWithTheHardwareSource) {
  ServerFlags flags;
  flags.source = "hardware";
  flags.replay_sensors = "/data/run.mostar";
  ServerConfig config;
  ApplyFlags(flags, &config);
  drive::DriveSettings settings;
  RobotDevices devices;
  std::string error;
  // Refused before any device is opened (no serial port, no recording is touched).
  EXPECT_FALSE(MakeRobotDevices(config, "", &SystemClock::Instance(), &settings, &devices, &error));
  EXPECT_NE(error.find("refused with source HARDWARE"), std::string::npos) << error;
  EXPECT_NE(error.find("laser.replay.file and camera.backend REPLAY"), std::string::npos) << error;
  EXPECT_EQ(devices.laser(), nullptr);
  EXPECT_EQ(devices.motors(), nullptr);
  // Either replay alone is refused too.
  ServerConfig laser_only;
  laser_only.set_source(ServerConfig::HARDWARE);
  laser_only.mutable_laser()->mutable_replay()->set_file("run.mostar");
  EXPECT_FALSE(CheckReplayIsNotOnHardware(laser_only, &error));
  EXPECT_NE(error.find("(laser.replay.file, or --replay-sensors)"), std::string::npos) << error;
  ServerConfig camera_only;
  camera_only.set_source(ServerConfig::HARDWARE);
  camera_only.mutable_camera()->set_backend(camera::CameraConfig::REPLAY);
  EXPECT_FALSE(CheckReplayIsNotOnHardware(camera_only, &error));
  EXPECT_NE(error.find("(camera.backend REPLAY, or"), std::string::npos) << error;
  // The same replay behind the simulated or pattern robot is allowed; hardware alone too.
  for (const auto source : {ServerConfig::SIM, ServerConfig::TEST_PATTERN}) {
    config.set_source(source);
    EXPECT_TRUE(CheckReplayIsNotOnHardware(config, &error)) << error;
  }
  ServerConfig hardware;
  hardware.set_source(ServerConfig::HARDWARE);
  EXPECT_TRUE(CheckReplayIsNotOnHardware(hardware, &error)) << error;
}

TEST(RobotDevicesTest, SonarAndBumpersMustFitTheSourceAndNameTheKey) {
  const Clock* clock = &SystemClock::Instance();
  std::string error;
  ServerConfig config;
  config.set_source(ServerConfig::SIM);
  config.mutable_bumpers()->set_backend(BumperConfig::GPIOD);
  RobotDevices devices;
  EXPECT_FALSE(MakeSonarAndBumpers(config, clock, &devices, &error));
  EXPECT_NE(error.find("bumpers.backend GPIOD needs source HARDWARE"), std::string::npos) << error;
  config.set_source(ServerConfig::HARDWARE);
  config.mutable_bumpers()->set_backend(BumperConfig::SIM);
  EXPECT_FALSE(MakeSonarAndBumpers(config, clock, &devices, &error));
  EXPECT_NE(error.find("bumpers.backend SIM needs source SIM"), std::string::npos) << error;
  // Hardware that is not there: the chip and the I2C adapter are named.
  config.mutable_bumpers()->set_backend(BumperConfig::GPIOD);
  config.mutable_bumpers()->set_chip("/dev/no-such-gpiochip");
  config.mutable_bumpers()->add_line(3);
  EXPECT_FALSE(MakeSonarAndBumpers(config, clock, &devices, &error));
  EXPECT_EQ(error.rfind("bumpers: ", 0), 0u) << error;
  EXPECT_NE(error.find("/dev/no-such-gpiochip"), std::string::npos) << error;
  config.mutable_bumpers()->set_backend(BumperConfig::NONE);
  auto* sensor = config.mutable_sonar()->add_sensors();
  sensor->set_address(0x70);
  config.mutable_sonar()->set_bus("/dev/no-such-i2c");
  EXPECT_FALSE(MakeSonarAndBumpers(config, clock, &devices, &error));
  EXPECT_EQ(error.rfind("sonar.bus: ", 0), 0u) << error;
  // The test pattern has neither, whatever the sections say (a SIM configuration run with
  // --source test_pattern).
  config.set_source(ServerConfig::TEST_PATTERN);
  config.mutable_bumpers()->set_backend(BumperConfig::SIM);
  EXPECT_TRUE(MakeSonarAndBumpers(config, clock, &devices, &error)) << error;
  EXPECT_EQ(devices.sonar(), nullptr);
  EXPECT_EQ(devices.bumpers, nullptr);
}

TEST(RobotDevicesTest, TheSimulatorHasTheConfiguredSonarAndBumpers) {
  const Clock* clock = &SystemClock::Instance();
  std::string error;
  RobotDevices devices;
  devices.world = sim::SimWorld::Create(sim::testing::OpenFloor(""), sim::proto::SimConfig(),
                                        clock->Now(), &error);
  ASSERT_NE(devices.world, nullptr) << error;
  ServerConfig config;
  config.set_source(ServerConfig::SIM);
  config.mutable_bumpers()->set_backend(BumperConfig::SIM);
  config.mutable_bumpers()->set_segments(12);
  auto* sensor = config.mutable_sonar()->add_sensors();
  sensor->set_address(0x70);
  ASSERT_TRUE(MakeSonarAndBumpers(config, clock, &devices, &error)) << error;
  ASSERT_NE(devices.bumpers, nullptr);
  EXPECT_EQ(devices.bumpers->segments(), 12);
  ASSERT_NE(devices.sonar(), nullptr);
  EXPECT_EQ(devices.sonar()->Health().name, "sonar");
  // Without sensors and with backend NONE: neither.
  RobotDevices none;
  none.world = std::move(devices.world);
  EXPECT_TRUE(MakeSonarAndBumpers(ServerConfig(), clock, &none, &error)) << error;
  EXPECT_EQ(none.sonar(), nullptr);
  EXPECT_EQ(none.bumpers, nullptr);
}

// --replay-sensors on a simulated robot with belts: the configured belts come from the
// recording too (one timeline with the camera and laser), and read its sonar and bumper records.
TEST(RobotDevicesTest, ReplaySensorsReplaysTheConfiguredBeltsFromTheSameRecording) {
  const std::string path = record::testing::TempPath("robot_devices_belts.mostar");
  {
    FakeClock clock(record::testing::T0());
    std::string error;
    auto writer =
        record::RecordingWriter::Open(path, {}, record::testing::MakeInfo(), clock, &error);
    ASSERT_NE(writer, nullptr) << error;
    const Time t0 = record::testing::T0();
    EXPECT_TRUE(writer->Write(record::testing::At(t0, record::testing::MakeScan(t0, 1))));
    EXPECT_TRUE(writer->Write(record::testing::At(t0, record::testing::MakeSonar(t0))));
    EXPECT_TRUE(writer->Write(record::testing::At(t0, record::testing::MakeBumpers(t0))));
    ASSERT_TRUE(writer->Close(&error)) << error;
  }
  ServerFlags flags;
  flags.scene = sim::testing::SourceDir() + "/deploy/scenes/glass_door.pbtxt";
  flags.replay_sensors = path;
  flags.replay_loop = true;
  ServerConfig config;
  config.mutable_bumpers()->set_backend(BumperConfig::SIM);
  config.mutable_bumpers()->set_segments(16);
  config.mutable_sonar()->add_sensors()->set_address(0x70);
  ApplyFlags(flags, &config);
  drive::DriveSettings settings;
  RobotDevices devices;
  std::string error;
  ASSERT_TRUE(MakeRobotDevices(config, "", &SystemClock::Instance(), &settings, &devices, &error))
      << error;
  EXPECT_NE(dynamic_cast<replay::ReplayLaserScanner*>(devices.laser()), nullptr);
  auto* sonar = dynamic_cast<replay::ReplaySonarRing*>(devices.sonar());
  ASSERT_NE(sonar, nullptr);
  auto* bumpers = dynamic_cast<replay::ReplayBumperBelt*>(devices.bumpers.get());
  ASSERT_NE(bumpers, nullptr);
  EXPECT_EQ(bumpers->segments(), 16);
  // The recorded bumper state (segments 0 and 15 pressed) is read once it is due.
  uint32_t pressed = 0;
  std::string why;
  for (int i = 0; i < 200 && !bumpers->Read(&pressed, &why); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(pressed, 0x8001u) << why;
  std::atomic<int> cycles{0};
  ASSERT_TRUE(sonar->Start([&](const SonarRanges&) { ++cycles; }, &error)) << error;
  for (int i = 0; i < 200 && cycles == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  sonar->Stop();
  EXPECT_GT(cycles.load(), 0);
  std::remove(path.c_str());
}

TEST(TestPatternLaserTest, ScansAtItsRateUntilStoppedAndStartsOnce) {
  const FakeClock clock;
  testpattern::KinematicRobot robot({}, &clock);
  testpattern::TestPatternLaser laser(&robot, 100.0, &clock);
  std::atomic<uint64_t> last_sequence{0};
  std::atomic<int> scans{0};
  std::string error;
  ASSERT_TRUE(laser.Start(
      [&](const LaserScan& scan) {
        EXPECT_EQ(scan.sequence, last_sequence + 1);
        EXPECT_EQ(scan.stamp, clock.Now());
        EXPECT_EQ(scan.ranges_m.size(), 181u);
        last_sequence = scan.sequence;
        ++scans;
      },
      &error));
  EXPECT_FALSE(laser.Start([](const LaserScan&) {}, &error));
  EXPECT_EQ(error, "test-pattern laser already started");
  while (scans < 5) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  laser.Stop();
  const int after_stop = scans;
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(scans, after_stop) << "no scan after Stop() returned";
  const DeviceHealth health = laser.Health();
  EXPECT_EQ(health.name, "laser");
  EXPECT_EQ(health.state, DeviceState::kOk);
  ASSERT_EQ(health.counters.size(), 1u);
  EXPECT_EQ(health.counters[0].second, static_cast<uint64_t>(after_stop));
}

}  // namespace
}  // namespace mostar::server
