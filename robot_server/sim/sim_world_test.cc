#include "robot_server/sim/sim_world.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <thread>

#include "robot_server/sim/sim_test_helpers.h"

namespace mostar::sim {
namespace {

using testing::NoiselessConfig;
using testing::OpenFloor;

const Time kStart = FromUnixNanos(1'700'000'000'000'000'000);

std::unique_ptr<SimWorld> MakeWorld(const std::string& scene_text,
                                    proto::SimConfig config = NoiselessConfig()) {
  // Small images keep the tests quick; geometry does not depend on the size.
  config.mutable_camera()->set_width_px(160);
  config.mutable_camera()->set_height_px(120);
  config.mutable_camera()->set_focal_px(110);
  std::string error;
  auto sim = SimWorld::Create(OpenFloor(scene_text), config, kStart, &error);
  EXPECT_NE(sim, nullptr) << error;
  return sim;
}

TEST(SimWorldTest, DrivesOnCommandAndCountsTicks) {
  auto sim = MakeWorld("");
  sim->SetVelocity(0.5, 0.0);
  const RobotState s = sim->StateAt(kStart + FromSeconds(3));
  EXPECT_EQ(s.time, kStart + FromSeconds(3));
  // 0.5 m/s reached after 0.625 s at 0.8 m/s^2: 3 s cover 1.5 - 0.15625 m.
  EXPECT_NEAR(s.world_from_base.x_m, 1.5 - 0.5 * 0.5 * 0.625, 0.005);
  EXPECT_NEAR(s.linear_mps, 0.5, 1e-9);
  EXPECT_GT(s.encoders.left_total, 1000);
  EXPECT_EQ(s.encoders.left, static_cast<uint64_t>(s.encoders.left_total));
}

TEST(SimWorldTest, EarlierTimeIsServedFromTheCurrentState) {
  auto sim = MakeWorld("");
  sim->SetVelocity(0.5, 0.0);
  const EncoderTicks later = sim->EncodersAt(kStart + FromSeconds(2));
  const EncoderTicks earlier = sim->EncodersAt(kStart + FromSeconds(1));
  EXPECT_EQ(later.left_total, earlier.left_total);
}

TEST(SimWorldTest, CollisionIsReportedInTheState) {
  auto sim = MakeWorld("wall { x0_m: 1.5 y0_m: -5 x1_m: 1.5 y1_m: 5 }");
  sim->SetVelocity(0.4, 0.0);
  const RobotState s = sim->StateAt(kStart + FromSeconds(10));
  EXPECT_TRUE(s.in_collision);
  EXPECT_EQ(s.collision_count, 1u);
  EXPECT_LT(s.world_from_base.x_m, 1.5);
}

TEST(SimWorldTest, SonarEchoFollowsTheRobotTowardsAGlassDoor) {
  auto sim = MakeWorld(
      "box { x_m: 3 y_m: 0 size_x_m: 0.02 size_y_m: 2 height_m: 2 "
      "material { laser: TRANSPARENT } }");
  SonarMount front;
  front.x_m = 0.3;
  const SonarCone cone;
  EXPECT_NEAR(sim->SonarEchoAt(kStart, front, cone), 2.69, 1e-3);
  sim->SetVelocity(0.5, 0.0);
  const float later = sim->SonarEchoAt(kStart + FromSeconds(2), front, cone);
  const RobotState s = sim->StateAt(kStart + FromSeconds(2));
  EXPECT_NEAR(later, 2.69 - s.world_from_base.x_m, 1e-3);
  EXPECT_GT(s.world_from_base.x_m, 0.5);
}

TEST(SimWorldTest, ScanIsStampedAndComesWithItsTruth) {
  auto sim = MakeWorld("wall { x0_m: 3 y0_m: -20 x1_m: 3 y1_m: 20 }");
  sim->SetVelocity(0.5, 0.0);
  LaserGroundTruth truth;
  const Time t = kStart + FromSeconds(2);
  const LaserScan scan = sim->ScanAt(t, &truth);
  EXPECT_EQ(scan.stamp, t);
  ASSERT_EQ(scan.ranges_m.size(), 361u);
  EXPECT_NEAR(scan.ranges_m[180], 3.0 - truth.world_from_base.x_m, 1e-4);
  EXPECT_EQ(truth.true_ranges_m.size(), 361u);
  std::vector<float> sampled;
  sim->SampleRanges(t, -M_PI / 2 * 100 / 180, M_PI / 720, 401, &sampled);
  ASSERT_EQ(sampled.size(), 401u);
  EXPECT_NEAR(sampled[200], scan.ranges_m[180], 1e-4);
}

TEST(SimWorldTest, StereoPairComesWithPoseAndTruth) {
  auto sim = MakeWorld("wall { x0_m: 4 y0_m: -20 x1_m: 4 y1_m: 20 }");
  Pose2D pose;
  const StereoImages images = sim->StereoAt(kStart, true, &pose);
  EXPECT_EQ(images.left.size(), cv::Size(160, 120));
  EXPECT_EQ(images.right.size(), cv::Size(160, 120));
  EXPECT_EQ(images.left_truth.base_row_px.size(), 160u);
  EXPECT_GE(images.left_truth.base_row_px[80], 0);
  EXPECT_EQ(pose.x_m, 0.0);
  EXPECT_EQ(sim->calibration().width_px, 160);
}

TEST(SimWorldTest, OneSteppingThreadAndReadersRunTogether) {
  auto sim = MakeWorld("wall { x0_m: 6 y0_m: -20 x1_m: 6 y1_m: 20 }");
  std::atomic<bool> done{false};
  std::atomic<int> reads{0};
  std::thread stepper([&] {
    // Start stepping only once the reader runs, so the two really overlap.
    while (reads.load() == 0) std::this_thread::yield();
    for (int i = 1; i <= 200; ++i) {
      sim->SetVelocity(0.3, i % 2 ? 0.2 : -0.2);
      sim->AdvanceTo(kStart + FromMilliseconds(10.0 * i));
    }
    done = true;
  });
  do {
    const LaserScan scan = sim->ScanAt(kStart);
    EXPECT_EQ(scan.ranges_m.size(), 361u);
    const StereoImages images = sim->StereoAt(kStart, false);
    EXPECT_FALSE(images.left.empty());
    ++reads;
  } while (!done);
  stepper.join();
  const RobotState s = sim->StateAt(kStart + FromSeconds(2));
  EXPECT_GT(s.world_from_base.x_m, 0.3);
}

}  // namespace
}  // namespace mostar::sim
