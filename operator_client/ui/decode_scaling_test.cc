#include "operator_client/ui/decode_scaling.h"

#include <gtest/gtest.h>

namespace mostar::ui {
namespace {

using render::DisplayMode;

client::DecodedStereoPair PairOfSize(int width, int height) {
  client::DecodedStereoPair pair;
  pair.left = cv::Mat(height, width, CV_8UC3, cv::Scalar::all(0));
  return pair;
}

TEST(DecodeScalingTest, ACalibrationScaledToHalfSizeProjectsToHalfTheFullSizePixel) {
  math::LaserCameraCalibration full;  // 640x480, principal point unset (image centre)
  full.image_width_px = 1280;
  full.image_height_px = 960;
  full.focal_px = 880;
  full.principal_y_px = 470.0;
  full.distortion.k1 = -0.05;
  const ImageScale scale = ScaleOfPair(full, PairOfSize(640, 480), {});
  EXPECT_DOUBLE_EQ(scale.x, 0.5);
  EXPECT_DOUBLE_EQ(scale.y, 0.5);
  const math::LaserCameraCalibration half = ScaledCalibration(full, scale);
  EXPECT_EQ(half.image_width_px, 640);
  EXPECT_EQ(half.image_height_px, 480);
  EXPECT_DOUBLE_EQ(half.fx(), 440);
  EXPECT_DOUBLE_EQ(half.cx(), 319.5);  // the image centre stays the image centre
  EXPECT_DOUBLE_EQ(half.cy(), (470.0 + 0.5) * 0.5 - 0.5);
  // A floor point lands on the same place of the scene in both images: u' + 0.5 = (u + 0.5) / 2.
  const math::CameraModel big(full, math::Eye::kLeft);
  const math::CameraModel small(half, math::Eye::kLeft);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(2.0, 0.5, -0.4), Eigen::Vector3d(4.0, -1.0, 0.3),
                                   Eigen::Vector3d(1.2, 0.2, -0.4)}) {
    const auto u = big.Project(p);
    const auto v = small.Project(p);
    ASSERT_TRUE(u && v);
    EXPECT_NEAR(v->x(), (u->x() + 0.5) * 0.5 - 0.5, 1e-9);
    EXPECT_NEAR(v->y(), (u->y() + 0.5) * 0.5 - 0.5, 1e-9);
  }
}

TEST(DecodeScalingTest, NoImageKeepsThePreviousScaleAndTheFullSizeIsUnchanged) {
  math::LaserCameraCalibration c;
  ImageScale previous;
  previous.width_px = 320;
  previous.height_px = 240;
  previous.x = previous.y = 0.5;
  EXPECT_EQ(ScaleOfPair(c, std::nullopt, previous), previous);
  EXPECT_EQ(ScaleOfPair(c, client::DecodedStereoPair{}, previous), previous);
  const ImageScale same = ScaleOfPair(c, PairOfSize(640, 480), previous);
  EXPECT_DOUBLE_EQ(ScaledCalibration(c, same).fx(), c.fx());
  EXPECT_FALSE(ScaledCalibration(c, same).principal_x_px.has_value());
}

TEST(DecodeScalingTest, AlignmentOffsetsAndCropsFollowTheScale) {
  render::EyeAlignment a;
  a.offset_x_px = 4;
  a.offset_y_px = -6;
  a.crop_left_px = 8;
  a.crop_top_px = 2;
  ImageScale s;
  s.width_px = 320;
  s.height_px = 240;
  s.x = s.y = 0.5;
  const render::EyeAlignment b = ScaledAlignment(a, s);
  EXPECT_FLOAT_EQ(b.offset_x_px, 2);
  EXPECT_FLOAT_EQ(b.offset_y_px, -3);
  EXPECT_FLOAT_EQ(b.crop_left_px, 4);
  EXPECT_FLOAT_EQ(b.crop_top_px, 1);
}

TEST(DecodeScalingTest, TheRightEyeTakesItsOwnIntrinsicsScaledLikeTheLeft) {
  math::LaserCameraCalibration shared;
  shared.focal_px = 440;
  CameraIntrinsicsInfo own;
  own.width_px = shared.image_width_px;
  own.height_px = shared.image_height_px;
  own.fx = own.fy = 460;
  own.cx = shared.cx();
  own.cy = shared.cy() + 4;
  const ImageScale half{shared.image_width_px / 2, shared.image_height_px / 2, 0.5, 0.5};
  const auto [left, right] = ScaledEyeCalibrations(shared, own, half);
  EXPECT_DOUBLE_EQ(left.fx(), 220);
  EXPECT_DOUBLE_EQ(right.fx(), 230);
  EXPECT_DOUBLE_EQ(right.cy() - left.cy(), 2);
  const auto [left_shared, right_shared] = ScaledEyeCalibrations(shared, std::nullopt, half);
  EXPECT_DOUBLE_EQ(right_shared.fx(), left_shared.fx());
}

// NESC measures on the decoded images; the hint is applied to the profile's offsets.
TEST(DecodeScalingTest, TheOffsetHintIsInTheProfilesPixelsAtAnyDecodeScale) {
  math::LaserCameraCalibration c;
  c.focal_px = 440;
  render::EyeAlignment left, right;
  right.offset_y_px = -2;
  const ImageScale full;
  const ImageScale half{320, 240, 0.5, 0.5};
  render::StereoGeometry at_full, at_half;
  std::string error;
  ASSERT_TRUE(at_full.Update(c, c, render::AlignmentModel::kSharedModel, left, right, &error))
      << error;
  ASSERT_TRUE(at_half.Update(ScaledCalibration(c, half), ScaledCalibration(c, half),
                             render::AlignmentModel::kSharedModel, ScaledAlignment(left, half),
                             ScaledAlignment(right, half), &error))
      << error;
  // The same 3 px misalignment reads 1.5 px on the half-size decode; both ask for -5 px.
  EXPECT_NEAR(SuggestedRightOffsetInProfile(at_full, left, full, 3.0), -5.f, 1e-4);
  EXPECT_NEAR(SuggestedRightOffsetInProfile(at_half, left, half, 1.5), -5.f, 1e-4);
}

TEST(DecodeScalingTest, MonoDecodesTheShownEyeUnlessEdgeProcessingNeedsTheOther) {
  client::DecodeTarget t = DecodeTargetFor(DisplayMode::kMonoLeft, 640, 480, false, true);
  EXPECT_TRUE(t.left);
  EXPECT_FALSE(t.right);
  EXPECT_EQ(t.width_px, 640);
  EXPECT_EQ(t.height_px, 480);
  t = DecodeTargetFor(DisplayMode::kMonoRight, 640, 480, false, true);
  EXPECT_FALSE(t.left);
  EXPECT_TRUE(t.right);
  // NESC needs both eyes; monoscopic edge processing needs the left one.
  t = DecodeTargetFor(DisplayMode::kMonoLeft, 640, 480, true, true);
  EXPECT_TRUE(t.left && t.right);
  t = DecodeTargetFor(DisplayMode::kMonoLeft, 640, 480, true, false);
  EXPECT_TRUE(t.left);
  EXPECT_FALSE(t.right);
  t = DecodeTargetFor(DisplayMode::kMonoRight, 640, 480, true, false);
  EXPECT_TRUE(t.left && t.right);
}

TEST(DecodeScalingTest, StereoModesDecodeBothEyesAtTheLargestViewport) {
  client::DecodeTarget t = DecodeTargetFor(DisplayMode::kSideBySideFull, 1280, 480, false, true);
  EXPECT_TRUE(t.left && t.right);
  EXPECT_EQ(t.width_px, 640);
  EXPECT_EQ(t.height_px, 480);
  t = DecodeTargetFor(DisplayMode::kAnaglyphGrey, 1280, 960, false, true);
  EXPECT_TRUE(t.left && t.right);
  EXPECT_EQ(t.width_px, 1280);
}

}  // namespace
}  // namespace mostar::ui
