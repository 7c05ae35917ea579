#include "robot_server/camera/camera_intrinsics.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace mostar::camera {
namespace {

namespace fs = std::filesystem;

CameraIntrinsics Example() {
  CameraIntrinsics intrinsics;
  intrinsics.image_size = cv::Size(640, 480);
  intrinsics.camera_matrix = cv::Matx33d(520.5, 0, 319.2, 0, 521.0, 241.7, 0, 0, 1);
  intrinsics.distortion = {-0.28, 0.09, 0.001, -0.0005, 0.0};
  return intrinsics;
}

class CameraIntrinsicsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "mostar_intrinsics_XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  fs::path dir_;
};

TEST_F(CameraIntrinsicsTest, SaveAndLoadRoundTrip) {
  for (const char* name : {"left.yaml", "left.xml"}) {
    const std::string path = (dir_ / name).string();
    std::string error;
    ASSERT_TRUE(SaveCameraIntrinsics(path, Example(), &error)) << error;
    CameraIntrinsics loaded;
    ASSERT_TRUE(LoadCameraIntrinsics(path, &loaded, &error)) << error;
    EXPECT_EQ(loaded.image_size, cv::Size(640, 480));
    EXPECT_EQ(loaded.camera_matrix, Example().camera_matrix);
    EXPECT_EQ(loaded.distortion, Example().distortion);
  }
}

TEST_F(CameraIntrinsicsTest, ShippedExampleFilesLoad) {
  const char* source = std::getenv("MOSTAR_SOURCE_DIR");
  ASSERT_NE(source, nullptr) << "MOSTAR_SOURCE_DIR is set by CTest";
  for (const char* eye : {"left", "right"}) {
    const std::string path =
        std::string(source) + "/deploy/calibration/camera_" + eye + "_640x480.yaml";
    CameraIntrinsics loaded;
    std::string error;
    ASSERT_TRUE(LoadCameraIntrinsics(path, &loaded, &error)) << error;
    EXPECT_EQ(loaded.image_size, cv::Size(640, 480));
    EXPECT_EQ(loaded.distortion.size(), 5u);
  }
}

TEST_F(CameraIntrinsicsTest, MissingFileIsAClearError) {
  CameraIntrinsics loaded;
  std::string error;
  EXPECT_FALSE(LoadCameraIntrinsics((dir_ / "nope.yaml").string(), &loaded, &error));
  EXPECT_NE(error.find("nope.yaml"), std::string::npos);
  EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
}

TEST_F(CameraIntrinsicsTest, UnparsableFileIsAClearError) {
  const std::string path = Write("bad.yaml", "%YAML:1.0\ncamera_matrix: [1, 2\n  : : :\n");
  CameraIntrinsics loaded;
  std::string error;
  EXPECT_FALSE(LoadCameraIntrinsics(path, &loaded, &error));
  EXPECT_NE(error.find("bad.yaml"), std::string::npos) << error;
}

TEST_F(CameraIntrinsicsTest, MissingKeysAndBadValuesAreNamed) {
  CameraIntrinsics loaded;
  std::string error;
  const std::string no_size =
      Write("no_size.yaml",
            "%YAML:1.0\n---\ncamera_matrix: !!opencv-matrix\n  rows: 3\n"
            "  cols: 3\n  dt: d\n  data: [500, 0, 320, 0, 500, 240, 0, 0, 1]\n");
  EXPECT_FALSE(LoadCameraIntrinsics(no_size, &loaded, &error));
  EXPECT_NE(error.find("image_width"), std::string::npos) << error;

  const std::string negative_focal =
      Write("negative.yaml",
            "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\ncamera_matrix: !!opencv-matrix\n"
            "  rows: 3\n  cols: 3\n  dt: d\n  data: [-500, 0, 320, 0, 500, 240, 0, 0, 1]\n");
  EXPECT_FALSE(LoadCameraIntrinsics(negative_focal, &loaded, &error));
  EXPECT_NE(error.find("fx and fy"), std::string::npos) << error;

  const std::string no_matrix =
      Write("no_matrix.yaml", "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n");
  EXPECT_FALSE(LoadCameraIntrinsics(no_matrix, &loaded, &error));
  EXPECT_NE(error.find("camera_matrix"), std::string::npos) << error;
}

TEST(CameraIntrinsicsScaleTest, HalfResolutionHalvesFocalLengthAndKeepsPixelCentres) {
  const CameraIntrinsics half = Example().ScaledTo(cv::Size(320, 240));
  EXPECT_EQ(half.image_size, cv::Size(320, 240));
  EXPECT_DOUBLE_EQ(half.camera_matrix(0, 0), 520.5 / 2);
  EXPECT_DOUBLE_EQ(half.camera_matrix(1, 1), 521.0 / 2);
  EXPECT_DOUBLE_EQ(half.camera_matrix(0, 2), (319.2 + 0.5) / 2 - 0.5);
  EXPECT_EQ(half.distortion, Example().distortion);
  std::string error;
  EXPECT_TRUE(half.IsValid(&error)) << error;
}

}  // namespace
}  // namespace mostar::camera
