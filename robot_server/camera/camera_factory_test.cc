#include "robot_server/camera/camera_factory.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "common/config/config_loader.h"
#include "common/time/fake_clock.h"

namespace mostar::camera {
namespace {

namespace fs = std::filesystem;

std::string SourceDir() {
  const char* source = std::getenv("MOSTAR_SOURCE_DIR");
  return source != nullptr ? source : ".";
}

TEST(CameraFactoryTest, EveryShippedCameraConfigLoadsAndValidates) {
  int files = 0;
  for (const auto& entry : fs::directory_iterator(SourceDir() + "/deploy/config")) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("camera_", 0) != 0 || entry.path().extension() != ".pbtxt") continue;
    ++files;
    CameraConfig config;
    std::string error;
    ASSERT_TRUE(LoadTextConfig(entry.path().string(), &config, &error)) << error;
    EXPECT_TRUE(ValidateCameraConfig(config, &error)) << name << ": " << error;
    CameraPipelineOptions options = MakePipelineOptions(config);
    EXPECT_TRUE(options.IsValid(&error)) << name << ": " << error;
    for (const std::string& file :
         {config.left_intrinsics_file(), config.right_intrinsics_file()}) {
      if (!file.empty()) {
        EXPECT_TRUE(fs::exists(SourceDir() + "/" + file)) << name << ": " << file;
      }
    }
  }
  EXPECT_GE(files, 3);
}

TEST(CameraFactoryTest, BuildsEachBackendWithoutOpeningIt) {
  FakeClock clock;
  std::string error;
  CameraConfig config;
  config.set_backend(CameraConfig::FAKE);
  auto fake = MakeStereoCamera(config, &clock, &error);
  ASSERT_NE(fake, nullptr) << error;
  EXPECT_EQ(fake->Info().backend, "fake");
  EXPECT_FALSE(fake->IsOpen());

  config.set_backend(CameraConfig::V4L2);
  auto v4l2 = MakeStereoCamera(config, &clock, &error);
  ASSERT_NE(v4l2, nullptr) << error;
  EXPECT_EQ(v4l2->Info().backend, "v4l2");
  EXPECT_EQ(v4l2->Info().left_device, "/dev/mostar-camera-left");

  config.set_backend(CameraConfig::SIM);
  EXPECT_EQ(MakeStereoCamera(config, &clock, &error), nullptr);
  EXPECT_NE(error.find("SIM"), std::string::npos);
}

TEST(CameraFactoryTest, FileBackendNeedsItsSources) {
  FakeClock clock;
  std::string error;
  CameraConfig config;
  config.set_backend(CameraConfig::FILE);
  EXPECT_EQ(MakeStereoCamera(config, &clock, &error), nullptr);
  EXPECT_NE(error.find("file.left"), std::string::npos) << error;
  config.mutable_file()->set_left("a_*.png");
  EXPECT_EQ(MakeStereoCamera(config, &clock, &error), nullptr);
  EXPECT_NE(error.find("file.right"), std::string::npos) << error;
}

TEST(CameraFactoryTest, PipelineOptionsFollowTheBitrateClasses) {
  CameraConfig config;
  std::string error;
  ASSERT_TRUE(ParseTextConfig(R"(
      jpeg_quality: 70
      bitrate {
        initial_class: "wan"
        classes { name: "lan" target_bits_per_s: 0 }
        classes { name: "wan" target_bits_per_s: 4000000 }
        scales: [1.0, 0.5]
      })",
                              "inline", &config, &error))
      << error;
  const CameraPipelineOptions options = MakePipelineOptions(config);
  EXPECT_EQ(options.bitrate.target_bits_per_s, 4e6);
  EXPECT_EQ(options.bitrate.initial_quality, 70);
  EXPECT_EQ(options.bitrate.scales, (std::vector<double>{1.0, 0.5}));
  EXPECT_EQ(options.bitrate_classes.size(), 2u);

  config.mutable_bitrate()->set_initial_class("moon");
  EXPECT_FALSE(ValidateCameraConfig(config, &error));
  EXPECT_NE(error.find("initial_class"), std::string::npos);
}

TEST(CameraFactoryTest, OutOfRangeValuesAreRefusedByTheLoader) {
  CameraConfig config;
  std::string error;
  EXPECT_FALSE(ParseTextConfig("jpeg_quality: 150", "inline", &config, &error));
  EXPECT_NE(error.find("jpeg_quality"), std::string::npos) << error;
}

}  // namespace
}  // namespace mostar::camera
