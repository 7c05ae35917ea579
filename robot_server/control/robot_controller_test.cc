#include "robot_server/control/robot_controller.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <mutex>

#include "common/testing/subprocess.h"
#include "common/time/fake_clock.h"
#include "robot_server/bumper/fake_bumper_belt.h"
#include "robot_server/drive/fake_drive_motors.h"
#include "robot_server/node/fake_robot_link.h"
#include "robot_server/sonar/fake_sonar_ring.h"

namespace mostar::server {
namespace {

using std::chrono::milliseconds;

constexpr Duration kCycle = milliseconds(20);

// A laser whose scans the test emits by hand, as its thread would.
class FakeLaser final : public laser::LaserScanner {
 public:
  bool Start(ScanCallback on_scan, std::string*) override {
    on_scan_ = std::move(on_scan);
    ++starts;
    return true;
  }
  void Stop() override { ++stops; }
  DeviceHealth Health() const override {
    DeviceHealth health;
    health.name = "laser";
    return health;
  }
  void Emit(const LaserScan& scan) { on_scan_(scan); }

  int starts = 0;
  int stops = 0;

 private:
  ScanCallback on_scan_;
};

// Motors whose commands fail while `failing` is set.
class FlakyMotors final : public drive::DriveMotors {
 public:
  bool SetWheelVelocities(const drive::WheelVelocities&, std::string* error) override {
    *error = "board silent";
    return !failing;
  }
  bool SetVelocity(double, double, std::string* error) override {
    return SetWheelVelocities({}, error);
  }
  bool Stop(std::string*, bool) override { return true; }
  drive::MotorStatus Status() const override { return {}; }  // no link
  bool ReadEncoders(drive::EncoderReading*, std::string* error) override {
    *error = "board silent";
    return false;
  }
  int counter_bits() const override { return 16; }
  bool failing = true;
};

// Free space everywhere: 181 beams at 10 m.
LaserScan OpenScan(Time stamp, uint64_t sequence) {
  LaserScan scan;
  scan.stamp = stamp;
  scan.sequence = sequence;
  scan.angle_min_rad = static_cast<float>(-M_PI / 2);
  scan.angle_increment_rad = static_cast<float>(M_PI / 180);
  scan.range_min_m = 0.05f;
  scan.range_max_m = 30.f;
  scan.ranges_m.assign(181, 10.f);
  return scan;
}

const DeviceHealth* Device(const RobotHealth& health, const std::string& name) {
  for (const DeviceHealth& d : health.devices) {
    if (d.name == name) return &d;
  }
  return nullptr;
}

uint64_t Counter(const DeviceHealth& device, const std::string& name) {
  for (const auto& [key, value] : device.counters) {
    if (key == name) return value;
  }
  return std::numeric_limits<uint64_t>::max();
}

class RobotControllerTest : public ::testing::Test {
 protected:
  RobotControllerTest() : motors_(0.5, drive::OdometryOptions{}.metres_per_tick()) {
    options_.roles.Set("alice", {drive::Role::kPilot, 10});
    options_.roles.Set("bob", {drive::Role::kPilot, 20});
    options_.roles.Set("olga", {drive::Role::kObserver, 0});
    options_.holder_timeout = milliseconds(500);
    options_.health_period = milliseconds(500);
    options_.lease_period = milliseconds(1000);
    options_.write_stall_limit = std::chrono::seconds(30);
    CameraIntrinsicsInfo left;
    left.frame_id = "camera_left";
    left.fx = 500;
    CameraIntrinsicsInfo right = left;
    right.frame_id = "camera_right";
    options_.intrinsics = {left, right};
  }

  RobotController& Make(drive::DriveMotors* motors = nullptr) {
    RobotControllerDevices devices;
    devices.motors = motors ? motors : &motors_;
    devices.laser = &laser_;
    devices.camera_health = [] {
      DeviceHealth camera;
      camera.name = "camera";
      return camera;
    };
    devices.estop_latch = latch_.get();
    devices.sonar = sonar_;
    devices.bumpers = bumpers_;
    controller_.emplace(options_, devices, &link_, &clock_);
    std::string error;
    EXPECT_TRUE(controller_->Start(&error)) << error;
    return *controller_;
  }

  // Stops the controller as a clean shutdown does, then starts a new one (with a new latch store
  // on `state_dir`, as a restarted process would).
  void Restart(const std::string& state_dir) {
    if (controller_) controller_->Stop();
    controller_.reset();
    latch_ = std::make_unique<drive::EstopLatchStore>(state_dir);
    sequence_.clear();
    Make();
  }
  void Estop(const std::string& id, bool engage) {
    EmergencyStop stop;
    stop.stamp = clock_.Now();
    stop.sender_id = id;
    stop.engage = engage;
    controller_->OnEmergencyStop(stop);
  }
  RobotHealth LatestHealth() {
    clock_.Advance(options_.health_period);
    Run(1);
    EXPECT_FALSE(link_.healths.empty());
    return link_.healths.empty() ? RobotHealth{} : link_.healths.back();
  }

  void Take(const std::string& id, bool take = true) {
    ControlRequest request;
    request.stamp = clock_.Now();
    request.sender_id = id;
    request.take = take;
    controller_->OnControlRequest(request);
  }
  void Command(const std::string& id, double v, bool enable) {
    VelocityCommand command;
    command.stamp = clock_.Now();
    command.sequence = ++sequence_[id];
    command.sender_id = id;
    command.linear_mps = v;
    command.enable = enable;
    controller_->OnCommand(command);
  }
  // Runs `cycles` control cycles: a fresh open scan each cycle, `on_cycle` before each step.
  void Run(
      int cycles, const std::function<void()>& on_cycle = [] {}) {
    for (int i = 0; i < cycles; ++i) {
      on_cycle();
      laser_.Emit(OpenScan(clock_.Now(), ++scan_sequence_));
      ASSERT_EQ(controller_->Step(clock_.SteadyNow()), StepResult::kRunning);
      clock_.Advance(kCycle);
      motors_.Advance(kCycle, clock_.Now(), clock_.SteadyNow());
    }
  }
  // Alice takes the lease, arms (deadman up, then down) and drives forward at 0.3 m/s.
  void AliceDrives(int cycles) {
    Take("alice");
    Command("alice", 0, false);
    Run(cycles, [this] { Command("alice", 0.3, true); });
  }

  FakeClock clock_;
  RobotControllerOptions options_;
  drive::FakeDriveMotors motors_;
  FlakyMotors flaky_motors_;  // declared before controller_, which uses the motors until it ends
  FakeLaser laser_;
  sonar::SonarRing* sonar_ = nullptr;      // set before Make() to fit a sonar belt
  bumper::BumperBelt* bumpers_ = nullptr;  // set before Make() to fit a bumper belt
  FakeRobotLink link_;
  std::unique_ptr<drive::EstopLatchStore> latch_;  // outlives controller_
  std::optional<RobotController> controller_;
  std::map<std::string, uint64_t> sequence_;
  uint64_t scan_sequence_ = 0;
};

TEST_F(RobotControllerTest, DrivesTheMotorsWithTheGovernorOutputAndPublishesOdometry) {
  Make();
  AliceDrives(50);  // 1 s: the ramp (0.5 m/s^2) reaches 0.3 m/s
  EXPECT_NEAR(motors_.wheels().left_mps, 0.3, 1e-6);
  EXPECT_NEAR(motors_.wheels().right_mps, 0.3, 1e-6);
  ASSERT_FALSE(link_.odometries.empty());
  EXPECT_GT(link_.odometries.back().pose.x_m, 0.1);
  EXPECT_EQ(controller_->governor().status().state, WatchdogState::kDriving);
}

TEST_F(RobotControllerTest, ScansReachTheGovernorAndTheLink) {
  Make();
  EXPECT_EQ(laser_.starts, 1);
  laser_.Emit(OpenScan(clock_.Now(), 7));
  ASSERT_EQ(link_.scans.size(), 1u);
  EXPECT_EQ(link_.scans[0].sequence, 7u);
  EXPECT_EQ(controller_->governor().status().counters.scans, 1u);
}

TEST_F(RobotControllerTest, SilentHolderLosesTheLeaseAndTheRobotStops) {
  Make();
  AliceDrives(50);
  ASSERT_EQ(controller_->lease().holder(), "alice");
  ASSERT_GT(motors_.wheels().left_mps, 0.2);
  // Alice goes silent: the deadman ramps down, then the holder timeout frees the lease.
  Run(24);  // 480 ms < holder_timeout
  EXPECT_EQ(controller_->lease().holder(), "alice");
  Run(5);
  EXPECT_EQ(controller_->lease().holder(), "");
  EXPECT_EQ(controller_->lease().stats().holder_lost, 1u);
  EXPECT_EQ(link_.leases.back().holder_id, "") << "the change is published at once";
  Run(50);
  EXPECT_DOUBLE_EQ(motors_.wheels().left_mps, 0.0);
  EXPECT_DOUBLE_EQ(motors_.wheels().right_mps, 0.0);
}

TEST_F(RobotControllerTest, AcceptedCommandsKeepTheHolderAliveLongAfterTheTimeout) {
  Make();
  AliceDrives(100);  // 2 s of commands: four holder timeouts
  EXPECT_EQ(controller_->lease().holder(), "alice");
  EXPECT_EQ(controller_->lease().stats().holder_lost, 0u);
}

TEST_F(RobotControllerTest, RejectedCommandsDoNotKeepTheHolderAlive) {
  Make();
  Take("alice");
  // Commands stamped 1 s in the past are stale (max age 300 ms): rejected, no sign of life.
  Run(30, [this] {
    VelocityCommand command;
    command.stamp = clock_.Now() - std::chrono::seconds(1);
    command.sequence = ++sequence_["alice"];
    command.sender_id = "alice";
    controller_->OnCommand(command);
  });
  EXPECT_EQ(controller_->lease().holder(), "");
  EXPECT_GT(controller_->governor().status().counters.rejected_stale, 20u);
}

TEST_F(RobotControllerTest, HolderTimeoutCountsFromTheGrantNotFromStart) {
  Make();
  Run(100);  // 2 s with nobody holding the lease
  Take("alice");
  Run(10);  // 200 ms after the grant, no command yet
  EXPECT_EQ(controller_->lease().holder(), "alice");
}

TEST_F(RobotControllerTest, PublishesLeaseAndIntrinsicsOnChangeAndEveryLeasePeriod) {
  Make();
  Run(1);
  ASSERT_EQ(link_.leases.size(), 1u);
  ASSERT_EQ(link_.camera_infos.size(), 2u);
  EXPECT_EQ(link_.camera_infos[0].first, Eye::kLeft);
  EXPECT_EQ(link_.camera_infos[1].second.frame_id, "camera_right");
  EXPECT_EQ(link_.camera_infos[0].second.stamp, link_.leases[0].stamp);
  Run(10);  // 200 ms: no change, no period
  EXPECT_EQ(link_.leases.size(), 1u);
  Take("bob");
  Run(1);
  ASSERT_EQ(link_.leases.size(), 2u);
  EXPECT_EQ(link_.leases.back().holder_id, "bob");
  Take("alice");  // weaker than bob: refused, but still re-published (a fresh answer)
  Run(1);
  EXPECT_EQ(link_.leases.back().holder_id, "bob");
  const size_t before = link_.leases.size();
  Run(50);  // one lease period
  EXPECT_EQ(link_.leases.size(), before + 1);
}

TEST_F(RobotControllerTest, HealthListsEveryDeviceEveryHealthPeriod) {
  Make();
  AliceDrives(26);  // 520 ms: health at 0 and at 500 ms
  ASSERT_EQ(link_.healths.size(), 2u);
  const RobotHealth& health = link_.healths.back();
  EXPECT_EQ(health.robot_id, "robot");
  EXPECT_EQ(health.lease_holder, "alice");
  EXPECT_EQ(health.watchdog_state, WatchdogState::kDriving);
  std::vector<std::string> names;
  for (const DeviceHealth& d : health.devices) names.push_back(d.name);
  EXPECT_EQ(names,
            (std::vector<std::string>{"camera", "laser", "drive_safety", "drive", "network"}));
  const DeviceHealth* drive = Device(health, "drive");
  ASSERT_NE(drive, nullptr);
  EXPECT_NEAR(drive->rate_hz, 50.0, 0.5);
  EXPECT_EQ(drive->state, DeviceState::kOk);
  EXPECT_EQ(Counter(*drive, "motor_errors"), 0u);
  EXPECT_EQ(Counter(*drive, "odometry_glitches"), 0u);
}

TEST_F(RobotControllerTest, MotorFailuresAreCountedAndTheDriveReportsNoLink) {
  Make(&flaky_motors_);
  Run(30);
  EXPECT_EQ(controller_->motor_errors(), 30u);
  const DeviceHealth* drive = Device(link_.healths.back(), "drive");
  ASSERT_NE(drive, nullptr);
  EXPECT_EQ(drive->state, DeviceState::kError);
  EXPECT_EQ(drive->message, "no link to the motor board");
  EXPECT_EQ(Counter(*drive, "motor_errors"), 26u) << "health at 500 ms, after 26 cycles";
  EXPECT_TRUE(link_.odometries.empty());
}

TEST_F(RobotControllerTest, AWriteBlockedPastTheLimitStopsTheMotorsAndReportsTheStall) {
  Make();
  AliceDrives(50);
  ASSERT_GT(motors_.wheels().left_mps, 0.2);
  const int stops_before = motors_.stops();
  link_.blocked = std::chrono::seconds(30);  // at the limit: not yet
  EXPECT_EQ(controller_->Step(clock_.SteadyNow()), StepResult::kRunning);
  link_.blocked = std::chrono::seconds(31);
  EXPECT_EQ(controller_->Step(clock_.SteadyNow()), StepResult::kWriteStalled);
  EXPECT_EQ(motors_.stops(), stops_before + 1);
  EXPECT_DOUBLE_EQ(motors_.wheels().left_mps, 0.0);
}

TEST_F(RobotControllerTest, NoStallVerdictWhenTheLimitIsZero) {
  options_.write_stall_limit = Duration::zero();
  Make();
  link_.blocked = std::chrono::hours(1);
  EXPECT_EQ(controller_->Step(clock_.SteadyNow()), StepResult::kRunning);
}

TEST_F(RobotControllerTest, EmergencyStopFromAStrangerIsRefusedFromAnObserverEngages) {
  Make();
  AliceDrives(50);
  EmergencyStop stop;
  stop.sender_id = "mallory";
  controller_->OnEmergencyStop(stop);
  EXPECT_FALSE(controller_->governor().status().estop_engaged);
  stop.sender_id = "olga";
  controller_->OnEmergencyStop(stop);
  EXPECT_TRUE(controller_->governor().status().estop_engaged);
  Run(1, [this] { Command("alice", 0.3, true); });
  EXPECT_DOUBLE_EQ(motors_.wheels().left_mps, 0.0) << "e-stop: zero at once, no ramp";
}

TEST_F(RobotControllerTest, AnEngagedEstopSurvivesARestartUntilAPilotReleasesIt) {
  const std::string dir = testing::MakeTempDir("mostar_controller_latch_");
  Restart(dir);  // first start: unlatched
  EXPECT_FALSE(controller_->governor().status().estop_engaged);
  AliceDrives(50);
  EXPECT_GT(motors_.wheels().left_mps, 0.0);
  Estop("olga", true);
  Estop("olga", true);  // clients repeat it until the robot reports it: recorded once
  const RobotHealth before = LatestHealth();
  const DeviceHealth* latch_before = Device(before, "estop_latch");
  ASSERT_NE(latch_before, nullptr);
  EXPECT_EQ(Counter(*latch_before, "writes"), 2u);  // the start, the engagement
  Restart(dir);
  EXPECT_TRUE(controller_->governor().status().estop_engaged);
  RobotHealth health = LatestHealth();
  EXPECT_TRUE(health.estop_engaged);
  const DeviceHealth* latch = Device(health, "estop_latch");
  ASSERT_NE(latch, nullptr);
  EXPECT_EQ(latch->state, DeviceState::kWarn);
  EXPECT_NE(latch->message.find("engaged before the restart by olga"), std::string::npos)
      << latch->message;
  EXPECT_NE(Device(health, "drive_safety")->message.find("engaged before the restart by olga"),
            std::string::npos);
  AliceDrives(50);
  EXPECT_DOUBLE_EQ(motors_.wheels().left_mps, 0.0) << "latched after the restart";
  // Alice (a pilot) releases; after a re-arm the robot drives, and a clean stop restarts free.
  Estop("alice", false);
  EXPECT_FALSE(controller_->governor().status().estop_engaged);
  AliceDrives(50);
  EXPECT_GT(motors_.wheels().left_mps, 0.0);
  Restart(dir);
  EXPECT_FALSE(controller_->governor().status().estop_engaged);
}

TEST_F(RobotControllerTest, AnUncleanStopRestartsLatchedWithTheReasonInHealth) {
  const std::string dir = testing::MakeTempDir("mostar_controller_latch_");
  Restart(dir);
  AliceDrives(20);
  // The process dies here (watchdog, crash): no clean stop. The next one starts latched.
  drive::EstopLatchStore next_store(dir);
  RobotControllerDevices devices;
  devices.motors = &motors_;
  devices.estop_latch = &next_store;
  RobotController next(options_, devices, &link_, &clock_);
  EXPECT_TRUE(next.governor().status().estop_engaged);
  next.Step(clock_.SteadyNow());
  ASSERT_FALSE(link_.healths.empty());
  const RobotHealth& health = link_.healths.back();
  EXPECT_TRUE(health.estop_engaged);
  ASSERT_NE(Device(health, "estop_latch"), nullptr);
  EXPECT_NE(Device(health, "estop_latch")->message.find("did not stop cleanly"), std::string::npos)
      << Device(health, "estop_latch")->message;
}

TEST_F(RobotControllerTest, AReleaseThatCannotBeRecordedDoesNotTakeEffect) {
  const std::string dir = testing::MakeTempDir("mostar_controller_latch_");
  {
    std::ofstream file(dir + "/file");
    file << "x";
  }
  Restart(dir + "/file");  // a state directory that cannot exist: starts latched
  EXPECT_TRUE(controller_->governor().status().estop_engaged);
  Take("alice");  // only the lease holder may release the e-stop
  Estop("alice", false);
  EXPECT_TRUE(controller_->governor().status().estop_engaged);
  const RobotHealth health = LatestHealth();
  EXPECT_TRUE(health.estop_engaged);
  const DeviceHealth* latch = Device(health, "estop_latch");
  ASSERT_NE(latch, nullptr);
  EXPECT_EQ(latch->state, DeviceState::kError);
  EXPECT_EQ(Counter(*latch, "write_failures"), 2u);  // the start, the release
  AliceDrives(50);
  EXPECT_DOUBLE_EQ(motors_.wheels().left_mps, 0.0);
}

// Observers may engage the e-stop, never release it; only the lease holder releases it.
TEST_F(RobotControllerTest, OnlyTheLeaseHolderReleasesTheEstop) {
  Make();
  AliceDrives(50);
  EmergencyStop stop;
  stop.sender_id = "olga";
  controller_->OnEmergencyStop(stop);
  ASSERT_TRUE(controller_->governor().status().estop_engaged);
  stop.engage = false;
  for (const char* id : {"olga", "bob", "mallory"}) {
    stop.sender_id = id;
    controller_->OnEmergencyStop(stop);
    EXPECT_TRUE(controller_->governor().status().estop_engaged) << id << " released it";
  }
  EXPECT_EQ(controller_->governor().status().counters.estop_refused, 3u);
  Run(5, [this] { Command("alice", 0.3, true); });
  EXPECT_DOUBLE_EQ(motors_.wheels().left_mps, 0.0);
  stop.sender_id = "alice";
  controller_->OnEmergencyStop(stop);
  EXPECT_FALSE(controller_->governor().status().estop_engaged);
}

// Someone at the robot releases the e-stop (SIGUSR2): recorded, and a re-arm is still needed.
TEST_F(RobotControllerTest, ALocalReleaseFreesTheLatchAndNeedsARearm) {
  const std::string dir = testing::MakeTempDir("mostar_controller_latch_");
  Restart(dir);
  EXPECT_FALSE(controller_->ReleaseEstopLocally()) << "nothing engaged";
  AliceDrives(50);
  Estop("olga", true);
  ASSERT_TRUE(controller_->governor().status().estop_engaged);
  EXPECT_TRUE(controller_->ReleaseEstopLocally());
  EXPECT_FALSE(controller_->governor().status().estop_engaged);
  Run(5, [this] { Command("alice", 0.3, true); });
  EXPECT_DOUBLE_EQ(motors_.wheels().left_mps, 0.0) << "drove without a re-arm";
  AliceDrives(50);
  EXPECT_GT(motors_.wheels().left_mps, 0.0);
  Restart(dir);  // the release was recorded
  EXPECT_FALSE(controller_->governor().status().estop_engaged);
}

// DDS liveliness of the holder's command writer (RobotNode::Callbacks::on_command_stream_lost).
TEST_F(RobotControllerTest, TheHoldersLostCommandStreamFreesTheLeaseAtOnce) {
  Make();
  AliceDrives(50);
  ASSERT_GT(motors_.wheels().left_mps, 0.2);
  controller_->OnCommandStreamLost("bob");  // not the holder: nothing happens
  EXPECT_EQ(controller_->lease().holder(), "alice");
  controller_->OnCommandStreamLost("alice");
  EXPECT_EQ(controller_->lease().holder(), "");
  EXPECT_EQ(controller_->lease().stats().holder_lost, 1u);
  EXPECT_EQ(controller_->governor().status().counters.link_losses, 1u);
  Run(1);
  EXPECT_EQ(link_.leases.back().holder_id, "") << "the change is published at once";
  Run(50, [this] { Command("alice", 0.3, true); });
  EXPECT_DOUBLE_EQ(motors_.wheels().left_mps, 0.0) << "nobody inherits motion";
}

TEST_F(RobotControllerTest, StopStopsTheLaserAndBrakesOnce) {
  Make();
  AliceDrives(50);
  const int stops_before = motors_.stops();
  controller_->Stop();
  controller_->Stop();
  EXPECT_EQ(laser_.stops, 1);
  EXPECT_EQ(motors_.stops(), stops_before + 1);
  EXPECT_DOUBLE_EQ(motors_.wheels().left_mps, 0.0);
}

// The front sonar hears something 0.25 m ahead of the bumper line.
SonarRanges CloseSonar(Time stamp) {
  SonarRange r;
  r.mount = SonarMount{"sonar_0", 0.2, 0, 0};
  r.stamp = stamp;
  r.range_m = 0.25f;
  r.min_range_m = 0.03f;
  r.max_range_m = 6.0f;
  r.field_of_view_rad = 0.96f;
  SonarRanges ranges;
  ranges.cycle = 1;
  ranges.ranges.push_back(r);
  return ranges;
}

TEST_F(RobotControllerTest, SonarCyclesReachTheGovernorTheLinkAndHealth) {
  sonar::FakeSonarRing ring;
  sonar_ = &ring;
  Make();
  EXPECT_EQ(ring.starts, 1);
  ring.Emit(CloseSonar(clock_.Now()));
  ASSERT_EQ(link_.sonars.size(), 1u);
  EXPECT_EQ(link_.sonars[0].ranges.size(), 1u);
  EXPECT_EQ(controller_->governor().status().counters.sonar_cycles, 1u);
  // The obstacle the laser does not see keeps the robot from driving forward.
  AliceDrives(20);
  EXPECT_EQ(motors_.wheels().left_mps, 0.0);
  const RobotHealth health = LatestHealth();
  std::vector<std::string> names;
  for (const DeviceHealth& d : health.devices) names.push_back(d.name);
  EXPECT_EQ(names, (std::vector<std::string>{"camera", "laser", "sonar", "drive_safety", "drive",
                                             "network"}));
  controller_->Stop();
  EXPECT_EQ(ring.stops, 1);
}

TEST_F(RobotControllerTest, ABumperContactStopsTheRobotAndLatchesUntilThePilotRearms) {
  bumper::FakeBumperBelt belt(16);
  bumpers_ = &belt;
  Make();
  AliceDrives(50);
  ASSERT_NEAR(motors_.wheels().left_mps, 0.3, 1e-6);
  ASSERT_FALSE(link_.bumpers.empty());
  EXPECT_EQ(link_.bumpers.back().segment_count, 16);
  EXPECT_EQ(link_.bumpers.back().latched, 0u);
  belt.Press(1u << 15);  // front right
  Run(1, [this] { Command("alice", 0.3, true); });
  EXPECT_EQ(motors_.wheels().left_mps, 0.0) << "stopped in the cycle of the contact";
  EXPECT_EQ(link_.bumpers.back().pressed, 1u << 15);
  EXPECT_EQ(link_.bumpers.back().latched, 1u << 15);
  belt.Press(0);
  Run(25, [this] { Command("alice", 0.3, true); });
  EXPECT_EQ(motors_.wheels().left_mps, 0.0) << "latched after the release";
  EXPECT_EQ(link_.bumpers.back().pressed, 0u);
  EXPECT_EQ(link_.bumpers.back().latched, 1u << 15);
  ASSERT_FALSE(link_.healths.empty());
  const RobotHealth health = link_.healths.back();  // of the last 500 ms
  EXPECT_EQ(health.watchdog_state, WatchdogState::kWaitRearm);
  const DeviceHealth* bumpers = Device(health, "bumpers");
  ASSERT_NE(bumpers, nullptr);
  EXPECT_EQ(bumpers->state, DeviceState::kWarn);
  EXPECT_NE(bumpers->message.find("segment 15 (338 deg)"), std::string::npos) << bumpers->message;
  EXPECT_EQ(Counter(*bumpers, "latched_mask"), 1u << 15);
  const DeviceHealth* safety = Device(health, "drive_safety");
  ASSERT_NE(safety, nullptr);
  EXPECT_NE(safety->message.find("segment 15"), std::string::npos) << safety->message;
  // The pilot re-arms: the latch clears and the robot drives.
  Command("alice", 0, false);
  Run(50, [this] { Command("alice", 0.3, true); });
  EXPECT_NEAR(motors_.wheels().left_mps, 0.3, 1e-6);
  EXPECT_EQ(link_.bumpers.back().latched, 0u);
}

TEST_F(RobotControllerTest, BumperStateIsPublishedOnChangeAndEveryPeriod) {
  bumper::FakeBumperBelt belt(16);
  bumpers_ = &belt;
  Make();
  Run(101);  // 0 .. 2 s: published at 0, 1 and 2 s
  EXPECT_EQ(link_.bumpers.size(), 3u);
  belt.Press(1u << 4);
  Run(1);
  ASSERT_EQ(link_.bumpers.size(), 4u) << "on change";
  EXPECT_EQ(link_.bumpers.back().pressed, 1u << 4);
  Run(1);
  EXPECT_EQ(link_.bumpers.size(), 4u);
}

TEST_F(RobotControllerTest, AnUnreadableBumperBeltStopsTheRobot) {
  bumper::FakeBumperBelt belt(16);
  bumpers_ = &belt;
  Make();
  AliceDrives(50);
  ASSERT_NEAR(motors_.wheels().left_mps, 0.3, 1e-6);
  belt.Fail("gpiochip0: read failed");
  Run(5, [this] { Command("alice", 0.3, true); });
  EXPECT_EQ(motors_.wheels().left_mps, 0.0);
  EXPECT_FALSE(link_.bumpers.back().readable);
  const RobotHealth health = LatestHealth();
  const DeviceHealth* bumpers = Device(health, "bumpers");
  ASSERT_NE(bumpers, nullptr);
  EXPECT_EQ(bumpers->state, DeviceState::kError);
  EXPECT_EQ(health.watchdog_state, WatchdogState::kWaitRearm);
}

TEST(RobotControllerOptionsTest, NamesTheInvalidOption) {
  RobotControllerOptions options;
  std::string error;
  EXPECT_TRUE(options.IsValid(&error)) << error;
  options.holder_timeout = Duration::zero();
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_EQ(error, "holder_timeout must be positive");
  options = {};
  options.safety.max_linear_mps = -1;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_EQ(error.rfind("safety: ", 0), 0u) << error;
}

TEST(RobotControllerDeathTest, InvalidOptionsAreABug) {
  FakeClock clock;
  FakeRobotLink link;
  drive::FakeDriveMotors motors(0.5, 0.001);
  RobotControllerOptions options;
  options.health_period = Duration::zero();
  RobotControllerDevices devices;
  devices.motors = &motors;
  EXPECT_DEATH(RobotController(options, devices, &link, &clock), "health_period must be positive");
}

}  // namespace
}  // namespace mostar::server
