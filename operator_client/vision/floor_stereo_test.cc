// Ground-plane stereo on synthetic images rendered from the camera model: a checkered floor and
// a panel with vertical stripes standing on it, seen by both eyes of the default rig.
#include "operator_client/vision/floor_stereo.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "operator_client/vision/vision_pipeline.h"

namespace mostar::vision {
namespace {

using math::CameraModel;

constexpr double kPanelX = 2.0;       // the panel's plane, laser x, metres
constexpr double kPanelHalfY = 0.4;   // its half width
constexpr double kPanelHeight = 0.6;  // above the floor

// Grey of the scene along the viewing ray of `pixel`: the panel (vertical stripes, 4 cm) where
// the ray meets it first, else the floor (25 cm squares, 60 / 190), else black (above horizon).
uint8_t SceneGrey(const CameraModel& camera, const Eigen::Vector2d& pixel, bool with_panel) {
  const Eigen::Vector3d origin = camera.CameraCenterInLaser();
  const Eigen::Vector3d ray = camera.PixelRayInLaser(pixel);
  const double floor_z = -camera.calibration().laser_height_m;
  if (with_panel && ray.x() > 1e-9) {
    const double t = (kPanelX - origin.x()) / ray.x();
    const Eigen::Vector3d p = origin + t * ray;
    if (t > 0 && std::abs(p.y()) < kPanelHalfY && p.z() >= floor_z &&
        p.z() < floor_z + kPanelHeight) {
      // Stripes 3 cm wide of pseudo-random grey (no period for the test to hit by chance).
      const auto stripe = static_cast<uint32_t>(std::floor(p.y() / 0.03) + 1000);
      return static_cast<uint8_t>(30 + (stripe * 2654435761u >> 16) % 200);
    }
  }
  const auto floor = camera.UnprojectToFloor(pixel);
  if (!floor) return 0;
  const int square =
      static_cast<int>(std::floor(floor->x() / 0.25) + std::floor(floor->y() / 0.25));
  return (square % 2 == 0) ? 60 : 190;
}

cv::Mat Render(const CameraModel& camera, bool with_panel) {
  cv::Mat image(camera.height_px(), camera.width_px(), CV_8UC1);
  for (int row = 0; row < image.rows; ++row) {
    for (int col = 0; col < image.cols; ++col) {
      image.at<uint8_t>(row, col) = SceneGrey(camera, Eigen::Vector2d(col, row), with_panel);
    }
  }
  return image;
}

class FloorStereoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    math::LaserCameraCalibration calibration;
    calibration.distortion.k1 = -0.2;  // the warp follows the lens model
    left_ = std::make_shared<const CameraModel>(calibration, math::Eye::kLeft);
    right_ = std::make_shared<const CameraModel>(calibration, math::Eye::kRight);
  }

  // The left eye's test images for a scene with or without the panel.
  FloorStereoImages LeftImages(bool with_panel) {
    std::string error;
    EXPECT_TRUE(warp_.Prepare(left_, right_, 200, &error)) << error;
    FloorStereoImages images;
    images.grey = Render(*left_, with_panel);
    images.other = Render(*right_, with_panel);
    warp_.Warp(images.other, &images.warped);
    images.valid = warp_.valid();
    images.shift = warp_.shift();
    images.focal_px = left_->calibration().fx();
    return images;
  }

  // Evidence over the left image's pixels showing floor points x in [x0, x1], y in [-0.3, 0.3],
  // for an edge on the floor at x = x0 (the standing hypothesis: a surface standing there).
  FloorEvidence Region(const FloorStereoImages& images, double x0, double x1) {
    FloorEvidence evidence;
    const auto a = left_->Project(Eigen::Vector3d(x0, 0, -0.4));
    const auto b = left_->Project(Eigen::Vector3d(x1, 0, -0.4));
    const cv::Vec2f edge_shift = images.shift.at<cv::Vec2f>(static_cast<int>(std::lround(a->y())),
                                                            static_cast<int>(std::lround(a->x())));
    for (int row = static_cast<int>(b->y()); row <= static_cast<int>(a->y()); ++row) {
      for (int col = 220; col <= 420; col += 2) {
        JudgePixel(images, col, row, edge_shift, options_, &evidence);
      }
    }
    return evidence;
  }

  std::shared_ptr<const CameraModel> left_;
  std::shared_ptr<const CameraModel> right_;
  FloorWarp warp_;
  FloorStereoOptions options_;
};

TEST_F(FloorStereoTest, FloorTextureAgreesUnderTheWarp) {
  const FloorStereoImages images = LeftImages(/*with_panel=*/false);
  // Where both eyes see the floor, the warped right image is the left one.
  cv::Mat difference;
  cv::absdiff(images.grey, images.warped, difference);
  cv::Mat masked;
  difference.copyTo(masked, images.valid);
  EXPECT_LT(cv::mean(masked, images.valid)[0], 6.0);
  const FloorEvidence evidence = Region(images, 1.2, 1.8);
  EXPECT_GE(evidence.judged, options_.min_judged);
  EXPECT_EQ(Verdict(evidence, options_), FloorVerdict::kFloor)
      << evidence.floor_agreeing << " and " << evidence.standing_agreeing << " of "
      << evidence.judged;
}

TEST_F(FloorStereoTest, AStandingTexturedPanelDisagrees) {
  const FloorStereoImages images = LeftImages(/*with_panel=*/true);
  // Beyond the panel's base (x = 2 m): its face, seen as if it were floor beyond 2 m.
  const FloorEvidence evidence = Region(images, 2.0, 4.0);
  EXPECT_GE(evidence.judged, options_.min_judged);
  EXPECT_EQ(Verdict(evidence, options_), FloorVerdict::kStanding)
      << evidence.floor_agreeing << " and " << evidence.standing_agreeing << " of "
      << evidence.judged;
  // In front of it, floor still.
  EXPECT_EQ(Verdict(Region(images, 1.2, 1.8), options_), FloorVerdict::kFloor);
}

TEST_F(FloorStereoTest, AUniformRegionIsUndecided) {
  FloorStereoImages images = LeftImages(/*with_panel=*/false);
  images.grey.setTo(128);
  images.warped.setTo(30);  // however different: nothing to judge without texture
  const FloorEvidence evidence = Region(images, 1.2, 1.8);
  EXPECT_EQ(evidence.judged, 0);
  EXPECT_EQ(Verdict(evidence, options_), FloorVerdict::kUndecided);
}

TEST_F(FloorStereoTest, WarpIsKeptForTheSameCamerasAndRebuiltForOthers) {
  std::string error;
  ASSERT_TRUE(warp_.Prepare(left_, right_, 200, &error));
  const uint8_t* before = warp_.valid().data;
  ASSERT_TRUE(warp_.Prepare(left_, right_, 200, &error));
  EXPECT_EQ(warp_.valid().data, before);
  ASSERT_TRUE(warp_.Prepare(right_, left_, 200, &error));
  EXPECT_EQ(warp_.top_row(), 200);
  EXPECT_EQ(cv::countNonZero(warp_.valid().rowRange(0, 200)), 0);
  EXPECT_GT(cv::countNonZero(warp_.valid().rowRange(200, 480)), 100000);
  EXPECT_FALSE(warp_.Prepare(nullptr, left_, 200, &error));
  EXPECT_NE(error.find("missing"), std::string::npos);
}

// The whole pipeline on the synthetic pair: a ray just left of straight ahead meets the squares'
// borders at x = 1.25, 1.5 and 1.75 m before the panel's base at 2 m. The floor test walks past the
// borders to the base; without it the NEP is the first border.
TEST_F(FloorStereoTest, PipelineWalksPastFloorBordersToTheBase) {
  LaserScan scan;
  scan.angle_min_rad = -0.1f;
  scan.angle_increment_rad = 0.02f;
  scan.ranges_m.assign(11, 2.0f);
  VisionInput input;
  cv::cvtColor(Render(*left_, true), input.left, cv::COLOR_GRAY2BGR);
  cv::cvtColor(Render(*right_, true), input.right, cv::COLOR_GRAY2BGR);
  input.scan = scan;
  input.left_camera = left_;
  input.right_camera = right_;
  const auto nep_ahead = [&](bool floor_test, int* floor_edges) {
    VisionOptions options;
    options.edges.low_threshold = 0;
    options.edges.high_threshold = 255;
    options.nearest_edge.floor_stereo.enabled = floor_test;
    VisionPipeline pipeline(options);
    const VisionResult result = pipeline.Process(input);
    EXPECT_TRUE(result.ok) << result.error;
    *floor_edges = result.left_ned.floor_edges + result.right_ned.floor_edges;
    return result.left_ned.neps[8];  // azimuth 0.06 rad: inside the squares, not on a border
  };
  int floor_edges = 0;
  const Nep without = nep_ahead(false, &floor_edges);
  ASSERT_TRUE(without.found);
  EXPECT_NEAR(without.distance_m, 1.25, 0.05);
  EXPECT_EQ(floor_edges, 0);
  const Nep with = nep_ahead(true, &floor_edges);
  ASSERT_TRUE(with.found);
  EXPECT_NEAR(with.distance_m, 2.0, 0.05);
  EXPECT_GT(floor_edges, 0);
}

TEST(FloorStereoOptionsTest, RangesAreChecked) {
  FloorStereoOptions options;
  std::string error;
  EXPECT_TRUE(options.IsValid(&error)) << error;
  options.far_px = options.near_px;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("far_px"), std::string::npos);
  options = FloorStereoOptions{};
  options.margin = 0;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("margin"), std::string::npos);
}

}  // namespace
}  // namespace mostar::vision
