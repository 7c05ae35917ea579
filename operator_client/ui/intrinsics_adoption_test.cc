#include "operator_client/ui/intrinsics_adoption.h"

#include <gtest/gtest.h>

namespace mostar::ui {
namespace {

CameraIntrinsicsInfo Intrinsics(double fx) {
  CameraIntrinsicsInfo k;
  k.width_px = 640;
  k.height_px = 480;
  k.fx = fx;
  k.fy = fx + 2;
  k.cx = 321.5;
  k.cy = 238.25;
  k.distortion = {-0.1, 0.02, 0.001, -0.002};
  return k;
}

math::LaserCameraCalibration Calibration() {
  math::LaserCameraCalibration c;
  c.camera_y_m = 0.3;
  c.tilt_rad = 0.1;
  return c;
}

TEST(WithRobotIntrinsicsTest, TakesIntrinsicsAndKeepsExtrinsics) {
  const math::LaserCameraCalibration base = Calibration();
  math::LaserCameraCalibration out;
  std::string error;
  ASSERT_TRUE(WithRobotIntrinsics(base, Intrinsics(600), &out, &error)) << error;
  EXPECT_EQ(out.fx(), 600);
  EXPECT_EQ(out.fy(), 602);
  EXPECT_EQ(out.cx(), 321.5);
  EXPECT_EQ(out.cy(), 238.25);
  EXPECT_EQ(out.distortion.k1, -0.1);
  EXPECT_EQ(out.distortion.k2, 0.02);
  EXPECT_EQ(out.distortion.p1, 0.001);
  EXPECT_EQ(out.distortion.p2, -0.002);
  EXPECT_EQ(out.distortion.k3, 0.0);  // missing coefficients are zero
  EXPECT_EQ(out.camera_y_m, base.camera_y_m);
  EXPECT_EQ(out.tilt_rad, base.tilt_rad);
  EXPECT_EQ(out.laser_height_m, base.laser_height_m);
}

TEST(WithRobotIntrinsicsTest, TheRightEyeTakesItsOwnValidIntrinsicsElseTheSharedOnes) {
  const math::LaserCameraCalibration shared = Calibration();
  EXPECT_EQ(RightEyeCalibration(shared, std::nullopt).fx(), shared.fx());
  EXPECT_EQ(RightEyeCalibration(shared, Intrinsics(610)).fx(), 610);
  EXPECT_EQ(RightEyeCalibration(shared, Intrinsics(610)).camera_y_m, shared.camera_y_m);
  CameraIntrinsicsInfo other_size = Intrinsics(610);
  other_size.width_px = 1280;
  EXPECT_EQ(RightEyeCalibration(shared, other_size).fx(), shared.fx());
}

TEST(WithRobotIntrinsicsTest, ScalesTheNativeSizeIntoTheProfilesPixels) {
  // The same camera at 1280x960: twice the focal length, pixel centres at 2 (c + 0.5) - 0.5.
  CameraIntrinsicsInfo k = Intrinsics(1200);
  k.fy = 1204;
  k.cx = 2 * (321.5 + 0.5) - 0.5;
  k.cy = 2 * (238.25 + 0.5) - 0.5;
  k.width_px = 1280;
  k.height_px = 960;
  math::LaserCameraCalibration out;
  std::string error;
  ASSERT_TRUE(WithRobotIntrinsics(Calibration(), k, &out, &error)) << error;
  EXPECT_EQ(out.image_width_px, 640);
  EXPECT_EQ(out.image_height_px, 480);
  EXPECT_DOUBLE_EQ(out.fx(), 600);
  EXPECT_DOUBLE_EQ(out.fy(), 602);
  EXPECT_DOUBLE_EQ(out.cx(), 321.5);
  EXPECT_DOUBLE_EQ(out.cy(), 238.25);
  EXPECT_EQ(out.distortion.k1, -0.1);  // normalised coordinates: unchanged
}

TEST(WithRobotIntrinsicsTest, RefusesIntrinsicsOfAnotherAspectRatio) {
  CameraIntrinsicsInfo k = Intrinsics(600);
  k.width_px = 1280;
  k.height_px = 720;
  math::LaserCameraCalibration out = Calibration();
  std::string error;
  EXPECT_FALSE(WithRobotIntrinsics(Calibration(), k, &out, &error));
  EXPECT_EQ(error,
            "robot intrinsics are for 1280x720 images, not of the aspect ratio of 640x480: not "
            "used");
  EXPECT_EQ(out.focal_px, Calibration().focal_px);
}

TEST(WithRobotIntrinsicsTest, RefusesAnInvalidCalibration) {
  math::LaserCameraCalibration out = Calibration();
  std::string error;
  EXPECT_FALSE(WithRobotIntrinsics(Calibration(), Intrinsics(-5), &out, &error));
  EXPECT_EQ(error.rfind("robot intrinsics refused: ", 0), 0u) << error;
  EXPECT_EQ(out.focal_px, Calibration().focal_px);
}

TEST(IntrinsicsAdopterTest, AdoptsEachNewSetOnce) {
  IntrinsicsAdopter adopter;
  math::LaserCameraCalibration c = Calibration();
  EXPECT_EQ(adopter.Apply(std::nullopt, &c).outcome, IntrinsicsAdopter::Outcome::kNothingNew);
  const IntrinsicsAdopter::Result adopted = adopter.Apply(Intrinsics(600), &c);
  EXPECT_EQ(adopted.outcome, IntrinsicsAdopter::Outcome::kAdopted);
  EXPECT_NE(adopted.message.find("f 600/602 px"), std::string::npos) << adopted.message;
  EXPECT_NE(adopted.message.find("640x480"), std::string::npos) << adopted.message;
  EXPECT_EQ(c.focal_px, 600);
  // The operator edits the focal length: the same published set does not overwrite it again.
  c.focal_px = 555;
  EXPECT_EQ(adopter.Apply(Intrinsics(600), &c).outcome, IntrinsicsAdopter::Outcome::kNothingNew);
  EXPECT_EQ(c.focal_px, 555);
  // A new set (the robot recalibrated) is adopted.
  EXPECT_EQ(adopter.Apply(Intrinsics(610), &c).outcome, IntrinsicsAdopter::Outcome::kAdopted);
  EXPECT_EQ(c.focal_px, 610);
}

TEST(IntrinsicsAdopterTest, RefusesABadSetOnceAndKeepsTheCalibration) {
  IntrinsicsAdopter adopter;
  math::LaserCameraCalibration c = Calibration();
  CameraIntrinsicsInfo k = Intrinsics(600);
  k.width_px = 320;
  const IntrinsicsAdopter::Result refused = adopter.Apply(k, &c);
  EXPECT_EQ(refused.outcome, IntrinsicsAdopter::Outcome::kRefused);
  EXPECT_FALSE(refused.message.empty());
  EXPECT_EQ(c.focal_px, Calibration().focal_px);
  EXPECT_EQ(adopter.Apply(k, &c).outcome, IntrinsicsAdopter::Outcome::kNothingNew);
}

}  // namespace
}  // namespace mostar::ui
