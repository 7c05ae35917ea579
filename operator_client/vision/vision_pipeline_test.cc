#include "operator_client/vision/vision_pipeline.h"

#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "common/config/config_loader.h"

namespace mostar::vision {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(VisionOptionsTest, ProtoDefaultsMatchTheStructDefaults) {
  const VisionOptions from_proto = FromProto(proto::VisionConfig{});
  const VisionOptions defaults;
  EXPECT_EQ(from_proto.edges.low_threshold, defaults.edges.low_threshold);
  EXPECT_EQ(from_proto.edges.high_threshold, defaults.edges.high_threshold);
  EXPECT_EQ(from_proto.edges.canny_threshold1, defaults.edges.canny_threshold1);
  EXPECT_EQ(from_proto.edges.canny_threshold2, defaults.edges.canny_threshold2);
  EXPECT_EQ(from_proto.nearest_edge.max_range_m, defaults.nearest_edge.max_range_m);
  EXPECT_EQ(from_proto.nearest_edge.step_px, defaults.nearest_edge.step_px);
  EXPECT_EQ(from_proto.classifier.edge_threshold_m, 0.10);
  EXPECT_EQ(from_proto.nesc.stereo_threshold_m, 0.05);  // edgeTh / 2 when unset
  EXPECT_TRUE(from_proto.stereo);
}

TEST(VisionOptionsTest, StereoThresholdDefaultsToHalfTheEdgeThreshold) {
  proto::VisionConfig config;
  config.set_edge_threshold_m(0.2);
  EXPECT_DOUBLE_EQ(FromProto(config).nesc.stereo_threshold_m, 0.1);
  config.set_stereo_threshold_m(0.03);
  EXPECT_DOUBLE_EQ(FromProto(config).nesc.stereo_threshold_m, 0.03);
}

TEST(VisionOptionsTest, RoundTripsThroughTheProfile) {
  VisionOptions options;
  options.edges.low_threshold = 12;
  options.edges.high_threshold = 190;
  options.edges.canny_threshold1 = 33;
  options.edges.canny_threshold2 = 99;
  options.edges.canny_aperture_px = 5;
  options.edges.l2_gradient = true;
  options.nearest_edge.max_range_m = 6.5;
  options.nearest_edge.step_px = 0.25;
  options.nearest_edge.lateral_tolerance_px = 2;
  options.nearest_edge.bottom_margin_px = 30;
  options.classifier.edge_threshold_m = 0.15;
  options.nesc.stereo_threshold_m = 0.07;
  options.stereo = false;
  options.keep_edge_images = false;
  const proto::VisionConfig config = ToProto(options);
  EXPECT_TRUE(
      google::protobuf::util::MessageDifferencer::Equals(config, ToProto(FromProto(config))));
  const VisionOptions back = FromProto(config);
  EXPECT_EQ(back.edges.canny_aperture_px, 5);
  EXPECT_EQ(back.nearest_edge.bottom_margin_px, 30);
  EXPECT_DOUBLE_EQ(back.nesc.stereo_threshold_m, 0.07);
  EXPECT_FALSE(back.stereo);
}

TEST(VisionOptionsTest, TextProfileIsRangeCheckedAndValidated) {
  proto::VisionConfig config;
  std::string error;
  ASSERT_TRUE(
      ParseTextConfig("edges { low_threshold: 40 high_threshold: 210 }\n"
                      "edge_threshold_m: 0.12\n",
                      "vision.pbtxt", &config, &error))
      << error;
  EXPECT_TRUE(FromProto(config).IsValid(&error)) << error;
  EXPECT_FALSE(ParseTextConfig("edges { low_threshold: 300 }", "vision.pbtxt", &config, &error));
  EXPECT_NE(error.find("low_threshold"), std::string::npos) << error;
  // In range field by field, but inconsistent: refused by IsValid with the part named.
  ASSERT_TRUE(ParseTextConfig("edges { low_threshold: 200 high_threshold: 100 }", "vision.pbtxt",
                              &config, &error));
  EXPECT_FALSE(FromProto(config).IsValid(&error));
  EXPECT_EQ(error.rfind("edges: ", 0), 0u) << error;
}

// A camera image with a dark obstacle base at `distance_m` ahead on a plain bright floor.
cv::Mat ImageWithObstacle(const math::CameraModel& camera, double distance_m) {
  cv::Mat image(camera.height_px(), camera.width_px(), CV_8UC3, cv::Scalar(210, 210, 210));
  const Eigen::Vector2d base =
      *camera.Project(Eigen::Vector3d(distance_m, 0, -camera.calibration().laser_height_m));
  image.rowRange(0, static_cast<int>(std::lround(base.y())) + 1).setTo(cv::Scalar(50, 50, 50));
  return image;
}

VisionInput StereoInput(double edge_distance_m, float laser_range_m) {
  VisionInput input;
  input.stamp = FromUnixNanos(1'000'000'000);
  input.sequence = 7;
  input.left_camera =
      std::make_shared<const math::CameraModel>(math::LaserCameraCalibration{}, math::Eye::kLeft);
  input.right_camera =
      std::make_shared<const math::CameraModel>(math::LaserCameraCalibration{}, math::Eye::kRight);
  input.left = ImageWithObstacle(*input.left_camera, edge_distance_m);
  input.right = ImageWithObstacle(*input.right_camera, edge_distance_m);
  input.scan.angle_min_rad = static_cast<float>(-kPi / 2);
  input.scan.angle_increment_rad = static_cast<float>(kPi / 180);
  input.scan.ranges_m.assign(181, laser_range_m);
  return input;
}

TEST(VisionPipelineTest, StereoPairThroughTheWholeChain) {
  VisionPipeline pipeline{VisionOptions{}};
  // A wall whose base is 2.5 m ahead, seen by the laser 4 cm further (small misalignment).
  const VisionResult result = pipeline.Process(StereoInput(2.5, 2.54f));
  ASSERT_TRUE(result.ok) << result.error;
  EXPECT_EQ(result.sequence, 7u);
  EXPECT_EQ(result.stamp, FromUnixNanos(1'000'000'000));
  EXPECT_FALSE(result.left_edges.edges.empty());
  EXPECT_GT(result.nesc.matched, 10);
  // Only beams at the border of the stereo overlap are seen by one eye.
  EXPECT_LE(result.nesc.one_eye, 6);
  EXPECT_EQ(result.nesc.disagree, 0);
  const size_t ahead = 90;
  EXPECT_EQ(result.classification.beams[ahead].relation, NepRelation::kAgrees);
  EXPECT_NEAR(result.classification.corrected_scan.ranges_m[ahead], 2.5, 0.03);
  EXPECT_TRUE(result.classification.possible_obstacles.empty());
}

TEST(VisionPipelineTest, MonoModeUsesTheLeftImageOnly) {
  VisionOptions options;
  options.stereo = false;
  options.keep_edge_images = false;
  VisionPipeline pipeline(options);
  VisionInput input = StereoInput(1.5, 4.0f);  // the laser does not see the low obstacle
  input.right = cv::Mat();
  input.right_camera = nullptr;
  const VisionResult result = pipeline.Process(input);
  ASSERT_TRUE(result.ok) << result.error;
  EXPECT_TRUE(result.left_edges.edges.empty());
  EXPECT_GT(result.classification.possible_obstacles.size(), 10u);
  for (const PossibleObstacle& dot : result.classification.possible_obstacles) {
    EXPECT_NEAR(dot.floor_point_laser.x(), 1.5, 0.03);
  }
}

TEST(VisionPipelineTest, BadInputGivesAMessageNotACrash) {
  VisionPipeline pipeline{VisionOptions{}};
  VisionInput input = StereoInput(2.0, 2.0f);
  input.right = cv::Mat(100, 100, CV_8UC3, cv::Scalar(0));
  VisionResult result = pipeline.Process(input);
  EXPECT_FALSE(result.ok);
  EXPECT_NE(result.error.find("right image is 100x100"), std::string::npos) << result.error;

  input = StereoInput(2.0, 2.0f);
  input.right_camera = nullptr;
  result = pipeline.Process(input);
  EXPECT_FALSE(result.ok);
  EXPECT_NE(result.error.find("camera"), std::string::npos);

  input = StereoInput(2.0, 2.0f);
  input.potential_outliers.assign(3, false);
  result = pipeline.Process(input);
  EXPECT_FALSE(result.ok);
  EXPECT_NE(result.error.find("outlier labels"), std::string::npos);
}

}  // namespace
}  // namespace mostar::vision
