// Edge processing while the robot turns (issue 36, "vision on the image's time"): the laser
// double-check decides per beam whether the nearest edge agrees with the laser (the overlay is
// corrected onto it) or lies much nearer (a possible-obstacle dot). Those decisions must not
// depend on the robot turning between the scan and the image.
//
// The simulated robot turns on the spot at 0.5 rad/s in the open room and in the corridor. For
// each stereo pair the
// same images are processed three times:
//  - still: with the scan measured at the image's own time (what a robot standing at that pose
//    gives: the reference);
//  - moved: with a scan measured 15-50 ms earlier, moved to the image's time and resampled as the
//    console does it (fusion::MoveScanToImageTime, ui::PlaceScanForVision), odometry at 50 Hz;
//  - unmoved: with that earlier scan as measured (what the console did before: the control that
//    shows the test can tell the two apart).
// The simulator measures every beam of a scan at its stamp's pose, so the scans' beam timing is
// set to 0. Range noise is off, so that only the motion differs between the runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "common/stats/percentile.h"
#include "operator_client/fusion/motion_compensation.h"
#include "operator_client/ui/motion_overlay.h"
#include "operator_client/vision/vision_pipeline.h"
#include "robot_server/sim/sim_world.h"
#include "tests/vision/sim_calibration.h"

namespace mostar::vision {
namespace {

const Time kStart = FromUnixNanos(1'700'000'000'000'000'000);
constexpr double kTurnRadps = 0.5;

struct Agreement {
  int reference = 0;  // beams with the relation in the still run
  int other = 0;      // in the compared run
  int both = 0;       // on the same beam in both
  double Jaccard() const {
    const int either = reference + other - both;
    return either == 0 ? 1.0 : static_cast<double>(both) / either;
  }
};

struct Comparison {
  Agreement agrees;
  Agreement dots;
  // Per beam valid in both scans: the laser range the run decided with minus the still one's.
  // (The NEPs themselves are the same in every run: same images, same virtual rays.)
  std::vector<double> range_gap_m;
};

void Compare(const VisionResult& still, const VisionResult& other, Comparison* out) {
  ASSERT_EQ(still.classification.beams.size(), other.classification.beams.size());
  for (size_t i = 0; i < still.classification.beams.size(); ++i) {
    const NepRelation a = still.classification.beams[i].relation;
    const NepRelation b = other.classification.beams[i].relation;
    for (const auto& [relation, agreement] : {std::pair{NepRelation::kAgrees, &out->agrees},
                                              std::pair{NepRelation::kNearer, &out->dots}}) {
      agreement->reference += a == relation;
      agreement->other += b == relation;
      agreement->both += a == relation && b == relation;
    }
    const float ra = still.scan.ranges_m[i], rb = other.scan.ranges_m[i];
    if (LaserScan::IsValidRange(ra) && LaserScan::IsValidRange(rb)) {
      out->range_gap_m.push_back(std::abs(ra - rb));
    }
  }
}

class VisionMotionTest : public ::testing::TestWithParam<const char*> {};

TEST_P(VisionMotionTest, DecisionsWhileTurningMatchThoseOfAStillRobot) {
  sim::proto::Scene scene;
  std::string error;
  ASSERT_TRUE(LoadSimScene(GetParam(), &scene, &error)) << error;
  sim::proto::SimConfig config;
  config.mutable_laser()->set_noise_sigma_m(0.0);
  config.mutable_drive()->set_step_s(0.0001);  // poses within 0.1 ms of the time asked
  auto world = sim::SimWorld::Create(scene, config, kStart, &error);
  ASSERT_NE(world, nullptr) << error;
  const double laser_height_m = world->laser_params().height_m;
  const auto left = SimCameraModel(world->calibration(), Eye::kLeft, laser_height_m);
  const auto right = SimCameraModel(world->calibration(), Eye::kRight, laser_height_m);
  const VisionOptions options;
  VisionPipeline still_pipeline{options};
  VisionPipeline moved_pipeline{options};
  VisionPipeline unmoved_pipeline{options};
  fusion::OdometryHistory odometry(4096);
  fusion::MotionCompensationOptions compensation;

  world->SetVelocity(0.0, kTurnRadps);
  const Duration gaps[] = {std::chrono::milliseconds(15), std::chrono::milliseconds(30),
                           std::chrono::milliseconds(50)};
  constexpr Duration kOdometryPeriod = std::chrono::milliseconds(20);
  Time next_odometry = kStart;
  const auto odometry_until = [&](Time t) {  // the world only advances forward
    for (; next_odometry <= t; next_odometry += kOdometryPeriod) {
      const sim::RobotState state = world->StateAt(next_odometry);
      Odometry o;
      o.stamp = next_odometry;
      o.pose = state.world_from_base;
      o.linear_mps = state.linear_mps;
      o.angular_radps = state.angular_radps;
      odometry.Add(o);
    }
  };
  Comparison moved, unmoved;
  int frames = 0, placed = 0;
  for (int k = 0; k < 24; ++k) {
    // Past the acceleration; frames 0.25 s (0.125 rad) apart sweep the room.
    const Time image_time = kStart + std::chrono::seconds(1) + std::chrono::milliseconds(250) * k;
    const Time scan_time = image_time - gaps[k % 3];
    odometry_until(scan_time);
    LaserScan earlier = world->ScanAt(scan_time);
    earlier.time_increment_s = 0.f;
    // The odometry up to the image, and one sample past it, as the console has when the pair
    // arrives (odometry comes at 50 Hz, the pair after encoding and transport).
    odometry_until(image_time);
    const sim::StereoImages images = world->StereoAt(image_time, /*with_truth=*/false);
    LaserScan now = world->ScanAt(image_time);
    now.time_increment_s = 0.f;
    odometry_until(image_time + kOdometryPeriod);

    VisionInput input;
    input.stamp = image_time;
    input.sequence = static_cast<uint64_t>(k + 1);
    input.left = images.left;
    input.right = images.right;
    input.left_camera = left;
    input.right_camera = right;
    input.scan = now;
    const VisionResult still = still_pipeline.Process(input);
    ASSERT_TRUE(still.ok) << still.error;

    fusion::MovedScan motion;
    fusion::MoveScanToImageTime(earlier, image_time, odometry, compensation, &motion);
    input.placement = ui::PlaceScanForVision(earlier, &motion, &input.scan);
    placed += input.placement.at_image_time;
    EXPECT_EQ(input.placement.measured_stamp, scan_time);
    const VisionResult at_image = moved_pipeline.Process(input);
    ASSERT_TRUE(at_image.ok) << at_image.error;
    EXPECT_TRUE(at_image.placement.at_image_time);

    input.scan = earlier;
    input.placement = {};
    const VisionResult as_measured = unmoved_pipeline.Process(input);
    ASSERT_TRUE(as_measured.ok) << as_measured.error;

    Compare(still, at_image, &moved);
    Compare(still, as_measured, &unmoved);
    ++frames;
  }
  EXPECT_EQ(placed, frames);
  const auto p95 = [](const std::vector<double>& v) { return Percentile(v, 0.95).value_or(0.0); };
  std::printf(
      "%s: %d pairs, turning %.1f rad/s, scan 15-50 ms before the image\n"
      "  agree: still %d beams; moved %d (Jaccard %.3f), unmoved %d (Jaccard %.3f)\n"
      "  dots:  still %d; moved %d (%d not in still), unmoved %d (%d not in still)\n"
      "  laser range against the still scan's, p95: moved %.1f mm, unmoved %.1f mm\n",
      GetParam(), frames, kTurnRadps, moved.agrees.reference, moved.agrees.other,
      moved.agrees.Jaccard(), unmoved.agrees.other, unmoved.agrees.Jaccard(), moved.dots.reference,
      moved.dots.other, moved.dots.other - moved.dots.both, unmoved.dots.other,
      unmoved.dots.other - unmoved.dots.both, 1e3 * p95(moved.range_gap_m),
      1e3 * p95(unmoved.range_gap_m));
  // Enough evidence for the comparison to mean something.
  ASSERT_GT(moved.agrees.reference, 1000);
  // Moved to the image's time, the decisions are those of the still robot, up to the
  // resampling between beams: the laser ranges match within millimetres.
  EXPECT_GE(moved.agrees.Jaccard(), 0.98);
  EXPECT_GE(moved.dots.Jaccard(), 0.98);
  EXPECT_LE(moved.dots.other - moved.dots.both, std::max(2, moved.dots.reference / 50));
  EXPECT_LE(p95(moved.range_gap_m), 0.005);
  // The control: the earlier scan as measured decides differently on many more beams.
  EXPECT_LT(unmoved.agrees.Jaccard(), moved.agrees.Jaccard() - 0.1);
  EXPECT_GT(p95(unmoved.range_gap_m), 10 * p95(moved.range_gap_m));
}

// Open room: low obstacles on a plain floor; corridor: walls close by, doors and baseboards.
INSTANTIATE_TEST_SUITE_P(Scenes, VisionMotionTest, ::testing::Values("open_room", "corridor"));

}  // namespace
}  // namespace mostar::vision
