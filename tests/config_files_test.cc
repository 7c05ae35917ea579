// Every configuration file shipped in deploy/ loads and validates with its schema. A new file
// must be registered here (an unknown file fails the test), so no shipped file goes untested.
#include <dirent.h>
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "common/config/config_loader.h"
#include "common/math/calibration_io.h"
#include "operator_client/client_config.pb.h"
#include "operator_client/vision/vision_pipeline.h"
#include "robot_server/camera/camera_config.pb.h"
#include "robot_server/camera/camera_factory.h"
#include "robot_server/drive/drive_config.h"
#include "robot_server/drive/drive_config.pb.h"
#include "robot_server/laser/lms200_config.pb.h"
#include "robot_server/laser/lms200_session.h"
#include "robot_server/server_config.pb.h"
#include "robot_server/sim/scene.h"
#include "robot_server/sim/sim_world.h"
#include "robot_server/sonar/sonar_config.h"

namespace mostar {
namespace {

std::vector<std::string> ListDir(const std::string& dir, const std::string& suffix) {
  std::vector<std::string> names;
  if (DIR* d = opendir(dir.c_str())) {
    while (dirent* e = readdir(d)) {
      const std::string name = e->d_name;
      if (name.size() > suffix.size() &&
          name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
        names.push_back(name);
      }
    }
    closedir(d);
  }
  return names;
}

bool StartsWith(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

// Loads `path` as the schema its name announces; false with the error.
bool LoadShippedConfig(const std::string& name, const std::string& path, std::string* error) {
  if (StartsWith(name, "server_")) {
    server::ServerConfig c;
    if (!LoadTextConfig(path, &c, error)) return false;
    drive::DriveSettings settings;
    if (!drive::DriveSettingsFromProto(c.drive(), &settings, error)) return false;
    if (!laser::ValidateLms200Config(c.laser(), error)) return false;
    sonar::Srf08RingOptions sonar;
    if (c.sonar().sensors_size() > 0 &&
        !sonar::Srf08RingOptionsFromConfig(c.sonar(), &sonar, error)) {
      return false;
    }
    return sim::ValidateSimConfig(c.sim(), path, error);
  }
  if (StartsWith(name, "sonar_")) {
    sonar::SonarConfig c;
    sonar::Srf08RingOptions options;
    return LoadTextConfig(path, &c, error) && sonar::Srf08RingOptionsFromConfig(c, &options, error);
  }
  if (StartsWith(name, "calibration_")) {
    math::LaserCameraCalibration c;
    return math::LoadCalibrationProfile(path, &c, error);
  }
  if (StartsWith(name, "camera_")) {
    camera::CameraConfig c;
    return LoadTextConfig(path, &c, error) && camera::ValidateCameraConfig(c, error);
  }
  if (StartsWith(name, "drive_")) {
    drive::DriveConfig c;
    drive::DriveSettings settings;
    return LoadTextConfig(path, &c, error) && drive::DriveSettingsFromProto(c, &settings, error);
  }
  if (StartsWith(name, "sim_")) {
    sim::proto::SimConfig c;
    return sim::LoadSimConfig(path, &c, error);
  }
  if (StartsWith(name, "client_")) {
    client::ClientConfig c;
    if (!LoadTextConfig(path, &c, error)) return false;
    math::LaserCameraCalibration calibration;
    const std::string dir = path.substr(0, path.rfind('/'));
    return !c.has_calibration_profile() ||
           math::LoadCalibrationProfile(dir + "/" + c.calibration_profile(), &calibration, error);
  }
  if (StartsWith(name, "lms200_")) {
    laser::Lms200Config c;
    return LoadTextConfig(path, &c, error);
  }
  *error = name + ": no schema registered for this file name (tests/config_files_test.cc)";
  return false;
}

TEST(ShippedConfigTest, EveryConfigFileLoads) {
  const std::string dir = std::string(MOSTAR_TEST_SOURCE_DIR) + "/deploy/config";
  const auto names = ListDir(dir, ".pbtxt");
  ASSERT_GE(names.size(), 5u) << "no configuration files found in " << dir;
  for (const std::string& name : names) {
    std::string error;
    EXPECT_TRUE(LoadShippedConfig(name, dir + "/" + name, &error)) << error;
  }
}

TEST(ShippedConfigTest, EverySceneLoads) {
  const std::string dir = std::string(MOSTAR_TEST_SOURCE_DIR) + "/deploy/scenes";
  const auto names = ListDir(dir, ".pbtxt");
  ASSERT_GE(names.size(), 3u);
  for (const std::string& name : names) {
    sim::proto::Scene scene;
    std::string error;
    EXPECT_TRUE(sim::LoadScene(dir + "/" + name, &scene, &error)) << error;
  }
}

TEST(ShippedConfigTest, UnknownFileNamesAreRefused) {
  std::string error;
  EXPECT_FALSE(LoadShippedConfig("mystery.pbtxt", "/dev/null", &error));
  EXPECT_NE(error.find("no schema"), std::string::npos);
}

// client_thesis.pbtxt: the thesis' algorithm with every extension off (docs/vision.md).
TEST(ShippedConfigTest, ThesisClientTurnsEveryExtensionOff) {
  const std::string dir = std::string(MOSTAR_TEST_SOURCE_DIR) + "/deploy/config";
  client::ClientConfig c;
  std::string error;
  ASSERT_TRUE(LoadTextConfig(dir + "/client_thesis.pbtxt", &c, &error)) << error;
  EXPECT_FALSE(c.intrinsics_from_robot());
  EXPECT_FALSE(c.ar().motion_compensation());
  EXPECT_FALSE(c.self_calibration().enabled());
  math::LaserCameraCalibration calibration;
  ASSERT_TRUE(
      math::LoadCalibrationProfile(dir + "/" + c.calibration_profile(), &calibration, &error))
      << error;
  EXPECT_TRUE(calibration.distortion.IsZero());
  EXPECT_FALSE(calibration.principal_x_px.has_value() || calibration.principal_y_px.has_value() ||
               calibration.focal_y_px.has_value());
  const vision::VisionOptions v = vision::FromProto(c.vision());
  ASSERT_TRUE(v.IsValid(&error)) << error;
  EXPECT_FALSE(v.edges.colour_edges);
  EXPECT_EQ(v.nearest_edge.base_search_m, 0.0);
  EXPECT_EQ(v.nearest_edge.min_step_grey, 0);
  EXPECT_EQ(v.nearest_edge.min_crossing_angle_deg, 0.0);
  EXPECT_EQ(v.nearest_edge.start_grey_deviation, 0);
  EXPECT_FALSE(v.nearest_edge.floor_stereo.enabled);
  EXPECT_EQ(v.nearest_edge.lateral_tolerance_px, 0);
  EXPECT_EQ(v.classifier.min_threshold_px, 0.0);
  EXPECT_EQ(v.nesc.min_threshold_px, 0.0);
  EXPECT_EQ(v.classifier.neighbour_beams, 0);
  EXPECT_EQ(v.classifier.min_obstacle_beams, 1);
  EXPECT_TRUE(v.stereo);
  EXPECT_DOUBLE_EQ(v.classifier.edge_threshold_m, 0.10);
  EXPECT_DOUBLE_EQ(v.nesc.stereo_threshold_m, 0.5 * v.classifier.edge_threshold_m);
}

}  // namespace
}  // namespace mostar
