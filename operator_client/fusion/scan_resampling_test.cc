#include "operator_client/fusion/scan_resampling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace mostar::fusion {
namespace {

const Time kT0 = FromUnixNanos(1'700'000'000'000'000'000);
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// 181 beams over 180 deg, every beam measured at the stamp.
LaserScan HalfCircleScan() {
  LaserScan scan;
  scan.stamp = kT0;
  scan.sequence = 42;
  scan.angle_min_rad = static_cast<float>(-M_PI / 2);
  scan.angle_increment_rad = static_cast<float>(M_PI / 180);
  scan.range_max_m = 8.f;
  scan.ranges_m.assign(181, 3.f);
  return scan;
}

// `scan` seen after the robot turned by `turn_rad` (counter-clockwise) on the spot: what
// MoveScanToImageTime gives for it.
MovedScan Turned(const LaserScan& scan, double turn_rad) {
  MovedScan moved;
  moved.moved = true;
  moved.image_minus_scan = std::chrono::milliseconds(40);
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const double a = scan.AngleOf(i) - turn_rad;
    const float r = scan.ranges_m[i];
    moved.azimuths_rad.push_back(static_cast<float>(a));
    moved.points.push_back(
        LaserScan::IsValidRange(r)
            ? PlanarPoint{static_cast<float>(r * std::cos(a)), static_cast<float>(r * std::sin(a))}
            : PlanarPoint{});
  }
  return moved;
}

TEST(ScanResamplingTest, ATurnByWholeBeamsShiftsEveryValueKindsIncluded) {
  LaserScan scan = HalfCircleScan();
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    scan.ranges_m[i] = 1.f + 0.01f * static_cast<float>(i % 7);
  }
  scan.ranges_m[50] = kNaN;  // unknown
  scan.ranges_m[90] = kInf;  // free
  scan.ranges_m[91] = kInf;
  scan.intensities.assign(scan.ranges_m.size(), 0.f);
  for (size_t i = 0; i < scan.intensities.size(); ++i) scan.intensities[i] = static_cast<float>(i);
  const double increment = scan.angle_increment_rad;
  LaserScan out;
  ASSERT_TRUE(ResampleAtImageTime(scan, Turned(scan, 3 * increment), &out));
  // Turned left by 3 beams: what beam j + 3 measured now lies ahead of beam j.
  for (size_t j = 0; j + 3 < scan.ranges_m.size(); ++j) {
    const float expected = scan.ranges_m[j + 3];
    if (std::isnan(expected)) {
      EXPECT_TRUE(std::isnan(out.ranges_m[j])) << j;
    } else if (std::isinf(expected)) {
      EXPECT_EQ(out.ranges_m[j], kInf) << j;
    } else {
      EXPECT_NEAR(out.ranges_m[j], expected, 1e-4) << j;
    }
    EXPECT_EQ(out.intensities[j], scan.intensities[j + 3]) << j;
  }
  // Nothing was measured beyond the old field of view's left end.
  for (size_t j = scan.ranges_m.size() - 3; j < scan.ranges_m.size(); ++j) {
    EXPECT_TRUE(std::isnan(out.ranges_m[j])) << j;
  }
  EXPECT_EQ(out.stamp, kT0 + std::chrono::milliseconds(40));
  EXPECT_EQ(out.time_increment_s, 0.f);
  EXPECT_EQ(out.sequence, 42u);
  EXPECT_EQ(out.angle_min_rad, scan.angle_min_rad);
  EXPECT_EQ(out.ranges_m.size(), scan.ranges_m.size());
}

TEST(ScanResamplingTest, AWallIsResampledWhereTheNewRaysMeetIt) {
  // A wall at x = 2 m ahead of the scan's origin; the robot then drives 0.1 m forward, 0.05 m to
  // the left and turns 0.4 beams left (a pose between beams).
  LaserScan scan = HalfCircleScan();
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const double c = std::cos(scan.AngleOf(i));
    scan.ranges_m[i] = c > 0.25 ? static_cast<float>(2.0 / c) : kInf;
  }
  const double dx = 0.1, dy = 0.05, dth = 0.4 * scan.angle_increment_rad;
  MovedScan moved;
  moved.moved = true;
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const double a = scan.AngleOf(i);
    const float r = scan.ranges_m[i];
    // image_from_scan = inverse(pose): rotate by -dth after subtracting the translation.
    const double x = LaserScan::IsValidRange(r) ? r * std::cos(a) - dx : 0;
    const double y = LaserScan::IsValidRange(r) ? r * std::sin(a) - dy : 0;
    moved.points.push_back(
        LaserScan::IsValidRange(r)
            ? PlanarPoint{static_cast<float>(std::cos(dth) * x + std::sin(dth) * y),
                          static_cast<float>(-std::sin(dth) * x + std::cos(dth) * y)}
            : PlanarPoint{});
    moved.azimuths_rad.push_back(static_cast<float>(a - dth));
  }
  LaserScan out;
  ASSERT_TRUE(ResampleAtImageTime(scan, moved, &out));
  int checked = 0;
  for (size_t j = 0; j < out.ranges_m.size(); ++j) {
    // The new ray from (dx, dy) at heading dth + a_j meets x = 2 at t = (2 - dx) / cos.
    const double c = std::cos(dth + out.AngleOf(j));
    if (c < 0.3) continue;  // near the wall's ends in the scan (+Inf there)
    EXPECT_NEAR(out.ranges_m[j], (2.0 - dx) / c, 2e-4) << j;
    ++checked;
  }
  EXPECT_GT(checked, 130);
}

TEST(ScanResamplingTest, AnOcclusionEdgeIsNeverBridged) {
  // A box 1 m away over beams 80-100 in front of a wall 3 m away; turned by half a beam.
  LaserScan scan = HalfCircleScan();
  for (size_t i = 80; i <= 100; ++i) scan.ranges_m[i] = 1.f;
  LaserScan out;
  ASSERT_TRUE(ResampleAtImageTime(scan, Turned(scan, 0.5 * scan.angle_increment_rad), &out));
  int near = 0;
  for (size_t j = 0; j + 1 < out.ranges_m.size(); ++j) {
    const float r = out.ranges_m[j];
    const bool on_box = std::abs(r - 1.f) < 0.01f;
    const bool on_wall = std::abs(r - 3.f) < 0.01f;
    EXPECT_TRUE(on_box || on_wall) << j << ": " << r;
    near += on_box;
  }
  // Beams 80-100 land on targets 79.5-99.5: targets 80-99 lie on the box, 79 and 100 are as
  // near to a box beam as to a wall beam (the nearer point wins such ties).
  EXPECT_GE(near, 20);
  EXPECT_LE(near, 22);
}

TEST(ScanResamplingTest, RefusesWhatItCannotResample) {
  const LaserScan scan = HalfCircleScan();
  LaserScan out;
  MovedScan not_moved = Turned(scan, 0.1);
  not_moved.moved = false;
  EXPECT_FALSE(ResampleAtImageTime(scan, not_moved, &out));
  EXPECT_EQ(out.stamp, scan.stamp);
  EXPECT_EQ(out.ranges_m, scan.ranges_m);
  MovedScan short_one = Turned(scan, 0.1);
  short_one.azimuths_rad.pop_back();
  EXPECT_FALSE(ResampleAtImageTime(scan, short_one, &out));
  LaserScan no_increment = scan;
  no_increment.angle_increment_rad = 0.f;
  EXPECT_FALSE(ResampleAtImageTime(no_increment, Turned(scan, 0.1), &out));
  EXPECT_EQ(out.angle_increment_rad, 0.f);
  LaserScan tiny_increment = scan;
  tiny_increment.angle_increment_rad = 1e-30f;
  EXPECT_FALSE(ResampleAtImageTime(tiny_increment, Turned(scan, 0.1), &out));
  LaserScan no_start = scan;
  no_start.angle_min_rad = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(ResampleAtImageTime(no_start, Turned(scan, 0.1), &out));
}

TEST(ScanResamplingTest, NonFiniteMovedPointsPlaceNothingAndTheRestIsResampled) {
  const LaserScan scan = HalfCircleScan();  // 3 m all round
  MovedScan moved = Turned(scan, 0.0);
  for (size_t i = 60; i < 70; ++i) {  // odometry gave NaN for these beams
    moved.points[i] = {kNaN, kNaN};
    moved.azimuths_rad[i] = kNaN;
  }
  LaserScan out;
  ASSERT_TRUE(ResampleAtImageTime(scan, moved, &out));
  for (size_t j = 0; j < out.ranges_m.size(); ++j) {
    if (j >= 60 && j < 70) {
      EXPECT_TRUE(std::isnan(out.ranges_m[j])) << j;
    } else {
      EXPECT_NEAR(out.ranges_m[j], 3.f, 1e-4) << j;
    }
  }
}

TEST(ScanResamplingTest, MovingToTheImageTimeAndResamplingKeepsAStillScene) {
  // Through MoveScanToImageTime: the robot turned at 0.5 rad/s for 50 ms between the scan and
  // the image; the odometry covers it. A wall all round at 3 m (a circle about the start)
  // resamples to 3 m everywhere except where no beam looked.
  OdometryHistory history(64);
  for (int k = -5; k <= 10; ++k) {
    Odometry o;
    o.stamp = kT0 + std::chrono::milliseconds(20 * k);
    o.pose = Pose2D{0, 0, 0.5 * 0.02 * k};
    o.angular_radps = 0.5;
    history.Add(o);
  }
  LaserScan scan = HalfCircleScan();
  scan.ranges_m[30] = kNaN;
  MovedScan moved;
  MotionCompensationOptions options;
  options.smoothing_window = Duration(0);
  MoveScanToImageTime(scan, kT0 + std::chrono::milliseconds(50), history, options, &moved);
  ASSERT_TRUE(moved.moved) << moved.reason;
  LaserScan out;
  ASSERT_TRUE(ResampleAtImageTime(scan, moved, &out));
  // 0.025 rad = 1.43 beams: the NaN beam 30 lands 0.43 beams from target 29; no beam looked
  // along target 180 (the nearest, beam 180, is 1.43 beams away).
  int unknown = 0;
  for (size_t j = 0; j < out.ranges_m.size(); ++j) {
    if (std::isnan(out.ranges_m[j])) {
      ++unknown;
      EXPECT_TRUE(j == 29 || j == 180) << j;
      continue;
    }
    EXPECT_NEAR(out.ranges_m[j], 3.f, 1e-3) << j;
  }
  EXPECT_EQ(unknown, 2);
}

}  // namespace
}  // namespace mostar::fusion
