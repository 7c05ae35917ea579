#include "operator_client/render/eye_geometry.h"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <cstdio>

namespace mostar::render {
namespace {

math::LaserCameraCalibration Distorted() {
  math::LaserCameraCalibration c;
  c.focal_px = 440;
  c.distortion.k1 = -0.28;
  c.distortion.k2 = 0.07;
  c.distortion.p1 = 0.001;
  c.distortion.p2 = -0.0005;
  return c;
}

EyeGeometry Make(const math::LaserCameraCalibration& c, math::Eye eye, float dx, float dy,
                 AlignmentModel model, float rotation_rad = 0.f) {
  EyeAlignment alignment;
  alignment.offset_x_px = dx;
  alignment.offset_y_px = dy;
  alignment.rotation_rad = rotation_rad;
  std::string error;
  const std::optional<EyeGeometry> g = MakeEyeGeometry(c, eye, alignment, model, &error);
  EXPECT_TRUE(g.has_value()) << error;
  return *g;
}

// The displayed pixel of a laser point shows what the camera image has at image.Project(), with
// and without a rotation (the calibration itself rolled, too).
TEST(EyeGeometryTest, DisplayedPixelShowsTheImageModelsProjection) {
  math::LaserCameraCalibration rolled = Distorted();
  rolled.roll_rad = 0.01;
  rolled.focal_y_px = 445;
  for (const AlignmentModel model :
       {AlignmentModel::kSharedModel, AlignmentModel::kPerEyeIntrinsics}) {
    for (const math::Eye eye : {math::Eye::kLeft, math::Eye::kRight}) {
      for (const float rotation : {0.f, -0.03f}) {
        const EyeGeometry g =
            Make(rotation == 0.f ? Distorted() : rolled, eye, 3.5f, -5.f, model, rotation);
        const ImageWarp warp = MakeImageWarp(g);
        for (double x = 1.0; x <= 6.0; x += 1.0) {
          for (double y = -2.0; y <= 2.0; y += 0.5) {
            const Eigen::Vector3d p(x, y, -0.4);
            const auto shown = g.display.ProjectUndistorted(p);
            const auto seen = g.image.Project(p);
            if (!shown || !seen || !g.image.IsInImage(*seen)) continue;
            EXPECT_LT((WarpToImage(warp, *shown) - *seen).norm(), 1e-3)
                << AlignmentModelName(model) << " " << x << " " << y << " " << rotation;
          }
        }
      }
    }
  }
}

TEST(EyeGeometryTest, SharedModelKeepsTheOverlayAndMovesTheImageModel) {
  const math::LaserCameraCalibration c = Distorted();
  const EyeGeometry g = Make(c, math::Eye::kRight, 2.f, -5.f, AlignmentModel::kSharedModel);
  EXPECT_DOUBLE_EQ(g.display.calibration().cx(), c.cx());
  EXPECT_DOUBLE_EQ(g.display.calibration().cy(), c.cy());
  EXPECT_DOUBLE_EQ(g.image.calibration().cx(), c.cx() - 2.0);
  EXPECT_DOUBLE_EQ(g.image.calibration().cy(), c.cy() + 5.0);
  const EyeGeometry turned =
      Make(c, math::Eye::kRight, 0.f, 0.f, AlignmentModel::kSharedModel, -0.02f);
  EXPECT_DOUBLE_EQ(turned.display.calibration().roll_rad, c.roll_rad);
  EXPECT_NEAR(turned.image.calibration().roll_rad, c.roll_rad + 0.02, 1e-7)
      << "a right camera rolled 0.02 rad is aligned by -0.02";
}

TEST(EyeGeometryTest, PerEyeIntrinsicsMoveTheOverlayWithTheImage) {
  const math::LaserCameraCalibration c = Distorted();
  const EyeGeometry g = Make(c, math::Eye::kRight, 2.f, -5.f, AlignmentModel::kPerEyeIntrinsics);
  EXPECT_DOUBLE_EQ(g.image.calibration().cx(), c.cx());
  EXPECT_DOUBLE_EQ(g.image.calibration().cy(), c.cy());
  EXPECT_DOUBLE_EQ(g.display.calibration().cx(), c.cx() + 2.0);
  EXPECT_DOUBLE_EQ(g.display.calibration().cy(), c.cy() - 5.0);
  const EyeGeometry turned =
      Make(c, math::Eye::kRight, 0.f, 0.f, AlignmentModel::kPerEyeIntrinsics, -0.02f);
  EXPECT_DOUBLE_EQ(turned.image.calibration().roll_rad, c.roll_rad);
  EXPECT_NEAR(turned.display.calibration().roll_rad, c.roll_rad - 0.02, 1e-7);
}

TEST(EyeGeometryTest, WithoutDistortionTheWarpIsTheOffset) {
  const EyeGeometry g = Make(math::LaserCameraCalibration{}, math::Eye::kLeft, 7.f, 4.f,
                             AlignmentModel::kSharedModel);
  const Eigen::Vector2d q(100.25, 300.5);
  EXPECT_LT((WarpToImage(MakeImageWarp(g), q) - (q - Eigen::Vector2d(7, 4))).norm(), 1e-4);
}

TEST(EyeGeometryTest, RefusesAnOffsetThatLeavesTheImage) {
  EyeAlignment alignment;
  alignment.offset_x_px = 1000.f;
  std::string error;
  EXPECT_FALSE(MakeEyeGeometry(math::LaserCameraCalibration{}, math::Eye::kRight, alignment,
                               AlignmentModel::kSharedModel, &error));
  EXPECT_NE(error.find("stereo alignment"), std::string::npos) << error;
}

TEST(EyeGeometryTest, CropKeepsWhatBothEyesShow) {
  EyeAlignment left, right;
  CropForRightOffset(-4.f, 6.f, &left, &right);
  EXPECT_EQ(right.offset_x_px, -4.f);
  EXPECT_EQ(right.offset_y_px, 6.f);
  EXPECT_EQ(left.offset_x_px, 0.f);
  for (const EyeAlignment& a : {left, right}) {
    EXPECT_EQ(a.crop_right_px, 4.f);
    EXPECT_EQ(a.crop_left_px, 0.f);
    EXPECT_EQ(a.crop_top_px, 6.f);
    EXPECT_EQ(a.crop_bottom_px, 0.f);
  }
}

TEST(EyeGeometryTest, SuggestedOffsetCancelsTheResidualInBothModels) {
  // Shared model: the right image model moves with the offset, so the residual is what is left.
  const math::LaserCameraCalibration c = Distorted();
  const EyeGeometry left = Make(c, math::Eye::kLeft, 0.f, 0.f, AlignmentModel::kSharedModel);
  const EyeGeometry right = Make(c, math::Eye::kRight, 0.f, -2.f, AlignmentModel::kSharedModel);
  EXPECT_FLOAT_EQ(SuggestedRightOffsetY(left, right, {}, 3.f), -5.f);
  // Per-eye intrinsics: the right camera's principal row is 5 px lower and its model knows it.
  math::LaserCameraCalibration low = c;
  low.principal_y_px = c.cy() + 5.0;
  const EyeGeometry left_own =
      Make(c, math::Eye::kLeft, 0.f, 0.f, AlignmentModel::kPerEyeIntrinsics);
  const EyeGeometry right_own =
      Make(low, math::Eye::kRight, 0.f, 0.f, AlignmentModel::kPerEyeIntrinsics);
  EXPECT_FLOAT_EQ(SuggestedRightOffsetY(left_own, right_own, {}, 0.0), -5.f);
}

TEST(EyeGeometryTest, ProfileRoundTrip) {
  EyeAlignment left, right;
  CropForRightOffset(1.5f, -5.f, &left, &right);
  right.rotation_rad = -0.0175f;
  const math::StereoAlignmentProfile profile =
      ToProfile(AlignmentModel::kPerEyeIntrinsics, left, right);
  EXPECT_TRUE(profile.per_eye_intrinsics);
  EXPECT_EQ(profile.right_offset_y_px, -5.0);
  EXPECT_EQ(profile.right_rotation_rad, static_cast<double>(-0.0175f));
  AlignmentModel model = AlignmentModel::kSharedModel;
  EyeAlignment left_back, right_back;
  FromProfile(profile, &model, &left_back, &right_back);
  EXPECT_EQ(model, AlignmentModel::kPerEyeIntrinsics);
  EXPECT_TRUE(left_back == left);
  EXPECT_TRUE(right_back == right);
}

TEST(EyeGeometryTest, LoadsTheAlignmentSavedInAProfileAndNothingFromAMissingFile) {
  char dir[] = "/tmp/eye_geometry_test_XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  const std::string path = std::string(dir) + "/profile.pbtxt";
  EyeAlignment left, right;
  CropForRightOffset(0.f, -4.f, &left, &right);
  right.rotation_rad = static_cast<float>(-1.0 * M_PI / 180.0);  // saved as -1 degree
  std::string error;
  ASSERT_TRUE(math::SaveCalibrationProfile(
      path, Distorted(), ToProfile(AlignmentModel::kPerEyeIntrinsics, left, right), "test", &error))
      << error;
  AlignmentModel model = AlignmentModel::kSharedModel;
  EyeAlignment left_back, right_back;
  ASSERT_TRUE(LoadAlignment(path, &model, &left_back, &right_back, &error)) << error;
  EXPECT_EQ(model, AlignmentModel::kPerEyeIntrinsics);
  EXPECT_NEAR(right_back.rotation_rad, right.rotation_rad, 1e-7);
  right_back.rotation_rad = right.rotation_rad;  // float through degrees and back
  EXPECT_TRUE(right_back == right);
  EyeAlignment untouched;
  untouched.offset_y_px = 7;
  EXPECT_FALSE(LoadAlignment(path + ".missing", &model, &untouched, &untouched, &error));
  EXPECT_NE(error.find(".missing"), std::string::npos) << error;
  EXPECT_EQ(untouched.offset_y_px, 7.f);
  std::remove(path.c_str());
  ::rmdir(dir);
}

TEST(StereoGeometryTest, RebuildsOnlyWhenAnInputChanges) {
  StereoGeometry geometry;
  std::string error;
  const math::LaserCameraCalibration c = Distorted();
  EyeAlignment right;
  EXPECT_FALSE(geometry.ready());
  EXPECT_TRUE(geometry.Update(c, c, AlignmentModel::kSharedModel, {}, right, &error)) << error;
  EXPECT_TRUE(geometry.ready());
  EXPECT_FALSE(geometry.Update(c, c, AlignmentModel::kSharedModel, {}, right, &error));
  right.offset_y_px = -5;
  EXPECT_TRUE(geometry.Update(c, c, AlignmentModel::kSharedModel, {}, right, &error)) << error;
  EXPECT_TRUE(error.empty()) << error;
  EXPECT_TRUE(geometry.Update(c, c, AlignmentModel::kPerEyeIntrinsics, {}, right, &error));
}

TEST(StereoGeometryTest, AnOffsetOutOfTheImageKeepsThePreviousGeometryAndSaysWhy) {
  StereoGeometry geometry;
  std::string error;
  const math::LaserCameraCalibration c = Distorted();
  EyeAlignment far;
  far.offset_x_px = 1e6f;
  // First build: nothing to keep, the geometry without offsets, and the reason.
  EXPECT_TRUE(geometry.Update(c, c, AlignmentModel::kPerEyeIntrinsics, {}, far, &error));
  EXPECT_FALSE(error.empty());
  ASSERT_TRUE(geometry.ready());
  const double cx = geometry.eye(1).display.calibration().cx();
  EyeAlignment near;
  near.offset_x_px = 4;
  EXPECT_TRUE(geometry.Update(c, c, AlignmentModel::kPerEyeIntrinsics, {}, near, &error));
  const double moved_cx = geometry.eye(1).display.calibration().cx();
  EXPECT_NE(moved_cx, cx);
  // Refused later: the last good geometry stays.
  EXPECT_FALSE(geometry.Update(c, c, AlignmentModel::kPerEyeIntrinsics, {}, far, &error));
  EXPECT_FALSE(error.empty());
  EXPECT_EQ(geometry.eye(1).display.calibration().cx(), moved_cx);
}

}  // namespace
}  // namespace mostar::render
