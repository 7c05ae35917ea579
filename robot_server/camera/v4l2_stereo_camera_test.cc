#include "robot_server/camera/v4l2_stereo_camera.h"

#include <gtest/gtest.h>

namespace mostar::camera {
namespace {

TEST(V4l2StereoCameraTest, MissingDeviceGivesAClearError) {
  V4l2StereoCamera::Options options;
  options.left_device = "/dev/mostar-no-such-camera";
  options.right_device = "/dev/mostar-no-such-camera-either";
  V4l2StereoCamera camera(options);
  std::string error;
  EXPECT_FALSE(camera.Open(&error));
  EXPECT_NE(error.find("/dev/mostar-no-such-camera"), std::string::npos) << error;
  EXPECT_FALSE(camera.IsOpen());
  StereoImagePair pair;
  EXPECT_EQ(camera.Grab(std::chrono::milliseconds(1), &pair).status, GrabStatus::kNotOpen);
  EXPECT_EQ(camera.Info().backend, "v4l2");
  EXPECT_EQ(camera.Info().width_px, 640);
  camera.Close();  // idempotent
}

TEST(V4l2StereoCameraTest, InvalidPairingOptionsAreRefused) {
  V4l2StereoCamera::Options options;
  options.pairing.max_pending = 0;
  V4l2StereoCamera camera(options);
  std::string error;
  EXPECT_FALSE(camera.Open(&error));
  EXPECT_NE(error.find("max_pending"), std::string::npos) << error;
}

}  // namespace
}  // namespace mostar::camera
