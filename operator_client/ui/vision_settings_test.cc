#include "operator_client/ui/vision_settings.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

namespace mostar::ui {
namespace {

TEST(VisionSettingsTest, StereoThresholdFollowsEdgeThresholdByDefault) {
  VisionSettings settings{vision::VisionOptions{}};
  ASSERT_TRUE(settings.stereo_follows_edge());
  std::string error;
  ASSERT_TRUE(settings.SetEdgeThreshold(0.20, &error)) << error;
  EXPECT_DOUBLE_EQ(settings.options().classifier.edge_threshold_m, 0.20);
  EXPECT_DOUBLE_EQ(settings.options().nesc.stereo_threshold_m, 0.10);
}

TEST(VisionSettingsTest, StereoThresholdSetOnItsOwnStaysPut) {
  VisionSettings settings{vision::VisionOptions{}};
  std::string error;
  ASSERT_TRUE(settings.SetStereoThreshold(0.03, &error)) << error;
  EXPECT_FALSE(settings.stereo_follows_edge());
  ASSERT_TRUE(settings.SetEdgeThreshold(0.30, &error)) << error;
  EXPECT_DOUBLE_EQ(settings.options().nesc.stereo_threshold_m, 0.03);
  ASSERT_TRUE(settings.FollowEdgeThreshold(&error)) << error;
  EXPECT_TRUE(settings.stereo_follows_edge());
  EXPECT_DOUBLE_EQ(settings.options().nesc.stereo_threshold_m, 0.15);
}

TEST(VisionSettingsTest, ConfiguredStereoThresholdOtherThanHalfIsOwn) {
  vision::VisionOptions options;
  options.nesc.stereo_threshold_m = 0.02;
  VisionSettings settings{options};
  EXPECT_FALSE(settings.stereo_follows_edge());
  std::string error;
  ASSERT_TRUE(settings.SetEdgeThreshold(0.2, &error)) << error;
  EXPECT_DOUBLE_EQ(settings.options().nesc.stereo_threshold_m, 0.02);
}

TEST(VisionSettingsTest, InvalidEditsChangeNothing) {
  VisionSettings settings{vision::VisionOptions{}};
  std::string error;
  EXPECT_FALSE(settings.SetStereoThreshold(-1.0, &error));
  EXPECT_NE(error.find("stereo_threshold_m"), std::string::npos) << error;
  EXPECT_TRUE(settings.stereo_follows_edge());
  EXPECT_DOUBLE_EQ(settings.options().nesc.stereo_threshold_m, 0.05);
}

TEST(VisionSettingsTest, SavedSettingsLoadBackWithTheRelation) {
  const std::string path = ::testing::TempDir() + "vision_settings_test.vision.pbtxt";
  std::string error;
  VisionSettings following{vision::VisionOptions{}};
  ASSERT_TRUE(following.SetEdgeThreshold(0.16, &error)) << error;
  vision::VisionOptions edges = following.options();
  edges.edges.canny_threshold2 = 222;
  ASSERT_TRUE(following.Set(edges, &error)) << error;
  ASSERT_TRUE(following.Save(path, &error)) << error;
  VisionSettings loaded{vision::VisionOptions{}};
  ASSERT_TRUE(loaded.SetStereoThreshold(0.01, &error)) << error;
  ASSERT_TRUE(loaded.Load(path, &error)) << error;
  EXPECT_TRUE(loaded.stereo_follows_edge());
  EXPECT_DOUBLE_EQ(loaded.options().nesc.stereo_threshold_m, 0.08);
  EXPECT_DOUBLE_EQ(loaded.options().edges.canny_threshold2, 222);

  VisionSettings own{vision::VisionOptions{}};
  ASSERT_TRUE(own.SetStereoThreshold(0.04, &error)) << error;
  ASSERT_TRUE(own.Save(path, &error)) << error;
  ASSERT_TRUE(loaded.Load(path, &error)) << error;
  EXPECT_FALSE(loaded.stereo_follows_edge());
  EXPECT_DOUBLE_EQ(loaded.options().nesc.stereo_threshold_m, 0.04);
  std::remove(path.c_str());
}

TEST(VisionSettingsTest, LoadRefusesABadFileAndKeepsTheSettings) {
  const std::string path = ::testing::TempDir() + "vision_settings_bad.vision.pbtxt";
  std::ofstream(path) << "edge_threshold_m: -3\n";
  VisionSettings settings{vision::VisionOptions{}};
  std::string error;
  EXPECT_FALSE(settings.Load(path, &error));
  EXPECT_NE(error.find("edge_threshold_m"), std::string::npos) << error;
  EXPECT_DOUBLE_EQ(settings.options().classifier.edge_threshold_m, 0.10);
  std::remove(path.c_str());
}

TEST(VisionSettingsTest, PathSitsBesideTheCalibrationProfile) {
  EXPECT_EQ(VisionSettingsPath("/etc/mostar/calibration.pbtxt"),
            "/etc/mostar/calibration.vision.pbtxt");
  EXPECT_EQ(VisionSettingsPath(""), "calibration_profile.vision.pbtxt");
  EXPECT_EQ(VisionSettingsPath("profile"), "profile.vision.pbtxt");
}

}  // namespace
}  // namespace mostar::ui
