#include "robot_server/camera/dc1394_stereo_camera.h"

#include <gtest/gtest.h>

namespace mostar::camera {
namespace {

// There is no FireWire bus (or no cameras on it) where the tests run.
TEST(Dc1394StereoCameraTest, NoBusOrCameraGivesAClearError) {
  Dc1394StereoCamera camera({});
  std::string error;
  EXPECT_FALSE(camera.Open(&error));
  EXPECT_NE(error.find("no IEEE1394 camera found"), std::string::npos) << error;
  EXPECT_FALSE(camera.IsOpen());
  StereoImagePair pair;
  EXPECT_EQ(camera.Grab(std::chrono::milliseconds(1), &pair).status, GrabStatus::kNotOpen);
  EXPECT_EQ(camera.Info().backend, "dc1394");
  camera.Close();
  EXPECT_FALSE(camera.Open(&error));  // retrying is safe
}

}  // namespace
}  // namespace mostar::camera
