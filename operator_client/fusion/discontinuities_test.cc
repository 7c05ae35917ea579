#include "operator_client/fusion/discontinuities.h"

#include <gtest/gtest.h>

#include <cmath>

#include "operator_client/fusion/test_scenes.h"

namespace mostar::fusion {
namespace {

using testing::BoxBeforeWall;
using testing::Legs;
using testing::MakeScan;
using testing::Room;

std::vector<size_t> DiscontinuityWalls(const ScanSegmentation& seg) {
  std::vector<size_t> walls;
  for (size_t i = 0; i < seg.wall_discontinuity.size(); ++i) {
    if (seg.wall_discontinuity[i] != 0) walls.push_back(i);
  }
  return walls;
}

TEST(WallSlopeTest, FollowsTheThesisFormula) {
  EXPECT_FLOAT_EQ(WallSlope(2.f, 2.f), 0.f);
  EXPECT_FLOAT_EQ(WallSlope(3.f, 1.f), 0.5f);
  EXPECT_FLOAT_EQ(WallSlope(1.f, 3.f), -0.5f);
  EXPECT_NEAR(WallSlope(1e-6f, 100.f), -1.f, 1e-6f);
}

TEST(SegmentScanTest, SmoothRoomHasNoDiscontinuities) {
  ScanSegmentation seg;
  SegmentScan(MakeScan(Room(), 181), SegmentationOptions{}, &seg);
  EXPECT_EQ(seg.invalid_beams, 0u);
  // Corners may cut the room into up to three walls, but no point is isolated.
  for (uint8_t outlier : seg.potential_outlier) EXPECT_EQ(outlier, 0);
  EXPECT_LE(seg.clusters.size(), 3u);
}

TEST(SegmentScanTest, BoxInFrontOfAWallIsCutAtBothSides) {
  const LaserScan scan = MakeScan(BoxBeforeWall(), 181);
  ScanSegmentation seg;
  SegmentScan(scan, SegmentationOptions{}, &seg);
  const std::vector<size_t> walls = DiscontinuityWalls(seg);
  ASSERT_EQ(walls.size(), 2u);
  for (size_t wall : walls) {
    // Each discontinuity joins a box point (~1.5 m) and a wall point (~3 m).
    const float a = scan.ranges_m[wall];
    const float b = scan.ranges_m[wall + 1];
    EXPECT_LT(std::min(a, b), 1.6f);
    EXPECT_GT(std::max(a, b), 2.9f);
    EXPECT_TRUE(seg.AtDiscontinuity(wall));
    EXPECT_TRUE(seg.AtDiscontinuity(wall + 1));
  }
  // Three objects: back wall right of the box, the box, back wall left of the box.
  ASSERT_EQ(seg.clusters.size(), 3u);
  EXPECT_NEAR(seg.clusters[1].nearest_range_m, 1.5f, 1e-4f);
  EXPECT_EQ(seg.clusters[1].first_beam, walls[0] + 1);
  EXPECT_EQ(seg.clusters[1].last_beam, walls[1]);
  for (uint8_t outlier : seg.potential_outlier) EXPECT_EQ(outlier, 0);
}

TEST(SegmentScanTest, IsolatedOutlierIsAPotentialOutlier) {
  LaserScan scan = MakeScan(Room(), 181);
  scan.ranges_m[100] = 0.8f;
  ScanSegmentation seg;
  SegmentScan(scan, SegmentationOptions{}, &seg);
  EXPECT_EQ(DiscontinuityWalls(seg), (std::vector<size_t>{99, 100}));
  for (size_t i = 0; i < seg.potential_outlier.size(); ++i) {
    EXPECT_EQ(seg.potential_outlier[i] != 0, i == 100) << i;
  }
}

TEST(SegmentScanTest, LongerRunsAreOutliersOnlyWhenAllowed) {
  LaserScan scan = MakeScan(Room(), 181);
  for (size_t i : {100u, 101u, 102u}) scan.ranges_m[i] = 0.8f;
  ScanSegmentation seg;
  SegmentScan(scan, SegmentationOptions{}, &seg);
  EXPECT_EQ(DiscontinuityWalls(seg), (std::vector<size_t>{99, 102}));
  for (size_t i : {100u, 101u, 102u}) EXPECT_EQ(seg.potential_outlier[i], 0) << i;
  SegmentationOptions three;
  three.max_outlier_run_points = 3;
  SegmentScan(scan, three, &seg);
  for (size_t i : {100u, 101u, 102u}) EXPECT_EQ(seg.potential_outlier[i], 1) << i;
  EXPECT_EQ(seg.potential_outlier[99], 0);
  EXPECT_EQ(seg.potential_outlier[103], 0);
  SegmentationOptions none;
  none.max_outlier_run_points = 0;
  scan.ranges_m[101] = scan.ranges_m[100] = scan.ranges_m[102] = 3.f;
  scan.ranges_m[50] = 0.8f;
  SegmentScan(scan, none, &seg);
  EXPECT_EQ(seg.potential_outlier[50], 0);
}

TEST(SegmentScanTest, TwoPointBlipIsSplitIntoTwoPotentialOutliers) {
  // The thesis rule compares each wall with its neighbours only: the flat wall of a two-point
  // blip differs from both jumps around it, so all three walls are discontinuities.
  LaserScan scan = MakeScan(Room(), 181);
  scan.ranges_m[100] = 0.8f;
  scan.ranges_m[101] = 0.8f;
  ScanSegmentation seg;
  SegmentScan(scan, SegmentationOptions{}, &seg);
  EXPECT_EQ(DiscontinuityWalls(seg), (std::vector<size_t>{99, 100, 101}));
  EXPECT_EQ(seg.potential_outlier[100], 1);
  EXPECT_EQ(seg.potential_outlier[101], 1);
}

TEST(SegmentScanTest, LegsAreTwoNarrowClustersNotOutliers) {
  const LaserScan scan = MakeScan(Legs(), 361);
  ScanSegmentation seg;
  SegmentScan(scan, SegmentationOptions{}, &seg);
  std::vector<Cluster> legs;
  for (const Cluster& c : seg.clusters) {
    if (c.nearest_range_m < 2.5f) legs.push_back(c);
  }
  ASSERT_EQ(legs.size(), 2u);
  for (const Cluster& leg : legs) {
    EXPECT_NEAR(leg.nearest_range_m, std::hypot(2.0, 0.15) - 0.06, 0.01);
    EXPECT_GE(leg.size(), 3u);
    EXPECT_LE(leg.size(), 9u);
    for (size_t b = leg.first_beam; b <= leg.last_beam; ++b) {
      EXPECT_EQ(seg.potential_outlier[b], 0) << b;
    }
  }
  EXPECT_GT(legs[1].first_beam, legs[0].last_beam + 5);  // wall seen between the legs
}

TEST(SegmentScanTest, InvalidBeamsBreakWallsAndAreCounted) {
  LaserScan scan = MakeScan(Room(), 181);
  scan.ranges_m[50] = NAN;
  scan.ranges_m[51] = INFINITY;
  scan.ranges_m[120] = -1.f;
  scan.ranges_m[121] = 20.f;  // beyond range_max_m
  ScanSegmentation seg;
  SegmentScan(scan, SegmentationOptions{}, &seg);
  EXPECT_EQ(seg.invalid_beams, 4u);
  for (size_t beam : {50u, 51u, 120u, 121u}) {
    EXPECT_EQ(seg.valid[beam], 0);
    EXPECT_EQ(seg.wall_exists[beam - 1], 0);
    EXPECT_EQ(seg.wall_exists[beam], 0);
    EXPECT_TRUE(std::isnan(seg.wall_slope[beam]));
    EXPECT_EQ(seg.wall_discontinuity[beam], 0);
  }
  for (const Cluster& c : seg.clusters) {
    for (size_t b = c.first_beam; b <= c.last_beam; ++b) EXPECT_EQ(seg.valid[b], 1);
  }
}

TEST(SegmentScanTest, DegenerateScansDoNotCrash) {
  ScanSegmentation seg;
  LaserScan empty;
  SegmentScan(empty, SegmentationOptions{}, &seg);
  EXPECT_EQ(seg.beam_count(), 0u);
  EXPECT_TRUE(seg.clusters.empty());

  LaserScan one;
  one.ranges_m = {1.f};
  SegmentScan(one, SegmentationOptions{}, &seg);
  EXPECT_EQ(seg.clusters.size(), 1u);
  EXPECT_TRUE(seg.wall_exists.empty());

  LaserScan bad_angles = MakeScan(Room(), 181);
  bad_angles.angle_increment_rad = NAN;
  SegmentScan(bad_angles, SegmentationOptions{}, &seg);
  EXPECT_EQ(seg.invalid_beams, 181u);
  EXPECT_TRUE(seg.clusters.empty());
}

TEST(SegmentationOptionsTest, IsValidNamesTheViolatedConstraint) {
  SegmentationOptions options;
  std::string error;
  EXPECT_TRUE(options.IsValid(&error));
  options.slope_threshold = 0.f;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("slope_threshold"), std::string::npos);
  options = SegmentationOptions{};
  options.max_outlier_run_points = -1;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("max_outlier_run_points"), std::string::npos);
}

}  // namespace
}  // namespace mostar::fusion
