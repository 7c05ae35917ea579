#include "operator_client/web/frame_composer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "operator_client/fusion/test_scenes.h"
#include "operator_client/web/frame_reader_for_test.h"

namespace mostar::web {
namespace {

FrameInputs WithScan(const LaserScan& scan) {
  FrameInputs inputs;
  inputs.scan = scan;
  return inputs;
}

// One sonar 0.2 m ahead of the laser looking forward with an echo at `range_m`.
SonarRanges SonarAhead(float range_m) {
  SonarRange r;
  r.mount.frame_id = "sonar_0";
  r.mount.x_m = 0.2;
  r.range_m = range_m;
  r.min_range_m = 0.03f;
  r.max_range_m = 6.0f;
  r.field_of_view_rad = 0.5f;
  SonarRanges ring;
  ring.cycle = 3;
  ring.ranges = {r};
  return ring;
}

bool IsMagenta(const uint8_t rgba[4]) { return rgba[0] == 255 && rgba[1] == 0 && rgba[2] == 255; }

CompressedStereoPair Pair() {
  CompressedStereoPair pair;
  pair.left.stamp = pair.right.stamp = FromUnixNanos(1700000000000000000);
  pair.left.data = {0xff, 0xd8, 'L'};
  pair.right.data = {0xff, 0xd8, 'R', 'R'};
  return pair;
}

TEST(FrameComposerTest, AScanGivesWallsInTheImageAndTheMap) {
  FrameComposer composer{ComposerOptions{}};
  LaserScan scan = fusion::testing::MakeScan(fusion::testing::Room(), 181);
  scan.stamp = FromUnixNanos(1700000000010000000);
  const ComposedFrame frame = composer.Compose(Pair(), WithScan(scan), 5, false);
  ASSERT_TRUE(frame.left_only);
  EXPECT_FALSE(frame.both_eyes);
  EXPECT_GT(frame.triangles, 10u);
  testing::ReadFrame f;
  ASSERT_TRUE(testing::Read(*frame.left_only, &f));
  EXPECT_EQ(f.sequence, 5u);
  EXPECT_EQ(f.width_px, 640);
  EXPECT_EQ(f.height_px, 480);
  EXPECT_EQ(f.left_jpeg, "\xff\xd8L");
  EXPECT_TRUE(f.right_jpeg.empty());
  EXPECT_NEAR(f.scan_stamp_s, 1700000000.01, 1e-6);
  EXPECT_EQ(f.triangles.size(), 3 * frame.triangles);
  EXPECT_FALSE(f.lines.empty());  // rays and circles
  EXPECT_GT(f.map.size(), 100u);
  // Every wall vertex is projected by the left image model: the first wall's floor corner.
  int in_image = 0;
  for (const PixelVertex& v : f.triangles) {
    if (composer.left_image_model().IsInImage(Eigen::Vector2d(v.u_px, v.v_px))) ++in_image;
  }
  EXPECT_GT(in_image, 0);
  EXPECT_EQ(f.flags, 0u);  // no edge result, no sonar
  EXPECT_TRUE(f.sonar_triangles.empty());
}

// As the console: the scan moved to the pair's time (here: the robot turned 5 degrees left
// between scan and image, so everything appears 5 degrees to the right), or faded when no
// odometry covers the gap; without a move function, drawn as measured.
TEST(FrameComposerTest, TheScanIsMovedToThePairsTimeOrFaded) {
  FrameComposer composer{ComposerOptions{}};
  LaserScan scan = fusion::testing::MakeScan(fusion::testing::Room(), 181);
  const double turn = 5.0 * M_PI / 180.0;
  auto moved_by_turn = [&](const LaserScan& s, fusion::MovedScan* out) {
    out->points.clear();
    for (size_t i = 0; i < s.ranges_m.size(); ++i) {
      const double a = s.AngleOf(i) - turn;
      const double r = s.ranges_m[i];
      out->points.push_back(
          {static_cast<float>(r * std::cos(a)), static_cast<float>(r * std::sin(a))});
    }
    out->moved = true;
  };
  auto not_covered = [](const LaserScan&, fusion::MovedScan* out) {
    out->moved = false;
    out->reason = "no odometry";
  };
  testing::ReadFrame measured, moved, faded;
  ComposedFrame frame = composer.Compose(Pair(), WithScan(scan), 1, false);
  EXPECT_FALSE(frame.motion.moved);
  EXPECT_FALSE(frame.motion.faded);
  ASSERT_TRUE(testing::Read(*frame.left_only, &measured));
  FrameInputs inputs = WithScan(scan);
  inputs.move_to_pair_time = moved_by_turn;
  frame = composer.Compose(Pair(), inputs, 2, false);
  EXPECT_TRUE(frame.motion.moved);
  ASSERT_TRUE(testing::Read(*frame.left_only, &moved));
  inputs.move_to_pair_time = not_covered;
  frame = composer.Compose(Pair(), inputs, 3, false);
  EXPECT_TRUE(frame.motion.faded);
  EXPECT_EQ(frame.motion.reason, "no odometry");
  ASSERT_TRUE(testing::Read(*frame.left_only, &faded));
  // On the map every point turned 5 degrees clockwise; in the image the faded walls are where
  // the measured ones are, more transparent.
  ASSERT_FALSE(measured.map.empty());
  ASSERT_EQ(moved.map.size(), measured.map.size());
  for (size_t i = 0; i < measured.map.size(); ++i) {
    const double before = std::atan2(measured.map[i].y_m, measured.map[i].x_m);
    const double after = std::atan2(moved.map[i].y_m, moved.map[i].x_m);
    EXPECT_NEAR(std::remainder(after - before, 2 * M_PI), -turn, 1e-3) << "map point " << i;
  }
  ASSERT_FALSE(measured.triangles.empty());
  ASSERT_EQ(faded.triangles.size(), measured.triangles.size());
  size_t fainter = 0;
  for (size_t i = 0; i < measured.triangles.size(); ++i) {
    EXPECT_FLOAT_EQ(faded.triangles[i].u_px, measured.triangles[i].u_px);
    EXPECT_LE(faded.triangles[i].rgba[3], measured.triangles[i].rgba[3]);
    fainter += faded.triangles[i].rgba[3] < measured.triangles[i].rgba[3];
  }
  EXPECT_GT(fainter, measured.triangles.size() / 2);
}

TEST(FrameComposerTest, BothEyesOnlyWhenAsked) {
  FrameComposer composer{ComposerOptions{}};
  const ComposedFrame frame = composer.Compose(Pair(), FrameInputs{}, 1, true);
  ASSERT_TRUE(frame.both_eyes);
  testing::ReadFrame f;
  ASSERT_TRUE(testing::Read(*frame.both_eyes, &f));
  EXPECT_EQ(f.right_jpeg, "\xff\xd8RR");
  EXPECT_EQ(f.scan_stamp_s, 0.0);
  // No scan, no overlay: the console draws none either (AssembleOverlay without features).
  EXPECT_TRUE(f.triangles.empty());
  EXPECT_TRUE(f.lines.empty());
  EXPECT_TRUE(f.map.empty());
}

TEST(FrameComposerTest, ThePairsEdgeResultGivesMagentaDotsAndTheCorrectedScan) {
  FrameComposer composer{ComposerOptions{}};
  LaserScan scan = fusion::testing::MakeScan(fusion::testing::Room(), 181);
  scan.stamp = FromUnixNanos(1700000000010000000);
  auto result = std::make_shared<vision::VisionResult>();
  result->ok = true;
  vision::PossibleObstacle obstacle;
  obstacle.floor_point_laser = Eigen::Vector3d(1.5, 0.0, -0.4);
  result->classification.possible_obstacles = {obstacle};
  result->classification.corrected_scan = scan;
  result->classification.corrected_scan.stamp = FromUnixNanos(1700000000020000000);
  FrameInputs inputs = WithScan(scan);
  inputs.edges = result;
  ComposedFrame frame = composer.Compose(Pair(), inputs, 1, false);
  EXPECT_TRUE(frame.edges);
  EXPECT_EQ(frame.possible_obstacles, 1u);
  testing::ReadFrame f;
  ASSERT_TRUE(testing::Read(*frame.left_only, &f));
  EXPECT_EQ(f.flags, kFrameEdges);
  EXPECT_EQ(f.possible_obstacles, 1u);
  EXPECT_NEAR(f.scan_stamp_s, 1700000000.02, 1e-6) << "the walls come from the corrected scan";
  // The dot where the camera model puts the obstacle (the laser points are not magenta).
  const Eigen::Vector2d expected = *composer.left_image_model().Project(obstacle.floor_point_laser);
  int dots = 0;
  for (const PixelVertex& p : f.points) {
    if (!IsMagenta(p.rgba)) continue;
    ++dots;
    EXPECT_NEAR(p.u_px, expected.x(), 1e-3);
    EXPECT_NEAR(p.v_px, expected.y(), 1e-3);
  }
  EXPECT_EQ(dots, 1);

  // A failed result draws nothing of it: the raw scan, no dots.
  result->ok = false;
  frame = composer.Compose(Pair(), inputs, 2, false);
  EXPECT_FALSE(frame.edges);
  ASSERT_TRUE(testing::Read(*frame.left_only, &f));
  EXPECT_EQ(f.flags, 0u);
  EXPECT_EQ(f.possible_obstacles, 0u);
  EXPECT_NEAR(f.scan_stamp_s, 1700000000.01, 1e-6);
  for (const PixelVertex& p : f.points) EXPECT_FALSE(IsMagenta(p.rgba));
}

// The corrected scan of an edge result is where edge processing had it (moved to the pair's time
// before processing): drawn as it is, never moved a second time.
TEST(FrameComposerTest, TheCorrectedScanIsNotMovedAgain) {
  FrameComposer composer{ComposerOptions{}};
  const LaserScan scan = fusion::testing::MakeScan(fusion::testing::Room(), 181);
  auto result = std::make_shared<vision::VisionResult>();
  result->ok = true;
  result->classification.corrected_scan = scan;
  result->placement.at_image_time = true;
  int moves = 0;
  FrameInputs inputs = WithScan(scan);
  inputs.move_to_pair_time = [&moves](const LaserScan&, fusion::MovedScan* out) {
    ++moves;
    out->moved = false;
    out->reason = "should not be asked";
  };
  testing::ReadFrame unmoved, placed;
  ComposedFrame frame = composer.Compose(Pair(), WithScan(scan), 1, false);
  ASSERT_TRUE(testing::Read(*frame.left_only, &unmoved));
  inputs.edges = result;
  frame = composer.Compose(Pair(), inputs, 2, false);
  EXPECT_EQ(moves, 0);
  EXPECT_TRUE(frame.motion.moved);
  EXPECT_FALSE(frame.motion.faded);
  ASSERT_TRUE(testing::Read(*frame.left_only, &placed));
  ASSERT_EQ(placed.map.size(), unmoved.map.size());
  for (size_t i = 0; i < placed.map.size(); ++i) {
    EXPECT_FLOAT_EQ(placed.map[i].x_m, unmoved.map[i].x_m);
    EXPECT_FLOAT_EQ(placed.map[i].y_m, unmoved.map[i].y_m);
  }
  // A result whose scan could not be moved is drawn faded, with the reason it carries.
  result->placement.at_image_time = false;
  result->placement.reason = "no odometry at the image time";
  frame = composer.Compose(Pair(), inputs, 3, false);
  EXPECT_EQ(moves, 0);
  EXPECT_TRUE(frame.motion.faded);
  EXPECT_EQ(frame.motion.reason, "no odometry at the image time");
}

TEST(FrameComposerTest, PossibleObstaclesWithoutAScanAreStillDrawn) {
  FrameComposer composer{ComposerOptions{}};
  auto result = std::make_shared<vision::VisionResult>();
  result->ok = true;
  vision::PossibleObstacle obstacle;
  obstacle.floor_point_laser = Eigen::Vector3d(1.5, 0.0, -0.4);
  result->classification.possible_obstacles = {obstacle};
  FrameInputs inputs;
  inputs.edges = result;
  const ComposedFrame frame = composer.Compose(Pair(), inputs, 1, false);
  testing::ReadFrame f;
  ASSERT_TRUE(testing::Read(*frame.left_only, &f));
  ASSERT_EQ(f.points.size(), 1u);
  EXPECT_TRUE(IsMagenta(f.points[0].rgba));
}

TEST(FrameComposerTest, SonarSectorsInTheImageAndTheMapUnderTheWalls) {
  FrameComposer composer{ComposerOptions{}};
  // The room's end wall is 3 m ahead: an echo at 1.2 m is something the laser does not see
  // (the glass door), outlined in magenta.
  LaserScan scan = fusion::testing::MakeScan(fusion::testing::Room(), 181);
  FrameInputs inputs = WithScan(scan);
  inputs.sonar = SonarAhead(1.2f);
  ComposedFrame frame = composer.Compose(Pair(), inputs, 1, false);
  EXPECT_GT(frame.sonar_triangles, 0u);
  testing::ReadFrame f;
  ASSERT_TRUE(testing::Read(*frame.left_only, &f));
  EXPECT_EQ(f.flags, kFrameSonar);
  EXPECT_EQ(f.sonar_echoes, 1);
  EXPECT_EQ(f.sonar_unseen, 1);
  EXPECT_EQ(f.triangles.size(), 3 * frame.triangles) << "the walls stay in their own layer";
  ASSERT_FALSE(f.sonar_triangles.empty());
  ASSERT_FALSE(f.sonar_lines.empty());
  for (const PixelVertex& v : f.sonar_lines) EXPECT_TRUE(IsMagenta(v.rgba));
  // Translucent fans whose vertices the camera model puts in the image's lower half (floor).
  int in_image = 0;
  for (const PixelVertex& v : f.sonar_triangles) {
    EXPECT_LT(v.rgba[3], 255);
    if (composer.left_image_model().IsInImage(Eigen::Vector2d(v.u_px, v.v_px))) {
      ++in_image;
      EXPECT_GT(v.v_px, f.height_px / 2);
    }
  }
  EXPECT_GT(in_image, 0);
  // On the map: the fan from the mount to the echo arc, in metres of the laser frame.
  ASSERT_FALSE(f.sonar_map_triangles.empty());
  ASSERT_FALSE(f.sonar_map_lines.empty());
  float farthest = 0;
  for (const MapPoint& p : f.sonar_map_triangles) {
    EXPECT_GE(p.x_m, 0.2f - 1e-4f);
    farthest = std::max(farthest, std::hypot(p.x_m - 0.2f, p.y_m));
  }
  EXPECT_NEAR(farthest, 1.2f, 1e-3);

  // An echo on the wall the laser sees: a sector, no outline.
  inputs.sonar = SonarAhead(2.8f);
  frame = composer.Compose(Pair(), inputs, 2, false);
  ASSERT_TRUE(testing::Read(*frame.left_only, &f));
  EXPECT_EQ(f.sonar_echoes, 1);
  EXPECT_EQ(f.sonar_unseen, 0);
  EXPECT_FALSE(f.sonar_map_triangles.empty());
  EXPECT_TRUE(f.sonar_lines.empty());

  // Sonar sectors switched off in the configuration: nothing, as in the console.
  ComposerOptions off;
  off.sonar.enabled = false;
  FrameComposer quiet{off};
  inputs.sonar = SonarAhead(1.2f);
  ASSERT_TRUE(testing::Read(*quiet.Compose(Pair(), inputs, 1, false).left_only, &f));
  EXPECT_EQ(f.flags, 0u);
  EXPECT_TRUE(f.sonar_map_triangles.empty());
}

TEST(FrameComposerTest, PotentialOutliersHaveOneLabelPerBeam) {
  FrameComposer composer{ComposerOptions{}};
  const LaserScan scan = fusion::testing::MakeScan(fusion::testing::Legs(), 361);
  const std::vector<bool> outliers = composer.PotentialOutliers(scan);
  ASSERT_EQ(outliers.size(), scan.ranges_m.size());
  ASSERT_TRUE(composer.left_model());
  ASSERT_TRUE(composer.right_model());
  EXPECT_EQ(composer.left_model()->width_px(), composer.left_image_model().width_px());
}

TEST(FrameComposerTest, AdoptsTheRobotsIntrinsicsOrSaysWhyNot) {
  FrameComposer composer{ComposerOptions{}};
  CameraIntrinsicsInfo k;
  k.width_px = 640;
  k.height_px = 480;
  k.fx = k.fy = 400;
  k.cx = 300;
  k.cy = 250;
  std::string message;
  composer.SetRobotIntrinsics(k, &message);
  EXPECT_TRUE(message.empty()) << message;
  EXPECT_DOUBLE_EQ(composer.left_image_model().calibration().fx(), 400);
  k.width_px = 320;
  k.fx = 500;
  composer.SetRobotIntrinsics(k, &message);
  EXPECT_FALSE(message.empty());
  EXPECT_DOUBLE_EQ(composer.left_image_model().calibration().fx(), 400);
}

}  // namespace
}  // namespace mostar::web
