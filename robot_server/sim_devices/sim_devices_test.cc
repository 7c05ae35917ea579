// The simulated robot driven through the same pieces robot_server uses (SimDriveMotors, the
// safety governor, odometry), on a fake clock: obstacle slow-down stops it before a wall the
// laser sees, and odometry from the simulated encoders follows the true pose.
#include "robot_server/sim_devices/sim_devices.h"

#include <gtest/gtest.h>

#include <cmath>
#include <mutex>
#include <optional>
#include <thread>

#include "common/time/fake_clock.h"
#include "robot_server/drive/odometry.h"
#include "robot_server/drive/safety_governor.h"
#include "robot_server/sim/scene.h"

namespace mostar::sim {
namespace {

// A 6 m x 3 m room, the robot 2 m from the far wall, facing it.
proto::Scene Room() {
  proto::Scene scene;
  std::string error;
  const std::string text = R"(
    name: "test_room"
    floor { min_x_m: -3 max_x_m: 3 min_y_m: -1.5 max_y_m: 1.5 pattern: PLAIN }
    wall { x0_m: -3 y0_m: 1.5 x1_m: 3 y1_m: 1.5 height_m: 2 }
    wall { x0_m: -3 y0_m: -1.5 x1_m: 3 y1_m: -1.5 height_m: 2 }
    wall { x0_m: 3 y0_m: -1.5 x1_m: 3 y1_m: 1.5 height_m: 2 }
    wall { x0_m: -3 y0_m: -1.5 x1_m: -3 y1_m: 1.5 height_m: 2 }
    start { x_m: 1.0 y_m: 0 theta_rad: 0 }
  )";
  EXPECT_TRUE(ParseScene(text, "test_room", &scene, &error)) << error;
  return scene;
}

class SimDrivingTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    world_ = SimWorld::Create(Room(), proto::SimConfig(), clock_.Now(), &error);
    ASSERT_NE(world_, nullptr) << error;
    motors_ = std::make_unique<SimDriveMotors>(world_.get(), &clock_);
  }

  // One 20 ms control cycle with a fresh command from the holder.
  void Cycle(drive::SafetyGovernor* governor, double v, double w, bool enable = true) {
    VelocityCommand cmd;
    cmd.stamp = clock_.Now();
    cmd.sequence = ++sequence_;
    cmd.sender_id = "pilot";
    cmd.linear_mps = v;
    cmd.angular_radps = w;
    cmd.enable = enable;
    governor->HandleCommand(cmd, Duration(0));
    governor->SetLaserScan(world_->ScanAt(clock_.Now()));
    const drive::GovernorOutput out = governor->Update();
    std::string error;
    motors_->SetVelocity(out.linear_mps, out.angular_radps, &error);
    clock_.Advance(std::chrono::milliseconds(20));
    world_->AdvanceTo(clock_.Now());
  }

  FakeClock clock_;
  std::unique_ptr<SimWorld> world_;
  std::unique_ptr<SimDriveMotors> motors_;
  uint64_t sequence_ = 0;
};

TEST_F(SimDrivingTest, ObstacleSlowDownStopsBeforeTheWallTheLaserSees) {
  drive::SafetyOptions options;
  options.front_extent_m = 0.15;
  drive::SafetyGovernor governor(clock_, options);
  governor.SetLeaseHolder("pilot");
  Cycle(&governor, 0, 0, false);  // arm: deadman up, then down
  double max_speed = 0;
  for (int i = 0; i < 600; ++i) {  // 12 s of "full speed ahead"
    Cycle(&governor, 0.6, 0);
    max_speed = std::max(max_speed, world_->StateAt(clock_.Now()).linear_mps);
  }
  const RobotState state = world_->StateAt(clock_.Now());
  EXPECT_GT(max_speed, 0.3) << "the robot never got going";
  EXPECT_EQ(state.collision_count, 0u) << "drove into the wall";
  EXPECT_NEAR(state.linear_mps, 0.0, 0.01) << "did not stop";
  // Stopped with the bumper about the stop distance (0.30 m) from the wall at x = 3.
  const double bumper_x = state.world_from_base.x_m + options.front_extent_m;
  EXPECT_GT(3.0 - bumper_x, 0.2);
  EXPECT_LT(3.0 - bumper_x, 0.45);
}

// Driven into the wall with no governor: the front bumper segment is pressed at the contact,
// and released once the robot backs off.
TEST_F(SimDrivingTest, DrivingIntoTheWallPressesTheFrontBumper) {
  SimBumperBelt bumpers(world_.get(), 16, &clock_);
  uint32_t pressed = 0;
  std::string error;
  ASSERT_TRUE(bumpers.Read(&pressed, &error));
  EXPECT_EQ(pressed, 0u);
  for (int i = 0; i < 500 && !world_->StateAt(clock_.Now()).in_collision; ++i) {
    ASSERT_TRUE(motors_->SetVelocity(0.3, 0, &error)) << error;
    clock_.Advance(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(world_->StateAt(clock_.Now()).in_collision) << "never reached the wall";
  ASSERT_TRUE(bumpers.Read(&pressed, &error));
  EXPECT_TRUE(pressed & 1u) << "front segment, mask " << pressed;
  EXPECT_FALSE(pressed & (1u << 8)) << "not the rear";
  for (int i = 0; i < 25; ++i) {
    ASSERT_TRUE(motors_->SetVelocity(-0.2, 0, &error)) << error;
    clock_.Advance(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(bumpers.Read(&pressed, &error));
  EXPECT_EQ(pressed, 0u);
}

TEST_F(SimDrivingTest, OdometryFollowsTheTruePoseOverADrivenPath) {
  drive::SafetyOptions options;
  options.stop_distance_m = 0.05;
  options.slow_distance_m = 0.10;
  drive::SafetyGovernor governor(clock_, options);
  governor.SetLeaseHolder("pilot");
  const auto& drive = world_->drive_params();
  drive::OdometryOptions odometry_options;
  odometry_options.wheel_radius_m = drive.wheel_radius_m;
  odometry_options.track_width_m = drive.track_width_m;
  odometry_options.ticks_per_turn = drive.encoder_pulses_per_turn;
  odometry_options.counter_bits = drive.encoder_counter_bits;
  odometry_options.axle_x_m = drive.axle_x_m;
  drive::OdometryIntegrator odometry(odometry_options);
  const Pose2D start = world_->StateAt(clock_.Now()).world_from_base;
  std::string error;
  Cycle(&governor, 0, 0, false);
  double travelled = 0;
  // Back up, turn, arc: a path away from the walls (reverse is not limited by the laser).
  const struct {
    double v, w;
    int cycles;
  } legs[] = {{-0.2, 0, 150}, {0, 0.8, 100}, {0.2, 0.3, 150}, {0, -0.6, 100}, {-0.15, 0, 100}};
  for (const auto& leg : legs) {
    for (int i = 0; i < leg.cycles; ++i) {
      Cycle(&governor, leg.v, leg.w);
      drive::EncoderReading reading;
      ASSERT_TRUE(motors_->ReadEncoders(&reading, &error)) << error;
      odometry.AddReading(reading);
      travelled += std::abs(world_->StateAt(clock_.Now()).linear_mps) * 0.02;
    }
  }
  const Pose2D truth = world_->StateAt(clock_.Now()).world_from_base;
  // Odometry starts at zero in the start pose's frame.
  const double dx = truth.x_m - start.x_m, dy = truth.y_m - start.y_m;
  const double c = std::cos(start.theta_rad), s = std::sin(start.theta_rad);
  const double expected_x = c * dx + s * dy, expected_y = -s * dx + c * dy;
  const Pose2D& odom = odometry.odometry().pose;
  ASSERT_GT(travelled, 0.5);
  EXPECT_LT(std::hypot(odom.x_m - expected_x, odom.y_m - expected_y), 0.02 * travelled + 0.01);
  EXPECT_NEAR(std::remainder(odom.theta_rad - (truth.theta_rad - start.theta_rad), 2 * M_PI), 0,
              0.03);
  EXPECT_EQ(world_->StateAt(clock_.Now()).collision_count, 0u);
}

// The real SRF08 driver on the emulated bus: the front sensor hears a glass pane that the laser
// passes, the rear one the wall behind; the belt runs on its own thread in real time.
TEST(SimulatedSonarTest, TheDriverHearsTheGlassPaneAheadAndTheWallBehind) {
  proto::Scene scene = Room();
  auto* glass = scene.add_box();
  glass->set_x_m(2.2);
  glass->set_size_x_m(0.02);
  glass->set_size_y_m(1.0);
  glass->set_height_m(2.0);
  glass->mutable_material()->set_laser(proto::TRANSPARENT);
  std::string error;
  auto world = SimWorld::Create(scene, proto::SimConfig(), SystemClock::Instance().Now(), &error);
  ASSERT_NE(world, nullptr) << error;
  sonar::SonarConfig config;
  auto* front = config.add_sensors();
  front->set_address(0x70);
  front->set_x_m(0.3);
  auto* rear = config.add_sensors();
  rear->set_address(0x71);
  rear->set_x_m(-0.3);
  rear->set_yaw_deg(180);
  config.set_ranging_time_ms(30);  // the 6 m window's echo time is 35 ms: polls wait the rest
  auto sim =
      SimulatedSonar::Create(world.get(), config, SonarCone{}, &SystemClock::Instance(), &error);
  ASSERT_NE(sim, nullptr) << error;
  std::mutex mutex;
  std::optional<SonarRanges> latest;
  ASSERT_TRUE(sim->ring()->Start(
      [&](const SonarRanges& r) {
        std::lock_guard<std::mutex> lock(mutex);
        latest = r;
      },
      &error))
      << error;
  for (int i = 0; i < 100; ++i) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (latest) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  sim->ring()->Stop();
  ASSERT_TRUE(latest.has_value()) << "no belt cycle within 2 s";
  ASSERT_EQ(latest->ranges.size(), 2u);
  // The robot at x = 1 (Room()): the front sensor 0.89 m from the pane at 2.19 m. The rear one
  // is 3.7 m from the wall at x = -3, but the edge of its 55 degree cone meets the side walls
  // (1.5 m away) first: 1.5 / sin(27.5 deg) = 3.25 m. A sonar's wide cone, as on the robot.
  EXPECT_NEAR(latest->ranges[0].range_m, 0.89, 0.011);
  EXPECT_NEAR(latest->ranges[1].range_m, 1.5 / std::sin(27.5 * M_PI / 180), 0.011);
  EXPECT_EQ(sim->ring()->Health().state, DeviceState::kOk) << sim->ring()->Health().message;
}

}  // namespace
}  // namespace mostar::sim
