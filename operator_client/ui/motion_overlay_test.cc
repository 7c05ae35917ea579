#include "operator_client/ui/motion_overlay.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mostar::ui {
namespace {

const Time kT0 = FromUnixNanos(1'700'000'000'000'000'000);

LaserScan Scan() {
  LaserScan scan;
  scan.stamp = kT0;
  scan.angle_min_rad = -0.5f;
  scan.angle_increment_rad = 0.01f;
  scan.ranges_m.assign(101, 2.0f);
  return scan;
}

// The scan moved 10 cm nearer, as a robot driving ahead would see it later.
fusion::MovedScan Nearer(const LaserScan& scan) {
  fusion::MovedScan moved;
  moved.moved = true;
  moved.image_minus_scan = std::chrono::milliseconds(40);
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const float a = scan.AngleOf(i);
    moved.points.push_back({2.0f * std::cos(a) - 0.1f, 2.0f * std::sin(a)});
    moved.azimuths_rad.push_back(a);
  }
  return moved;
}

TEST(MotionOverlayTest, EdgeProcessingGetsTheScanAtTheImagesTimeWhenItCanBeMoved) {
  const LaserScan scan = Scan();
  LaserScan placed;
  const vision::ScanPlacement off = PlaceScanForVision(scan, nullptr, &placed);
  EXPECT_FALSE(off.at_image_time);
  EXPECT_TRUE(off.reason.empty());  // compensation off: nothing to say
  EXPECT_EQ(off.measured_stamp, kT0);
  EXPECT_EQ(placed.ranges_m, scan.ranges_m);

  const fusion::MovedScan moved = Nearer(scan);
  const vision::ScanPlacement on = PlaceScanForVision(scan, &moved, &placed);
  EXPECT_TRUE(on.at_image_time);
  EXPECT_FALSE(on.extrapolated);
  EXPECT_EQ(on.measured_stamp, kT0);
  EXPECT_EQ(placed.stamp, kT0 + std::chrono::milliseconds(40));
  // 10 cm nearer straight ahead (beam 50 looks along x), on the same beam grid.
  ASSERT_EQ(placed.ranges_m.size(), scan.ranges_m.size());
  EXPECT_NEAR(placed.ranges_m[50], 1.9f, 1e-3);
  EXPECT_EQ(placed.angle_min_rad, scan.angle_min_rad);

  fusion::MovedScan not_moved = Nearer(scan);
  not_moved.moved = false;
  not_moved.reason = "no odometry";
  const vision::ScanPlacement refused = PlaceScanForVision(scan, &not_moved, &placed);
  EXPECT_FALSE(refused.at_image_time);
  EXPECT_EQ(refused.reason, "no odometry");
  EXPECT_EQ(placed.ranges_m, scan.ranges_m);
}

TEST(MotionOverlayTest, APlacedScanIsDrawnWhereItIsAndNeverMovedAgain) {
  const fusion::ArFeatureBuilder builder{fusion::ArFeatureOptions{}};
  const LaserScan scan = Scan();  // say, a result's corrected scan at the image's time
  fusion::ArFeatures plain;
  builder.Build(scan, &plain);
  vision::ScanPlacement placement;
  placement.at_image_time = true;
  placement.measured_stamp = kT0 - std::chrono::milliseconds(30);
  fusion::ArFeatures features;
  MotionOverlayStatus status = BuildPlacedOverlayFeatures(builder, scan, placement, kT0, true,
                                                          MotionOverlayOptions{}, &features);
  EXPECT_TRUE(status.moved);
  EXPECT_FALSE(status.faded);
  EXPECT_DOUBLE_EQ(status.scan_age_ms, 30.0);
  EXPECT_EQ(features.laser_points.positions, plain.laser_points.positions);
  EXPECT_EQ(features.laser_points.colors, plain.laser_points.colors);

  placement.at_image_time = false;
  placement.reason = "no odometry at the image time";
  status = BuildPlacedOverlayFeatures(builder, scan, placement, kT0, true, MotionOverlayOptions{},
                                      &features);
  EXPECT_FALSE(status.moved);
  EXPECT_TRUE(status.faded);
  EXPECT_EQ(status.reason, "no odometry at the image time");
  EXPECT_EQ(features.laser_points.positions, plain.laser_points.positions);
  EXPECT_LT(features.laser_points.colors[3], plain.laser_points.colors[3]);

  // Compensation off: the thesis' drawing, neither moved nor faded.
  status = BuildPlacedOverlayFeatures(builder, scan, placement, kT0, false, MotionOverlayOptions{},
                                      &features);
  EXPECT_FALSE(status.moved);
  EXPECT_FALSE(status.faded);
  EXPECT_EQ(features.laser_points.colors, plain.laser_points.colors);
}

TEST(MotionOverlayTest, AMovedScanIsDrawnWhereItWasMovedNotFaded) {
  const fusion::ArFeatureBuilder builder{fusion::ArFeatureOptions{}};
  const LaserScan scan = Scan();
  fusion::ArFeatures plain;
  builder.Build(scan, &plain);
  const fusion::MovedScan moved = Nearer(scan);
  fusion::ArFeatures features;
  const MotionOverlayStatus status =
      BuildOverlayFeatures(builder, scan, &moved, MotionOverlayOptions{}, &features);
  EXPECT_TRUE(status.moved);
  EXPECT_FALSE(status.faded);
  EXPECT_DOUBLE_EQ(status.scan_age_ms, 40.0);
  EXPECT_TRUE(MotionOverlayNote(status).empty());
  ASSERT_EQ(features.laser_points.positions.size(), plain.laser_points.positions.size());
  EXPECT_NEAR(features.laser_points.positions[0], plain.laser_points.positions[0] - 0.1f, 1e-5);
  EXPECT_EQ(features.laser_points.colors, plain.laser_points.colors);
}

TEST(MotionOverlayTest, AScanNotCoveredByOdometryIsDrawnAsMeasuredAndFaded) {
  const fusion::ArFeatureBuilder builder{fusion::ArFeatureOptions{}};
  const LaserScan scan = Scan();
  fusion::ArFeatures plain;
  builder.Build(scan, &plain);
  fusion::MovedScan moved = Nearer(scan);
  moved.moved = false;
  moved.reason = "no odometry at the image time";
  MotionOverlayOptions options;
  options.faded_alpha_scale = 0.25f;
  fusion::ArFeatures features;
  const MotionOverlayStatus status =
      BuildOverlayFeatures(builder, scan, &moved, options, &features);
  EXPECT_FALSE(status.moved);
  EXPECT_TRUE(status.faded);
  EXPECT_EQ(MotionOverlayNote(status),
            "overlay faded: no odometry at the image time (scan 40 ms before the image)");
  EXPECT_EQ(features.walls.positions, plain.walls.positions);
  ASSERT_FALSE(features.walls.empty());
  EXPECT_FLOAT_EQ(features.walls.colors[3], 0.25f * plain.walls.colors[3]);
  EXPECT_FLOAT_EQ(features.laser_points.colors[3], 0.25f * plain.laser_points.colors[3]);
  EXPECT_FLOAT_EQ(features.rays.colors[3], 0.25f * plain.rays.colors[3]);
  EXPECT_EQ(features.circles.colors, plain.circles.colors) << "circles go with the robot";
}

TEST(MotionOverlayTest, WithoutCompensationTheScanIsDrawnAsMeasured) {
  const fusion::ArFeatureBuilder builder{fusion::ArFeatureOptions{}};
  const LaserScan scan = Scan();
  fusion::ArFeatures plain;
  builder.Build(scan, &plain);
  fusion::ArFeatures features;
  const MotionOverlayStatus status =
      BuildOverlayFeatures(builder, scan, nullptr, MotionOverlayOptions{}, &features);
  EXPECT_FALSE(status.moved);
  EXPECT_FALSE(status.faded);
  EXPECT_EQ(features.walls.colors, plain.walls.colors);
  EXPECT_EQ(features.walls.positions, plain.walls.positions);
}

TEST(MotionOverlayTest, OptionsAreChecked) {
  MotionOverlayOptions options;
  std::string error;
  EXPECT_TRUE(options.IsValid(&error)) << error;
  options.faded_alpha_scale = 0.f;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_EQ(error, "faded_alpha_scale must be in (0, 1]");
  options.faded_alpha_scale = 0.5f;
  options.compensation.max_odometry_gap = Duration::zero();
  EXPECT_FALSE(options.IsValid(&error));
}

}  // namespace
}  // namespace mostar::ui
