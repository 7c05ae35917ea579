// The native resolution path: a 1280x960 simulated pair through the robot's JPEG compressor,
// the client's receiver decoding at the displayed size (DCT scaling), the calibration scaled to
// the decoded images, and the edge processing on them, against the same simulator at 640x480.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "operator_client/ui/decode_scaling.h"
#include "operator_client/ui/intrinsics_adoption.h"
#include "operator_client/video/stereo_receiver.h"
#include "operator_client/vision/vision_pipeline.h"
#include "robot_server/camera/jpeg_compressor.h"
#include "robot_server/sim/sim_world.h"
#include "tests/vision/sim_calibration.h"

namespace mostar {
namespace {

const Time kStart = FromUnixNanos(1'700'000'000'000'000'000);

// The simulator with cameras of `width` x 3/4 width (the same lens: focal length follows).
std::unique_ptr<sim::SimWorld> World(int width) {
  sim::proto::Scene scene;
  std::string error;
  EXPECT_TRUE(vision::LoadSimScene("open_room", &scene, &error)) << error;
  sim::proto::SimConfig config;
  config.mutable_laser()->set_resolution(sim::proto::LaserConfig::RES_1_DEG);
  config.mutable_camera()->set_width_px(width);
  config.mutable_camera()->set_height_px(width * 3 / 4);
  config.mutable_camera()->set_focal_px(440.0 * width / 640);
  auto world = sim::SimWorld::Create(scene, config, kStart, &error);
  EXPECT_NE(world, nullptr) << error;
  return world;
}

template <class Predicate>
bool WaitFor(Predicate predicate) {
  for (int i = 0; i < 1000 && !predicate(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return predicate();
}

vision::VisionResult RunVision(const cv::Mat& left, const cv::Mat& right,
                               const math::LaserCameraCalibration& left_calibration,
                               const math::LaserCameraCalibration& right_calibration,
                               const LaserScan& scan) {
  vision::VisionInput input;
  input.left = left;
  input.right = right;
  input.scan = scan;
  input.left_camera = std::make_shared<const math::CameraModel>(left_calibration, Eye::kLeft);
  input.right_camera = std::make_shared<const math::CameraModel>(right_calibration, Eye::kRight);
  vision::VisionPipeline pipeline{vision::VisionOptions{}};
  vision::VisionResult result;
  pipeline.Process(input, &result);
  return result;
}

TEST(NativeResolutionTest, A1280x960PairIsDecodedAtTheDisplayedSizeWithScaledIntrinsics) {
  const auto world = World(1280);
  ASSERT_NE(world, nullptr);
  const sim::StereoImages rendered = world->StereoAt(kStart, false);
  ASSERT_EQ(rendered.left.cols, 1280);
  ASSERT_EQ(rendered.left.rows, 960);
  camera::StereoImagePair pair;
  pair.stamp = kStart;
  pair.left = rendered.left;
  pair.right = rendered.right;
  camera::JpegCompressor compressor(true);
  CompressedStereoPair jpeg;
  std::string error;
  ASSERT_TRUE(compressor.Compress(pair, {80, 1.0}, &jpeg, &error)) << error;

  // An anaglyph window of 640x480: both eyes, each shown at 640x480.
  client::StereoReceiver receiver;
  receiver.SetExpectedSize(Eye::kLeft, 1280, 960);
  receiver.SetExpectedSize(Eye::kRight, 1280, 960);
  receiver.SetDecodeTarget(ui::DecodeTargetFor(render::DisplayMode::kAnaglyphGrey, 640, 480,
                                               /*vision_enabled=*/true, /*vision_stereo=*/true));
  receiver.Push(Eye::kLeft, jpeg.left);
  receiver.Push(Eye::kRight, jpeg.right);
  ASSERT_TRUE(WaitFor([&] { return receiver.Latest().has_value(); }));
  const client::DecodedStereoPair decoded = *receiver.Latest();
  EXPECT_EQ(decoded.scale_denominator, 2);
  EXPECT_EQ(decoded.source_width_px, 1280);
  EXPECT_EQ(decoded.source_height_px, 960);
  ASSERT_EQ(decoded.left.cols, 640);
  ASSERT_EQ(decoded.left.rows, 480);
  ASSERT_EQ(decoded.right.cols, 640);
  ASSERT_EQ(decoded.right.rows, 480);
  EXPECT_EQ(receiver.Stats().scaled_decodes, 2u);

  // The client's calibration (the native size) scaled to the decoded images is the simulator's
  // 640x480 camera.
  const double laser_height_m = world->laser_params().height_m;
  const auto full_left =
      vision::MathCalibrationFromSim(world->calibration(), Eye::kLeft, laser_height_m);
  const auto full_right =
      vision::MathCalibrationFromSim(world->calibration(), Eye::kRight, laser_height_m);
  const ui::ImageScale scale = ui::ScaleOfPair(full_left, decoded, {});
  const math::LaserCameraCalibration left = ui::ScaledCalibration(full_left, scale);
  const math::LaserCameraCalibration right = ui::ScaledCalibration(full_right, scale);
  const auto small_world = World(640);
  ASSERT_NE(small_world, nullptr);
  const auto expected =
      vision::MathCalibrationFromSim(small_world->calibration(), Eye::kLeft, laser_height_m);
  EXPECT_EQ(left.image_width_px, 640);
  EXPECT_EQ(left.image_height_px, 480);
  EXPECT_DOUBLE_EQ(left.fx(), expected.fx());
  EXPECT_DOUBLE_EQ(left.fy(), expected.fy());
  EXPECT_DOUBLE_EQ(left.cx(), expected.cx());
  EXPECT_DOUBLE_EQ(left.cy(), expected.cy());

  // The robot's CameraInfo for 1280x960 adopted into a 640x480 profile gives the same numbers.
  CameraIntrinsicsInfo k;
  k.width_px = 1280;
  k.height_px = 960;
  k.fx = full_left.fx();
  k.fy = full_left.fy();
  k.cx = full_left.cx();
  k.cy = full_left.cy();
  math::LaserCameraCalibration adopted;
  ASSERT_TRUE(ui::WithRobotIntrinsics(expected, k, &adopted, &error)) << error;
  EXPECT_DOUBLE_EQ(adopted.fx(), expected.fx());
  EXPECT_DOUBLE_EQ(adopted.cx(), expected.cx());
  EXPECT_DOUBLE_EQ(adopted.cy(), expected.cy());

  // Edge processing works on the half-size decode with the scaled intrinsics, and on the full
  // 1280x960 images with the native ones; both find the obstacle bases in both eyes.
  const LaserScan scan = world->ScanAt(kStart);
  const vision::VisionResult half = RunVision(decoded.left, decoded.right, left, right, scan);
  ASSERT_TRUE(half.ok) << half.error;
  const vision::VisionResult full =
      RunVision(rendered.left, rendered.right, full_left, full_right, scan);
  ASSERT_TRUE(full.ok) << full.error;
  const vision::VisionResult reference = [&] {
    const sim::StereoImages small = small_world->StereoAt(kStart, false);
    return RunVision(
        small.left, small.right, expected,
        vision::MathCalibrationFromSim(small_world->calibration(), Eye::kRight, laser_height_m),
        scan);
  }();
  ASSERT_TRUE(reference.ok) << reference.error;
  std::printf("NESC matched: 640x480 rendered %d, 1280x960 decoded at 1/2 %d, 1280x960 full %d\n",
              reference.nesc.matched, half.nesc.matched, full.nesc.matched);
  EXPECT_GE(half.nesc.matched, reference.nesc.matched * 8 / 10);
  EXPECT_GE(full.nesc.matched, reference.nesc.matched * 8 / 10);
  EXPECT_GT(reference.nesc.matched, 20);
}

}  // namespace
}  // namespace mostar
