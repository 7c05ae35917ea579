#include "common/math/calibration_io.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "common/config/config_loader.h"

namespace mostar::math {
namespace {

// The repository root: MOSTAR_SOURCE_DIR when the test runner sets it, else the build's
// MOSTAR_TEST_SOURCE_DIR, else derived from this file's path.
std::string SourceDir() {
  const char* dir = std::getenv("MOSTAR_SOURCE_DIR");
  if (dir != nullptr && *dir != '\0') return dir;
#ifdef MOSTAR_TEST_SOURCE_DIR
  return MOSTAR_TEST_SOURCE_DIR;
#else
  const std::string file = __FILE__;
  const std::string suffix = "common/math/calibration_io_test.cc";
  if (file.size() > suffix.size() &&
      file.compare(file.size() - suffix.size(), suffix.size(), suffix) == 0) {
    return file.substr(0, file.size() - suffix.size());
  }
  return ".";
#endif
}

void ExpectEqual(const LaserCameraCalibration& a, const LaserCameraCalibration& b) {
  EXPECT_EQ(a.image_width_px, b.image_width_px);
  EXPECT_EQ(a.image_height_px, b.image_height_px);
  EXPECT_EQ(a.focal_px, b.focal_px);
  EXPECT_EQ(a.focal_y_px, b.focal_y_px);
  EXPECT_EQ(a.principal_x_px, b.principal_x_px);
  EXPECT_EQ(a.principal_y_px, b.principal_y_px);
  EXPECT_EQ(a.distortion.k1, b.distortion.k1);
  EXPECT_EQ(a.distortion.k2, b.distortion.k2);
  EXPECT_EQ(a.distortion.p1, b.distortion.p1);
  EXPECT_EQ(a.distortion.p2, b.distortion.p2);
  EXPECT_EQ(a.distortion.k3, b.distortion.k3);
  EXPECT_EQ(a.camera_x_m, b.camera_x_m);
  EXPECT_EQ(a.camera_y_m, b.camera_y_m);
  EXPECT_EQ(a.camera_z_m, b.camera_z_m);
  EXPECT_EQ(a.tilt_rad, b.tilt_rad);
  EXPECT_EQ(a.pan_rad, b.pan_rad);
  EXPECT_EQ(a.roll_rad, b.roll_rad);
  EXPECT_EQ(a.left_eye_x_offset_m, b.left_eye_x_offset_m);
  EXPECT_EQ(a.right_eye_x_offset_m, b.right_eye_x_offset_m);
  EXPECT_EQ(a.laser_height_m, b.laser_height_m);
}

TEST(CalibrationIoTest, ProtoDefaultsEqualStructDefaults) {
  LaserCameraCalibration from_empty;
  from_empty.focal_px = 1.0;  // must be overwritten
  std::string error;
  ASSERT_TRUE(FromProto(proto::LaserCameraCalibration(), &from_empty, &error)) << error;
  ExpectEqual(from_empty, LaserCameraCalibration{});
}

TEST(CalibrationIoTest, RoundTripsThroughProto) {
  LaserCameraCalibration calibration;
  calibration.focal_px = 610.25;
  calibration.focal_y_px = 612.5;
  calibration.principal_x_px = 330.0;
  calibration.principal_y_px = 241.0;
  calibration.distortion = {-0.2, 0.05, 0.001, -0.002, 0.003};
  calibration.camera_x_m = 0.015;
  calibration.camera_y_m = 0.6;
  calibration.camera_z_m = 0.05;
  calibration.tilt_rad = 0.3;
  calibration.pan_rad = -0.1;
  calibration.roll_rad = 0.02;
  calibration.left_eye_x_offset_m = -0.07;
  calibration.right_eye_x_offset_m = 0.05;
  calibration.laser_height_m = 0.35;
  const proto::LaserCameraCalibration message = ToProto(calibration, "bench");
  EXPECT_EQ(message.name(), "bench");
  LaserCameraCalibration back;
  std::string error;
  ASSERT_TRUE(FromProto(message, &back, &error)) << error;
  ExpectEqual(back, calibration);
  // Unset optional intrinsics stay unset.
  EXPECT_FALSE(ToProto(LaserCameraCalibration{}).has_focal_y_px());
  EXPECT_FALSE(ToProto(LaserCameraCalibration{}).has_principal_x_px());
}

TEST(CalibrationIoTest, RefusesInvalidProfilesAndKeepsTheOldValue) {
  proto::LaserCameraCalibration message;
  message.set_left_eye_x_offset_m(0.1);
  message.set_right_eye_x_offset_m(-0.1);
  LaserCameraCalibration calibration;
  calibration.focal_px = 700.0;
  std::string error;
  EXPECT_FALSE(FromProto(message, &calibration, &error));
  EXPECT_NE(error.find("left eye is on the left"), std::string::npos) << error;
  EXPECT_EQ(calibration.focal_px, 700.0);

  message.Clear();
  message.set_tilt_rad(2.0);
  EXPECT_FALSE(FromProto(message, &calibration, &error));
  EXPECT_NE(error.find("tilt_rad"), std::string::npos) << error;
}

TEST(CalibrationIoTest, TextRangeErrorsNameTheKey) {
  proto::LaserCameraCalibration message;
  std::string error;
  EXPECT_FALSE(ParseTextConfig("focal_px: -5", "profile.pbtxt", &message, &error));
  EXPECT_NE(error.find("focal_px"), std::string::npos) << error;
}

TEST(CalibrationIoTest, LoadsTheShippedMorducProfile) {
  const std::string path = SourceDir() + "/deploy/config/calibration_morduc.pbtxt";
  LaserCameraCalibration calibration;
  std::string error;
  ASSERT_TRUE(LoadCalibrationProfile(path, &calibration, &error)) << error;
  EXPECT_NEAR(calibration.laser_height_m + calibration.camera_y_m, 0.95, 1e-9);
  EXPECT_NEAR(calibration.tilt_rad, 12.0 * 3.14159265358979 / 180.0, 1e-4);
  EXPECT_NEAR(calibration.baseline_m(), 0.12, 1e-9);
  EXPECT_EQ(calibration.image_width_px, 640);
  EXPECT_EQ(calibration.image_height_px, 480);
  EXPECT_EQ(calibration.focal_px, 525.0);
}

TEST(CalibrationIoTest, SavedProfileLoadsBack) {
  LaserCameraCalibration calibration;
  calibration.camera_x_m = 0.012;
  calibration.tilt_rad = 0.25;
  calibration.principal_x_px = 318.0;
  const std::string path = ::testing::TempDir() + "calibration_io_test_profile.pbtxt";
  std::string error;
  ASSERT_TRUE(SaveCalibrationProfile(path, calibration, "saved", &error)) << error;
  LaserCameraCalibration back;
  ASSERT_TRUE(LoadCalibrationProfile(path, &back, &error)) << error;
  ExpectEqual(back, calibration);
  std::remove(path.c_str());

  calibration.focal_px = -1.0;
  EXPECT_FALSE(SaveCalibrationProfile(path, calibration, "bad", &error));
  EXPECT_NE(error.find("focal_px"), std::string::npos) << error;
}

TEST(CalibrationIoTest, StereoAlignmentIsSavedBesideTheCalibration) {
  LaserCameraCalibration calibration;
  calibration.focal_px = 440.0;
  StereoAlignmentProfile alignment;
  alignment.per_eye_intrinsics = true;
  alignment.right_offset_x_px = -1.5;
  alignment.right_offset_y_px = -5.0;
  alignment.crop_right_px = 1.5;
  alignment.crop_bottom_px = 5.0;
  const std::string path = ::testing::TempDir() + "calibration_io_test_alignment.pbtxt";
  std::string error;
  ASSERT_TRUE(SaveCalibrationProfile(path, calibration, alignment, "aligned", &error)) << error;
  LaserCameraCalibration back;
  StereoAlignmentProfile alignment_back;
  ASSERT_TRUE(LoadCalibrationProfile(path, &back, &alignment_back, &error)) << error;
  ExpectEqual(back, calibration);
  EXPECT_TRUE(alignment_back == alignment);
  // The calibration alone still loads from a profile with an alignment.
  LaserCameraCalibration only;
  ASSERT_TRUE(LoadCalibrationProfile(path, &only, &error)) << error;
  ExpectEqual(only, calibration);
  std::remove(path.c_str());
}

TEST(CalibrationIoTest, ProfileWithoutAlignmentLoadsNone) {
  StereoAlignmentProfile alignment;
  alignment.right_offset_y_px = 3.0;
  LaserCameraCalibration calibration;
  std::string error;
  ASSERT_TRUE(LoadCalibrationProfile(SourceDir() + "/deploy/config/calibration_morduc.pbtxt",
                                     &calibration, &alignment, &error))
      << error;
  EXPECT_TRUE(alignment == StereoAlignmentProfile{});
}

TEST(CalibrationIoTest, MissingFileIsAnError) {
  LaserCameraCalibration calibration;
  std::string error;
  EXPECT_FALSE(LoadCalibrationProfile("no/such/profile.pbtxt", &calibration, &error));
  EXPECT_FALSE(error.empty());
}

}  // namespace
}  // namespace mostar::math
