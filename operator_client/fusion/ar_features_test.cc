#include "operator_client/fusion/ar_features.h"

#include <gtest/gtest.h>

#include <cmath>

#include "operator_client/fusion/test_scenes.h"

namespace mostar::fusion {
namespace {

using testing::BoxBeforeWall;
using testing::Legs;
using testing::MakeScan;
using testing::Room;

bool AllFinite(const VertexArray& array) {
  for (float v : array.positions) {
    if (!std::isfinite(v)) return false;
  }
  for (float v : array.colors) {
    if (!std::isfinite(v)) return false;
  }
  return array.colors.size() == array.vertex_count() * 4 &&
         array.positions.size() == array.vertex_count() * 3;
}

// True when the array holds a line from the robot base to the floor point under beam `i`.
bool HasRayTo(const ArFeatures& f, size_t beam) {
  const ScanPointLabel& p = f.points[beam];
  const std::vector<float>& pos = f.rays.positions;
  for (size_t v = 1; v < f.rays.vertex_count(); v += 2) {
    if (pos[3 * v] == p.x_m && pos[3 * v + 1] == p.y_m) return true;
  }
  return false;
}

TEST(ArFeatureBuilderTest, PointsAreInTheLaserFrameWithDistanceColours) {
  const ArFeatureBuilder builder(ArFeatureOptions{});
  const LaserScan scan = MakeScan(Room(), 181);
  const ArFeatures f = builder.Build(scan);
  ASSERT_EQ(f.points.size(), 181u);
  const ScanPointLabel& ahead = f.points[90];
  EXPECT_NEAR(ahead.x_m, 3.f, 1e-5f);
  EXPECT_NEAR(ahead.y_m, 0.f, 1e-5f);
  EXPECT_FLOAT_EQ(ahead.color.g, 1.f);         // 3 m = max_distance_m: green
  const ScanPointLabel& left = f.points[180];  // +90 degrees: the left wall at 1.5 m
  EXPECT_NEAR(left.x_m, 0.f, 1e-5f);
  EXPECT_NEAR(left.y_m, 1.5f, 1e-5f);
  EXPECT_EQ(f.laser_points.vertex_count(), 181u);
  EXPECT_EQ(f.laser_points.positions[2], 0.f);  // scan plane
}

TEST(ArFeatureBuilderTest, WallsStandOnTheFloorUpToTheirHeight) {
  ArFeatureOptions options;
  options.laser_height_m = 0.4f;
  options.wall_height_m = 0.6f;
  const ArFeatures f = ArFeatureBuilder(options).Build(MakeScan(Room(), 181));
  EXPECT_EQ(f.walls.vertex_count(), 6 * f.drawn_walls);
  EXPECT_EQ(f.drawn_walls, 180u - (f.segmentation.clusters.size() - 1));
  for (size_t v = 0; v < f.walls.vertex_count(); ++v) {
    const float z = f.walls.positions[3 * v + 2];
    const float alpha = f.walls.colors[4 * v + 3];
    EXPECT_TRUE(std::abs(z + 0.4f) < 1e-6f || std::abs(z - 0.2f) < 1e-6f) << z;
    EXPECT_FLOAT_EQ(alpha, z < 0.f ? options.wall_bottom_alpha : options.wall_top_alpha);
  }
  EXPECT_TRUE(AllFinite(f.walls));
}

TEST(ArFeatureBuilderTest, BoxDiscontinuitiesAreNotWalledButGetRays) {
  ArFeatureOptions options;
  options.ray_beam_interval = 1000;  // only the always-drawn rays
  const ArFeatures f = ArFeatureBuilder(options).Build(MakeScan(BoxBeforeWall(), 181));
  std::vector<size_t> cut;
  for (size_t i = 0; i + 1 < f.points.size(); ++i) {
    if (f.segmentation.wall_discontinuity[i] != 0) cut.push_back(i);
  }
  ASSERT_EQ(cut.size(), 2u);
  for (size_t wall : cut) {
    EXPECT_TRUE(f.points[wall].at_discontinuity);
    EXPECT_TRUE(f.points[wall + 1].at_discontinuity);
    EXPECT_TRUE(HasRayTo(f, wall));
    EXPECT_TRUE(HasRayTo(f, wall + 1));
  }
  // Rays: beam 0 (interval) if valid, plus the four discontinuity ends.
  const size_t interval_rays = f.points[0].valid ? 1 : 0;
  EXPECT_EQ(f.rays.vertex_count(), 2 * (4 + interval_rays));
  // Every existing wall but the two cuts is drawn.
  size_t existing = 0;
  for (uint8_t e : f.segmentation.wall_exists) existing += e;
  EXPECT_EQ(f.drawn_walls, existing - 2);
  // No drawn wall spans the jump between box (1.5 m) and back wall (3 m).
  for (size_t v = 0; v + 5 < f.walls.vertex_count(); v += 6) {
    const float ax = f.walls.positions[3 * v];
    const float bx = f.walls.positions[3 * (v + 1)];
    EXPECT_LT(std::abs(ax - bx), 0.5f);
  }
  // Rays start at the robot base on the floor.
  for (size_t v = 0; v < f.rays.vertex_count(); v += 2) {
    EXPECT_EQ(f.rays.positions[3 * v], 0.f);
    EXPECT_EQ(f.rays.positions[3 * v + 1], 0.f);
    EXPECT_EQ(f.rays.positions[3 * v + 2], -options.laser_height_m);
    EXPECT_EQ(f.rays.positions[3 * v + 5], -options.laser_height_m);
  }
}

TEST(ArFeatureBuilderTest, RaysAtARegularBeamInterval) {
  ArFeatureOptions options;
  options.ray_beam_interval = 10;
  const ArFeatures f = ArFeatureBuilder(options).Build(MakeScan(Room(), 181));
  size_t expected = 0;
  for (size_t i = 0; i < f.points.size(); ++i) {
    if (i % 10 == 0 || f.points[i].at_discontinuity) ++expected;
    if (i % 10 == 0) {
      EXPECT_TRUE(HasRayTo(f, i)) << i;
    }
  }
  EXPECT_EQ(f.rays.vertex_count(), 2 * expected);
  EXPECT_FLOAT_EQ(f.rays.colors[3], options.ray_alpha);
}

TEST(ArFeatureBuilderTest, IsolatedOutlierIsLabelledAndUnlabelledByDistance) {
  LaserScan scan = MakeScan(Room(), 181);
  scan.ranges_m[100] = 0.8f;
  const ArFeatures f = ArFeatureBuilder(ArFeatureOptions{}).Build(scan);
  EXPECT_TRUE(f.points[100].potential_outlier);
  EXPECT_TRUE(f.points[100].at_discontinuity);
  EXPECT_FALSE(f.points[99].potential_outlier);
  EXPECT_FALSE(f.points[101].potential_outlier);
  // The outlier is the nearest point but gets no distance label.
  for (const DistanceLabel& label : f.labels) EXPECT_NE(label.beam, 100u);
}

TEST(ArFeatureBuilderTest, LabelsTheNearestClustersFirst) {
  ArFeatureOptions options;
  options.label_count = 2;
  options.label_height_m = 0.7f;
  const ArFeatures f = ArFeatureBuilder(options).Build(MakeScan(Legs(), 361));
  ASSERT_EQ(f.labels.size(), 2u);
  const float leg_distance = static_cast<float>(std::hypot(2.0, 0.15) - 0.06);
  for (const DistanceLabel& label : f.labels) {
    EXPECT_NEAR(label.distance_m, leg_distance, 0.01f);
    EXPECT_NEAR(label.anchor_z_m, -options.laser_height_m + 0.7f, 1e-6f);
    EXPECT_EQ(label.anchor_x_m, f.points[label.beam].x_m);
    EXPECT_EQ(label.text.substr(label.text.size() - 2), " m");
  }
  EXPECT_NE(f.labels[0].cluster, f.labels[1].cluster);
  EXPECT_LE(f.labels[0].distance_m, f.labels[1].distance_m);

  LaserScan box = MakeScan(BoxBeforeWall(), 181);
  const ArFeatures g = ArFeatureBuilder(ArFeatureOptions{}).Build(box);
  ASSERT_FALSE(g.labels.empty());
  EXPECT_EQ(g.labels[0].text, "1.50 m");
}

TEST(ArFeatureBuilderTest, CirclesEveryHalfMetreOnTheFloor) {
  ArFeatureOptions options;
  options.circle_spacing_m = 0.5f;
  options.circle_max_radius_m = 2.0f;
  options.circle_segments_per_turn = 64;
  const ArFeatures f = ArFeatureBuilder(options).Build(MakeScan(Room(), 181));
  EXPECT_EQ(f.circle_radii_m, (std::vector<float>{0.5f, 1.0f, 1.5f, 2.0f}));
  ASSERT_EQ(f.circles.vertex_count(), 4u * 64u * 2u);
  for (size_t v = 0; v < f.circles.vertex_count(); ++v) {
    const float x = f.circles.positions[3 * v];
    const float y = f.circles.positions[3 * v + 1];
    const float radius = f.circle_radii_m[v / (64 * 2)];
    EXPECT_NEAR(std::hypot(x, y), radius, 1e-5f);
    EXPECT_EQ(f.circles.positions[3 * v + 2], -options.laser_height_m);
  }
  // Half circles in front of the robot.
  options.circle_half_angle_rad = 1.5707964f;
  const ArFeatures half = ArFeatureBuilder(options).Build(MakeScan(Room(), 181));
  EXPECT_EQ(half.circles.vertex_count(), 4u * 32u * 2u);
  for (size_t v = 0; v < half.circles.vertex_count(); ++v) {
    EXPECT_GE(half.circles.positions[3 * v], -1e-5f);
  }
}

TEST(ArFeatureBuilderTest, VerticalLinesAtValidPointsWhenEnabled) {
  ArFeatureOptions options;
  EXPECT_TRUE(ArFeatureBuilder(options).Build(MakeScan(Room(), 181)).vertical_lines.empty());
  options.vertical_lines_enabled = true;
  LaserScan scan = MakeScan(Room(), 181);
  scan.ranges_m[7] = NAN;
  const ArFeatures f = ArFeatureBuilder(options).Build(scan);
  EXPECT_EQ(f.vertical_lines.vertex_count(), 2u * 180u);
}

TEST(ArFeatureBuilderTest, InvalidBeamsProduceNoGeometryAndNoNaN) {
  ArFeatureOptions options;
  options.vertical_lines_enabled = true;
  options.ray_beam_interval = 1;
  LaserScan scan = MakeScan(Room(), 181);
  scan.ranges_m[10] = NAN;
  scan.ranges_m[11] = INFINITY;
  scan.ranges_m[12] = NAN;
  scan.ranges_m[90] = -INFINITY;
  const ArFeatures f = ArFeatureBuilder(options).Build(scan);
  EXPECT_EQ(f.invalid_beams, 4u);
  EXPECT_FALSE(f.points[10].valid);
  EXPECT_FALSE(f.points[90].valid);
  EXPECT_EQ(f.points[90].cluster, -1);
  EXPECT_EQ(f.laser_points.vertex_count(), 177u);
  EXPECT_EQ(f.rays.vertex_count(), 2u * 177u);
  for (const VertexArray* a : {&f.laser_points, &f.walls, &f.vertical_lines, &f.rays, &f.circles}) {
    EXPECT_TRUE(AllFinite(*a));
  }
  // 180 walls minus the 5 touching beams 10-12 (walls 9-12) and 90 (walls 89, 90).
  EXPECT_EQ(f.drawn_walls, 180u - 6u - (f.segmentation.clusters.size() - 3));
}

TEST(ArFeatureBuilderTest, EmptyScanGivesOnlyCircles) {
  const ArFeatures f = ArFeatureBuilder(ArFeatureOptions{}).Build(LaserScan{});
  EXPECT_TRUE(f.points.empty());
  EXPECT_TRUE(f.walls.empty());
  EXPECT_TRUE(f.rays.empty());
  EXPECT_TRUE(f.labels.empty());
  EXPECT_FALSE(f.circles.empty());
}

TEST(ArFeatureBuilderTest, ReusedOutputIsOverwritten) {
  const ArFeatureBuilder builder(ArFeatureOptions{});
  ArFeatures f;
  builder.Build(MakeScan(BoxBeforeWall(), 361), &f);
  LaserScan room = MakeScan(Room(), 181);
  room.sequence = 42;
  builder.Build(room, &f);
  const ArFeatures fresh = builder.Build(room);
  EXPECT_EQ(f.scan_sequence, 42u);
  EXPECT_EQ(f.points.size(), 181u);
  EXPECT_EQ(f.walls.positions, fresh.walls.positions);
  EXPECT_EQ(f.rays.positions, fresh.rays.positions);
  EXPECT_EQ(f.labels.size(), fresh.labels.size());
}

TEST(ArFeatureOptionsTest, IsValidNamesTheViolatedConstraint) {
  struct Case {
    void (*mutate)(ArFeatureOptions*);
    const char* expected;
  };
  const Case cases[] = {
      {[](ArFeatureOptions* o) { o->max_distance_m = 0.2f; }, "max_distance_m"},
      {[](ArFeatureOptions* o) { o->min_distance_m = -1.f; }, "min_distance_m"},
      {[](ArFeatureOptions* o) { o->laser_height_m = 0.f; }, "laser_height_m"},
      {[](ArFeatureOptions* o) { o->wall_height_m = NAN; }, "wall_height_m"},
      {[](ArFeatureOptions* o) { o->wall_top_alpha = 1.5f; }, "wall_top_alpha"},
      {[](ArFeatureOptions* o) { o->ray_beam_interval = 0; }, "ray_beam_interval"},
      {[](ArFeatureOptions* o) { o->circle_spacing_m = 0.f; }, "circle_spacing_m"},
      {[](ArFeatureOptions* o) { o->circle_max_radius_m = 0.1f; }, "circle_max_radius_m"},
      {[](ArFeatureOptions* o) { o->circle_segments_per_turn = 3; }, "circle_segments_per_turn"},
      {[](ArFeatureOptions* o) { o->circle_half_angle_rad = 4.f; }, "circle_half_angle_rad"},
      {[](ArFeatureOptions* o) { o->label_count = -2; }, "label_count"},
      {[](ArFeatureOptions* o) { o->segmentation.slope_threshold = -1.f; },
       "segmentation.slope_threshold"},
  };
  for (const Case& c : cases) {
    ArFeatureOptions options;
    c.mutate(&options);
    std::string error;
    EXPECT_FALSE(options.IsValid(&error)) << c.expected;
    EXPECT_NE(error.find(c.expected), std::string::npos) << error;
    EXPECT_FALSE(ArFeatureBuilder::Create(options, &error).has_value());
  }
  std::string error;
  EXPECT_TRUE(ArFeatureOptions{}.IsValid(&error)) << error;
}

}  // namespace
}  // namespace mostar::fusion
