// The robot's control loop (RobotController with the governor of server_sim.pbtxt) driving the
// simulated MORDUC in deploy/scenes/glass_door.pbtxt, in-process on a fake clock: the laser
// scans, sonar cycles and bumper contacts come from the simulated world at their rates, the
// motors are the simulated drive. The laser sees through the glass door and over the low black
// cabinet; the sonar belt and the bumpers do not miss them.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "common/config/config_loader.h"
#include "common/time/fake_clock.h"
#include "robot_server/control/robot_controller.h"
#include "robot_server/drive/drive_config.h"
#include "robot_server/node/fake_robot_link.h"
#include "robot_server/server_config.pb.h"
#include "robot_server/server_options.h"
#include "robot_server/sim/scene.h"
#include "robot_server/sim/sim_test_helpers.h"
#include "robot_server/sim/sim_world.h"
#include "robot_server/sim_devices/sim_devices.h"
#include "robot_server/sonar/sonar_config.h"

namespace mostar {
namespace {

using sim::testing::SourceDir;
using std::chrono::milliseconds;

constexpr Duration kCycle = milliseconds(20);
constexpr double kDoorX = 2.0 - 0.01;  // the glass door's near face, world frame
constexpr double kFrontX = 0.12;       // front of the footprint circle, base frame

// A laser the test feeds from the simulated world, as the LMS200 driver's thread would.
class WorldLaser final : public laser::LaserScanner {
 public:
  bool Start(ScanCallback on_scan, std::string*) override {
    on_scan_ = std::move(on_scan);
    return true;
  }
  void Stop() override {}
  DeviceHealth Health() const override {
    DeviceHealth health;
    health.name = "laser";
    return health;
  }
  void Emit(const LaserScan& scan) { on_scan_(scan); }

 private:
  ScanCallback on_scan_;
};

// The sonar belt of the configuration, ranging in the simulated world (SimWorld::SonarEchoAt,
// the echo the SRF08 emulator answers with in SimulatedSonar) one cycle at a time.
class WorldSonar final : public sonar::SonarRing {
 public:
  WorldSonar(sim::SimWorld* world, sonar::Srf08RingOptions options)
      : world_(world), options_(std::move(options)) {
    cone_.field_of_view_rad = options_.field_of_view_rad;
    cone_.min_range_m = options_.min_range_m;
    cone_.max_range_m = options_.max_range_m;
  }
  bool Start(RangesCallback on_ranges, std::string*) override {
    on_ranges_ = std::move(on_ranges);
    return true;
  }
  void Stop() override {}
  DeviceHealth Health() const override {
    DeviceHealth health;
    health.name = "sonar";
    return health;
  }
  void Cycle(Time now) {
    SonarRanges ranges;
    ranges.cycle = ++cycle_;
    for (const sonar::Srf08Sensor& s : options_.sensors) {
      SonarRange r;
      r.mount = s.mount;
      r.stamp = now;
      const float echo = world_->SonarEchoAt(now, s.mount, cone_);
      r.range_m = echo > options_.max_range_m ? std::numeric_limits<float>::infinity() : echo;
      r.min_range_m = static_cast<float>(options_.min_range_m);
      r.max_range_m = static_cast<float>(options_.max_range_m);
      r.field_of_view_rad = static_cast<float>(options_.field_of_view_rad);
      ranges.ranges.push_back(r);
    }
    on_ranges_(ranges);
  }

 private:
  sim::SimWorld* world_;
  const sonar::Srf08RingOptions options_;
  sim::SonarCone cone_;
  RangesCallback on_ranges_;
  uint64_t cycle_ = 0;
};

class GlassDoorTest : public ::testing::Test {
 protected:
  // The shipped simulator configuration and scene; the robot starts at `start` (world frame).
  void Build(double x_m, double y_m, double theta_rad, bool with_sonar = true) {
    std::string error;
    ASSERT_TRUE(LoadTextConfig(SourceDir() + "/deploy/config/server_sim.pbtxt", &config_, &error))
        << error;
    sim::proto::Scene scene;
    ASSERT_TRUE(sim::LoadScene(SourceDir() + "/deploy/scenes/glass_door.pbtxt", &scene, &error))
        << error;
    scene.mutable_start()->set_x_m(x_m);
    scene.mutable_start()->set_y_m(y_m);
    scene.mutable_start()->set_theta_rad(theta_rad);
    sim::proto::SimConfig sim_config;
    ASSERT_TRUE(
        sim::LoadSimConfig(SourceDir() + "/deploy/config/sim_morduc.pbtxt", &sim_config, &error))
        << error;
    world_ = sim::SimWorld::Create(scene, sim_config, clock_.Now(), &error);
    ASSERT_NE(world_, nullptr) << error;
    drive::DriveSettings settings;
    ASSERT_TRUE(drive::DriveSettingsFromProto(config_.drive(), &settings, &error)) << error;
    sonar::Srf08RingOptions sonar_options;
    ASSERT_TRUE(sonar::Srf08RingOptionsFromConfig(config_.sonar(), &sonar_options, &error))
        << error;
    ASSERT_EQ(sonar_options.sensors.size(), 8u) << "server_sim.pbtxt: the MORDUC's belt of 8";
    ASSERT_EQ(config_.bumpers().segments(), 16);
    motors_ = std::make_unique<sim::SimDriveMotors>(world_.get(), &clock_);
    sonar_ = std::make_unique<WorldSonar>(world_.get(), sonar_options);
    bumpers_ =
        std::make_unique<sim::SimBumperBelt>(world_.get(), config_.bumpers().segments(), &clock_);
    server::RobotControllerDevices devices;
    devices.motors = motors_.get();
    devices.laser = &laser_;
    with_sonar_ = with_sonar;
    devices.sonar = with_sonar ? sonar_.get() : nullptr;
    devices.bumpers = bumpers_.get();
    controller_ = std::make_unique<server::RobotController>(
        server::ControllerOptionsFrom(config_, settings, {}), devices, &link_, &clock_);
    ASSERT_TRUE(controller_->Start(&error)) << error;
    server::RobotController& c = *controller_;
    ControlRequest take;
    take.sender_id = "operator";  // a pilot of server_sim.pbtxt
    take.take = true;
    take.stamp = clock_.Now();
    c.OnControlRequest(take);
    Command(0, 0, false);  // arm: enable off, then on
  }

  void Command(double v, double w, bool enable) {
    VelocityCommand command;
    command.stamp = clock_.Now();
    command.sequence = ++sequence_;
    command.sender_id = "operator";
    command.linear_mps = v;
    command.angular_radps = w;
    command.enable = enable;
    controller_->OnCommand(command);
  }

  // One control cycle with the pilot asking for (v, w): a scan every cycle, a sonar cycle
  // every 6 (the belt's 4 groups of 30 ms), then the controller steps and time passes.
  void Cycle(double v, double w) {
    Command(v, w, true);
    laser_.Emit(world_->ScanAt(clock_.Now()));
    if (cycles_++ % 6 == 0 && with_sonar_) sonar_->Cycle(clock_.Now());
    ASSERT_EQ(controller_->Step(clock_.SteadyNow()), server::StepResult::kRunning);
    clock_.Advance(kCycle);
    world_->AdvanceTo(clock_.Now());
  }

  const DeviceHealth* Device(const RobotHealth& health, const std::string& name) {
    for (const DeviceHealth& d : health.devices) {
      if (d.name == name) return &d;
    }
    return nullptr;
  }

  FakeClock clock_;
  server::ServerConfig config_;
  std::unique_ptr<sim::SimWorld> world_;
  std::unique_ptr<sim::SimDriveMotors> motors_;
  WorldLaser laser_;
  std::unique_ptr<WorldSonar> sonar_;
  std::unique_ptr<sim::SimBumperBelt> bumpers_;
  server::FakeRobotLink link_;
  std::unique_ptr<server::RobotController> controller_;
  uint64_t sequence_ = 0;
  int cycles_ = 0;
  bool with_sonar_ = true;
};

// Driving at 0.4 m/s straight at the closed glass door: the laser measures the far wall through
// it, the sonar hears the door, and the governor stops the robot before it.
TEST_F(GlassDoorTest, TheRobotStopsBeforeTheGlassDoorTheLaserSeesThrough) {
  Build(0, 0, 0);
  double fastest = 0;
  for (int i = 0; i < 750; ++i) {  // 15 s: the cap's approach to the stop distance is gradual
    Cycle(0.4, 0);
    fastest = std::max(fastest, world_->StateAt(clock_.Now()).linear_mps);
  }
  const sim::RobotState state = world_->StateAt(clock_.Now());
  EXPECT_GT(fastest, 0.35) << "never drove at the pilot's 0.4 m/s";
  EXPECT_NEAR(state.linear_mps, 0.0, 0.01) << "did not stop";
  EXPECT_EQ(state.collision_count, 0u);
  const double front_x = state.world_from_base.x_m + kFrontX;
  EXPECT_GT(kDoorX - front_x, 0.0) << "stopped before the door";
  EXPECT_LT(kDoorX - front_x, 0.6) << "stopped near the stop distance";
  EXPECT_GT(front_x, 1.0) << "went most of the way";
  // The laser's beam straight ahead passes the door: it measures the far wall at x = 4.
  const LaserScan scan = world_->ScanAt(clock_.Now());
  const size_t ahead =
      static_cast<size_t>(std::lround(-scan.angle_min_rad / scan.angle_increment_rad));
  ASSERT_LT(ahead, scan.ranges_m.size());
  EXPECT_GT(scan.ranges_m[ahead], kDoorX - state.world_from_base.x_m + 0.5)
      << "the laser sees the door";
  for (const BumperState& b : link_.bumpers) EXPECT_EQ(b.pressed, 0u) << "no contact";
}

// The same run without the sonar belt hits the door: the test can fail.
TEST_F(GlassDoorTest, WithoutTheSonarTheLaserAloneDrivesIntoTheDoor) {
  Build(0, 0, 0, /*with_sonar=*/false);
  for (int i = 0; i < 500; ++i) Cycle(0.4, 0);
  const sim::RobotState state = world_->StateAt(clock_.Now());
  EXPECT_GT(state.world_from_base.x_m + kFrontX, kDoorX - 0.02) << "reached the door";
  ASSERT_FALSE(link_.bumpers.empty());
  EXPECT_NE(link_.bumpers.back().latched, 0u) << "the bumpers stopped it";
}

// Backing into the low black cabinet (reverse is not limited by the front sensors): the rear
// bumper segment closes, the robot stops in that cycle and stays latched, health names the
// segment; the pilot's re-arm releases it and forward motion away from the cabinet is allowed.
TEST_F(GlassDoorTest, BackingIntoTheCabinetPressesTheRearBumperStopsAndLatches) {
  // Facing -y, the rear of the footprint 0.14 m from the cabinet's front face (y = 1.2).
  Build(0, 0.5, -M_PI / 2);
  int cycles = 0;
  for (; cycles < 250 && (link_.bumpers.empty() || link_.bumpers.back().latched == 0); ++cycles) {
    Cycle(-0.2, 0);
  }
  ASSERT_FALSE(link_.bumpers.empty());
  const BumperState contact = link_.bumpers.back();
  ASSERT_NE(contact.latched, 0u) << "no contact within 5 s";
  EXPECT_TRUE(contact.latched & (1u << 8)) << "the rear segment, mask " << contact.latched;
  EXPECT_FALSE(contact.latched & 1u) << "not the front";
  // The laser sees nothing of the cabinet (under its plane, black).
  for (int i = 0; i < 50; ++i) Cycle(-0.2, 0);
  const sim::RobotState state = world_->StateAt(clock_.Now());
  EXPECT_EQ(state.linear_mps, 0.0) << "stopped and latched";
  const RobotHealth health = link_.healths.back();
  EXPECT_EQ(health.watchdog_state, WatchdogState::kWaitRearm);
  const DeviceHealth* bumpers = Device(health, "bumpers");
  ASSERT_NE(bumpers, nullptr);
  EXPECT_NE(bumpers->message.find("segment 8 (180 deg)"), std::string::npos) << bumpers->message;
  // Re-arm and drive away from it.
  Command(0, 0, false);
  const double y_before = world_->StateAt(clock_.Now()).world_from_base.y_m;
  for (int i = 0; i < 50; ++i) Cycle(0.2, 0);
  EXPECT_LT(world_->StateAt(clock_.Now()).world_from_base.y_m, y_before - 0.05);
  EXPECT_EQ(link_.bumpers.back().latched, 0u);
}

}  // namespace
}  // namespace mostar
