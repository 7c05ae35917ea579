#include "operator_client/web/frame_composer.h"

#include <gtest/gtest.h>

#include "operator_client/fusion/test_scenes.h"
#include "operator_client/web/frame_reader_for_test.h"

namespace mostar::web {
namespace {

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
  const ComposedFrame frame = composer.Compose(Pair(), scan, {}, 5, false);
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
}

TEST(FrameComposerTest, BothEyesOnlyWhenAsked) {
  FrameComposer composer{ComposerOptions{}};
  const ComposedFrame frame = composer.Compose(Pair(), std::nullopt, {}, 1, true);
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

TEST(FrameComposerTest, PossibleObstaclesAreMagentaDots) {
  FrameComposer composer{ComposerOptions{}};
  vision::PossibleObstacle obstacle;
  obstacle.floor_point_laser = Eigen::Vector3d(1.5, 0.0, -0.4);
  const ComposedFrame frame = composer.Compose(Pair(), std::nullopt, {obstacle}, 1, false);
  testing::ReadFrame f;
  ASSERT_TRUE(testing::Read(*frame.left_only, &f));
  ASSERT_EQ(f.points.size(), 1u);
  EXPECT_EQ(f.points[0].rgba[0], 255);
  EXPECT_EQ(f.points[0].rgba[1], 0);
  EXPECT_EQ(f.points[0].rgba[2], 255);
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
