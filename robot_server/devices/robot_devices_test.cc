#include "robot_server/devices/robot_devices.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "common/time/fake_clock.h"

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
