#include "robot_server/sim/stereo_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "robot_server/sim/laser_raycast.h"
#include "robot_server/sim/scene.h"
#include "robot_server/sim/sim_test_helpers.h"
#include "robot_server/sim/sim_world.h"

namespace mostar::sim {
namespace {

using testing::NoiselessConfig;
using testing::OpenFloor;
using testing::SourceDir;

class RendererFixture : public ::testing::Test {
 protected:
  void Build(const std::string& scene_text, const proto::SimConfig& config = NoiselessConfig()) {
    world_ = std::make_unique<World>(OpenFloor(scene_text));
    renderer_ = std::make_unique<StereoRenderer>(*world_, CameraParams::FromProto(config.camera()),
                                                 config.laser().height_m());
  }
  std::unique_ptr<World> world_;
  std::unique_ptr<StereoRenderer> renderer_;
};

// The default mounting, by hand: laser 0.35 m above the floor, cameras 0.60 m above and
// 0.20 m behind it (0.95 m above the floor), tilted 0.21 rad down, f = 440 px, cy = 239.5.
constexpr double kFocal = 440, kCy = 239.5, kTilt = 0.21;

// Image row of a point `drop_m` below the camera and `ahead_m` in front of it (pinhole).
double RowByHand(double drop_m, double ahead_m) {
  return kCy + kFocal * std::tan(std::atan2(drop_m, ahead_m) - kTilt);
}

TEST_F(RendererFixture, WallBaseLandsOnTheRowOfThePinholeFormula) {
  Build("wall { x0_m: 4 y0_m: -20 x1_m: 4 y1_m: 20 }");
  ImageGroundTruth truth;
  const cv::Mat image = renderer_->RenderEye(Eye::kLeft, Pose2D{}, 0, &truth);
  ASSERT_EQ(image.type(), CV_8UC3);
  ASSERT_EQ(image.cols, 640);
  ASSERT_EQ(image.rows, 480);
  // The wall base (floor, x = 4 m) is 0.95 m below and 4.2 m ahead of the cameras.
  const double v_base = RowByHand(0.95, 4.2);  // 244.96
  const int expected_row = static_cast<int>(std::ceil(v_base)) - 1;
  int exact = 0;
  for (int u = 0; u < image.cols; ++u) {
    ASSERT_NEAR(truth.base_row_px[u], expected_row, 1) << "column " << u;
    exact += truth.base_row_px[u] == expected_row;
    EXPECT_EQ(truth.base_obstacle_id[u], 1);
  }
  EXPECT_GT(exact, 630);
  // The rows below the base line are floor, the ones above it wall.
  EXPECT_EQ(truth.labels.at<uint8_t>(expected_row + 1, 320), kLabelFloor);
  EXPECT_EQ(truth.labels.at<uint8_t>(expected_row - 5, 320), 1);
}

TEST_F(RendererFixture, GroundTruthProjectionAgreesWithTheHandFormula) {
  Build("");
  const LaserCameraCalibration& k = renderer_->params().calibration;
  // A laser point 4 m ahead in the laser frame is 0.6 m below and 4.2 m ahead of the cameras.
  double u, v;
  ASSERT_TRUE(ProjectLaserPoint(k, Eye::kLeft, 4.0, 0.06, 0.0, &u, &v));
  EXPECT_NEAR(u, 319.5, 1e-9);
  EXPECT_NEAR(v, RowByHand(0.6, 4.2), 1e-9);
  // Left eye at +6 cm: a point straight ahead of the pair appears right of centre by f b/2/z.
  ASSERT_TRUE(ProjectLaserPoint(k, Eye::kLeft, 4.0, 0.0, 0.6, &u, &v));
  EXPECT_NEAR(u, 319.5 + kFocal * 0.06 / (4.2 * std::cos(kTilt)), 1e-9);
  ASSERT_TRUE(ProjectLaserPoint(k, Eye::kRight, 4.0, 0.0, 0.6, &u, &v));
  EXPECT_NEAR(u, 319.5 - kFocal * 0.06 / (4.2 * std::cos(kTilt)), 1e-9);
  EXPECT_FALSE(ProjectLaserPoint(k, Eye::kLeft, -3.0, 0.0, 0.0, &u, &v));  // behind
}

TEST_F(RendererFixture, WallEndLandsOnTheColumnOfThePinholeFormula) {
  Build("wall { x0_m: 4 y0_m: 0.5 x1_m: 4 y1_m: 20 }");
  ImageGroundTruth truth;
  renderer_->RenderEye(Eye::kLeft, Pose2D{}, 0, &truth);
  // End of the wall at the floor: 0.44 m left of the left eye, 4.2 m ahead, 0.95 m down.
  const double z_cam = 4.2 * std::cos(kTilt) + 0.95 * std::sin(kTilt);
  const double u_end = 319.5 - kFocal * 0.44 / z_cam;
  const int row = static_cast<int>(std::ceil(RowByHand(0.95, 4.2))) - 3;
  int last_wall_column = -1;
  for (int u = 0; u < 640; ++u) {
    if (truth.labels.at<uint8_t>(row, u) == 1) last_wall_column = u;
  }
  EXPECT_NEAR(last_wall_column, u_end, 1.0);
}

TEST_F(RendererFixture, LowObjectIsVisibleToTheCamerasButNotToTheLaser) {
  Build(
      "wall { x0_m: 5 y0_m: -20 x1_m: 5 y1_m: 20 }\n"
      "box { x_m: 2 y_m: 0 size_x_m: 0.4 size_y_m: 0.6 height_m: 0.15 }");
  ImageGroundTruth truth;
  renderer_->RenderEye(Eye::kLeft, Pose2D{}, 0, &truth);
  const int box_id = 2;
  EXPECT_GT(cv::countNonZero(truth.labels == box_id), 1000);
  EXPECT_EQ(truth.base_obstacle_id[320], box_id);  // the nearest base in the centre column
  LaserParams laser;
  laser.noise_sigma_m = 0;
  const auto ranges = TrueRangesAt(*world_, laser, Pose2D{});
  EXPECT_NEAR(ranges[180], 5.0, 1e-4);  // the beam straight ahead passes over the box
}

TEST_F(RendererFixture, RightEyeVerticalOffsetMovesItsImageDown) {
  proto::SimConfig config = NoiselessConfig();
  config.mutable_camera()->set_right_vertical_offset_px(3);
  Build("wall { x0_m: 4 y0_m: -20 x1_m: 4 y1_m: 20 }", config);
  StereoImages images;
  renderer_->Render(Pose2D{}, 0, true, &images);
  EXPECT_EQ(images.right_truth.base_row_px[320], images.left_truth.base_row_px[320] + 3);
  EXPECT_NEAR(renderer_->params().calibration.right_cy_px, 242.5, 1e-12);
}

// A right camera rolled 1 degree clockwise (seen from behind): its image turns counter-clockwise,
// so a level wall base rises to the right, 5 px over the 280 px from the centre to column 600;
// the rendered base follows the ground-truth projection, and the left eye is level.
TEST_F(RendererFixture, RightEyeRollTurnsItsImage) {
  proto::SimConfig config = NoiselessConfig();
  config.mutable_camera()->set_right_roll_deg(1.0);
  Build("wall { x0_m: 4 y0_m: -20 x1_m: 4 y1_m: 20 }", config);
  StereoImages images;
  renderer_->Render(Pose2D{}, 0, true, &images);
  const LaserCameraCalibration& k = renderer_->params().calibration;
  EXPECT_NEAR(k.right_roll_rad, M_PI / 180.0, 1e-12);
  EXPECT_EQ(images.left_truth.base_row_px[40], images.left_truth.base_row_px[600]);
  const int rise = images.right_truth.base_row_px[40] - images.right_truth.base_row_px[600];
  EXPECT_NEAR(rise, 560 * std::tan(M_PI / 180.0), 1.0);
  // The right image's base row where the ground truth projects points of the wall base (laser
  // frame: 4 m ahead, the floor 0.35 m below the laser).
  for (const double y_m : {-1.5, 0.0, 1.5}) {
    double u = 0, v = 0;
    ASSERT_TRUE(ProjectLaserPoint(k, Eye::kRight, 4.0, y_m, -0.35, &u, &v));
    const int column = static_cast<int>(std::lround(u));
    ASSERT_GE(column, 0);
    ASSERT_LT(column, 640);
    EXPECT_NEAR(images.right_truth.base_row_px[column], v, 1.5) << "y " << y_m;
  }
}

TEST_F(RendererFixture, ArtifactAppearsInOneEyeOnly) {
  proto::SimConfig config = NoiselessConfig();
  auto* a = config.mutable_camera()->mutable_artifact();
  a->set_kind(proto::ArtifactConfig::DARK_BLOB);
  a->set_eye(proto::ArtifactConfig::RIGHT);
  a->set_size_px(30);
  Build("wall { x0_m: 4 y0_m: -20 x1_m: 4 y1_m: 20 }", config);
  StereoImages images;
  renderer_->Render(Pose2D{}, 5, true, &images);
  EXPECT_FALSE(images.left_truth.artifact_present);
  ASSERT_TRUE(images.right_truth.artifact_present);
  const cv::Rect box = images.right_truth.artifact_box & cv::Rect(0, 0, 640, 480);
  ASSERT_GT(box.area(), 100);
  // The blob darkens the right eye where it lies.
  const cv::Point centre(box.x + box.width / 2, box.y + box.height / 2);
  const cv::Vec3b with = images.right.at<cv::Vec3b>(centre);
  const cv::Mat clean = renderer_->RenderEye(Eye::kLeft, Pose2D{}, 5, nullptr);
  EXPECT_LT(with[1], clean.at<cv::Vec3b>(centre)[1]);
}

TEST_F(RendererFixture, FramesAreReproducibleAndNoisy) {
  proto::SimConfig config = NoiselessConfig();
  config.mutable_camera()->set_noise_sigma(3.0);
  Build("wall { x0_m: 4 y0_m: -20 x1_m: 4 y1_m: 20 }", config);
  const cv::Mat a = renderer_->RenderEye(Eye::kLeft, Pose2D{}, 7, nullptr);
  const cv::Mat b = renderer_->RenderEye(Eye::kLeft, Pose2D{}, 7, nullptr);
  const cv::Mat c = renderer_->RenderEye(Eye::kLeft, Pose2D{}, 8, nullptr);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  cv::Mat diff;
  cv::absdiff(a, c, diff);
  EXPECT_GT(cv::mean(diff)[0], 1.0);  // independent noise of sigma 3: mean |d| ~ 3.4
  EXPECT_LT(cv::mean(diff)[0], 6.0);
}

TEST_F(RendererFixture, CheckerboardFloorShowsBothColours) {
  Build(
      "floor { pattern: CHECKERBOARD square_m: 0.5 colour { r: 230 g: 230 b: 230 } "
      "colour2 { r: 20 g: 20 b: 20 } }");
  const cv::Mat image = renderer_->RenderEye(Eye::kLeft, Pose2D{}, 0, nullptr);
  cv::Mat grey;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  const cv::Mat bottom = grey(cv::Rect(0, 300, 640, 180));
  EXPECT_GT(cv::countNonZero(bottom < 40), 5000);
  EXPECT_GT(cv::countNonZero(bottom > 120), 5000);
}

// Contact shadows darken the floor in front of a base and the wall just above it; switched
// off, both look exactly like open floor and the rest of the wall.
TEST_F(RendererFixture, ContactShadowsCanBeSwitchedOff) {
  // At 2.2 m from the cameras a floor row spans ~1.2 cm, a wall row ~0.5 cm.
  const std::string wall = "wall { x0_m: 2 y0_m: -20 x1_m: 2 y1_m: 20 }";
  Build("");
  const cv::Mat open_floor = renderer_->RenderEye(Eye::kLeft, Pose2D{}, 0, nullptr);
  for (const bool shadows : {true, false}) {
    SCOPED_TRACE(shadows ? "shadows on" : "shadows off");
    proto::SimConfig config = NoiselessConfig();
    config.mutable_camera()->set_contact_shadows(shadows);
    Build(wall, config);
    ImageGroundTruth truth;
    const cv::Mat image = renderer_->RenderEye(Eye::kLeft, Pose2D{}, 0, &truth);
    const int u = 320, base = truth.base_row_px[u];
    ASSERT_GT(base, 0);
    const int floor_near = image.at<cv::Vec3b>(base + 2, u)[1];  // ~2 cm in front of the base
    const int floor_open = open_floor.at<cv::Vec3b>(base + 2, u)[1];
    const int wall_low = image.at<cv::Vec3b>(base - 1, u)[1];  // ~1 cm above the floor
    const int wall_high = image.at<cv::Vec3b>(base - 40, u)[1];
    ASSERT_EQ(truth.labels.at<uint8_t>(base - 40, u), 1);
    if (shadows) {
      EXPECT_LT(floor_near, 0.85 * floor_open);
      EXPECT_LT(wall_low, 0.9 * wall_high);
    } else {
      EXPECT_EQ(floor_near, floor_open);
      EXPECT_EQ(wall_low, wall_high);
    }
  }
}

// The picture by definition, one World::Trace per pixel: the ray through the pixel centre
// (undistorted by fixed point), Shade, distance fall-off, vignetting and eye gain, no blur and
// no noise. Labels as in ground_truth.h.
struct ReferenceImage {
  cv::Mat bgr;     // CV_8UC3
  cv::Mat labels;  // CV_8U
};

ReferenceImage TraceEveryPixel(const World& world, const CameraParams& p, double laser_height_m,
                               Eye eye, const Pose2D& pose) {
  const LaserCameraCalibration& k = p.calibration;
  const double cam_x = k.camera_x_m, cam_y = k.EyeYm(eye), cam_z = laser_height_m + k.camera_z_m;
  const double c = std::cos(pose.theta_rad), s = std::sin(pose.theta_rad);
  const double ox = pose.x_m + c * cam_x - s * cam_y, oy = pose.y_m + s * cam_x + c * cam_y;
  const double ct = std::cos(k.tilt_rad), st = std::sin(k.tilt_rad);
  const double gain = eye == Eye::kLeft ? p.left_gain : p.right_gain;
  ReferenceImage out{cv::Mat(k.height_px, k.width_px, CV_8UC3),
                     cv::Mat(k.height_px, k.width_px, CV_8U)};
  for (int v = 0; v < k.height_px; ++v) {
    for (int u = 0; u < k.width_px; ++u) {
      const double xd = (u - k.cx_px) / k.focal_px, yd = (v - k.Cy(eye)) / k.focal_px;
      double xn = xd, yn = yd;
      for (int it = 0; it < 20; ++it) {
        const double r2 = xn * xn + yn * yn;
        xn = xd / (1 + k.k1 * r2 + k.k2 * r2 * r2);
        yn = yd / (1 + k.k1 * r2 + k.k2 * r2 * r2);
      }
      const double bx = ct - yn * st, by = -xn, bz = -st - yn * ct;
      const RayHit hit = world.Trace(ox, oy, cam_z, pose.theta_rad + std::atan2(by, bx),
                                     bz / std::hypot(bx, by), 1e9, /*skip_transparent=*/false);
      const Rgb colour = world.Shade(hit, p.contact_shadows);
      const double cos2 = 1.0 / (1.0 + xn * xn + yn * yn);
      const double vignette = p.vignetting ? 0.55 + 0.45 * cos2 * cos2 : 1.0;
      const double dist = hit.kind == RayHit::kNothing ? 0.0 : hit.h_m;
      const double gain_px = gain * vignette / (1.0 + 0.035 * dist);
      out.bgr.at<cv::Vec3b>(v, u) = cv::Vec3b(cv::saturate_cast<uint8_t>(colour.b * gain_px),
                                              cv::saturate_cast<uint8_t>(colour.g * gain_px),
                                              cv::saturate_cast<uint8_t>(colour.r * gain_px));
      uint8_t label = kLabelVoid;
      if (hit.kind == RayHit::kObstacle)
        label = static_cast<uint8_t>(std::min(hit.obstacle->id, 253));
      if (hit.kind == RayHit::kFloor) label = kLabelFloor;
      if (hit.kind == RayHit::kCeiling) label = kLabelCeiling;
      out.labels.at<uint8_t>(v, u) = label;
    }
  }
  return out;
}

// The shipped corridor (walls with skirting, boxes, cylinders, a person, the ceiling, a tiled
// floor with contact shadows), seen from poses in and near it, with vignetting and a lens
// distortion: the fast renderer draws what a trace of every pixel gives. Obstacles are crossed
// per azimuth bin a quarter pixel wide, so labels may differ on silhouettes only, and colours
// by the rounding of a grey level where a bin's ray and the pixel's ray fall on different
// floor tiles or texture cells.
TEST(StereoRendererReferenceTest, DrawsWhatATraceOfEveryPixelGives) {
  proto::Scene scene;
  proto::SimConfig config;
  std::string error;
  ASSERT_TRUE(LoadScene(SourceDir() + "/deploy/scenes/corridor.pbtxt", &scene, &error)) << error;
  ASSERT_TRUE(LoadSimConfig(SourceDir() + "/deploy/config/sim_morduc.pbtxt", &config, &error))
      << error;
  config.mutable_camera()->set_noise_sigma(0);
  config.mutable_camera()->set_blur_sigma_px(0);
  config.mutable_camera()->set_k1(-0.04);
  const World world(scene);
  const CameraParams params = CameraParams::FromProto(config.camera());
  const StereoRenderer renderer(world, params, config.laser().height_m());
  for (const Pose2D& pose :
       {Pose2D{0, 0, 0}, Pose2D{3.1, 0.4, 0.5}, Pose2D{6.3, -0.5, -0.9}, Pose2D{11.0, 0.2, 3.0}}) {
    SCOPED_TRACE(::testing::Message() << "pose " << pose.x_m << " " << pose.y_m);
    StereoImages images;
    renderer.Render(pose, 0, /*with_truth=*/true, &images);
    for (const Eye eye : {Eye::kLeft, Eye::kRight}) {
      const bool left = eye == Eye::kLeft;
      const ReferenceImage ref =
          TraceEveryPixel(world, params, config.laser().height_m(), eye, pose);
      const cv::Mat& image = left ? images.left : images.right;
      const cv::Mat& labels = left ? images.left_truth.labels : images.right_truth.labels;
      ASSERT_EQ(image.size(), ref.bgr.size());
      ASSERT_EQ(image.type(), CV_8UC3);
      const double n = static_cast<double>(image.total());
      EXPECT_LT(cv::countNonZero(labels != ref.labels) / n, 0.004);
      cv::Mat diff;
      cv::absdiff(image, ref.bgr, diff);
      diff = diff.reshape(1);
      EXPECT_LT(cv::mean(diff)[0], 0.15);
      EXPECT_LT(cv::countNonZero(diff > 2) / (3 * n), 0.004);
      // Where the labels agree, the colour is the trace's up to rounding and texture cells.
      const cv::Mat agree = (labels == ref.labels);
      cv::Mat diff3 = diff.reshape(3), grey;
      cv::cvtColor(diff3, grey, cv::COLOR_BGR2GRAY);
      EXPECT_LT(cv::countNonZero((grey > 1) & agree) / n, 0.002);
    }
  }
}

// Blur and sensor noise on top of the sharp picture: the blur is the Gaussian of the sharp
// image, the noise zero-mean with the configured sigma.
TEST_F(RendererFixture, BlurAndNoiseSitOnTheSharpPicture) {
  const std::string scene =
      "floor { pattern: CHECKERBOARD square_m: 0.5 colour { r: 200 g: 190 b: 180 } "
      "colour2 { r: 40 g: 40 b: 50 } }\n"
      "wall { x0_m: 4 y0_m: -20 x1_m: 4 y1_m: 20 }";
  Build(scene);
  const cv::Mat sharp = renderer_->RenderEye(Eye::kLeft, Pose2D{}, 3, nullptr);
  proto::SimConfig config = NoiselessConfig();
  config.mutable_camera()->set_blur_sigma_px(0.6);
  Build(scene, config);
  const cv::Mat blurred = renderer_->RenderEye(Eye::kLeft, Pose2D{}, 3, nullptr);
  cv::Mat expected;
  cv::GaussianBlur(sharp, expected, cv::Size(0, 0), 0.6);
  EXPECT_LE(cv::norm(blurred, expected, cv::NORM_INF), 1.0);
  EXPECT_GT(cv::norm(blurred, sharp, cv::NORM_INF), 20.0);  // the checker edges did soften

  config.mutable_camera()->set_noise_sigma(2.0);
  Build(scene, config);
  for (const uint64_t frame : {3, 4}) {
    const cv::Mat noisy = renderer_->RenderEye(Eye::kLeft, Pose2D{}, frame, nullptr);
    cv::Mat noise;
    cv::subtract(noisy, blurred, noise, cv::noArray(), CV_32F);
    cv::Scalar mean, sigma;
    cv::meanStdDev(noise.reshape(1), mean, sigma);
    EXPECT_NEAR(mean[0], 0.0, 0.05);
    EXPECT_NEAR(sigma[0], 2.0, 0.1);
  }
}

// The renderer's shortcut for plain sides: above the height it gives, Shade() of any hit on
// that side is the plain colour; below it (skirting board, contact shadow) it is not.
TEST(WorldShadingTest, PlainSideIsWhatShadeGivesFromItsHeightUp) {
  const World world(OpenFloor(
      "wall { x0_m: 4 y0_m: -20 x1_m: 4 y1_m: 20 height_m: 2 baseboard_height_m: 0.08 }\n"
      "box { x_m: 2 y_m: 3 size_x_m: 0.4 size_y_m: 0.6 height_m: 0.5 elevation_m: 0.3 }\n"
      "cylinder { x_m: -2 y_m: 0 radius_m: 0.3 height_m: 1 material { texture: STRIPES } }"));
  for (const bool shadows : {true, false}) {
    for (const Obstacle& ob : world.obstacles()) {
      SCOPED_TRACE(::testing::Message()
                   << ob.name << (shadows ? " with" : " without") << " shadows");
      RayHit hit;
      hit.kind = RayHit::kObstacle;
      hit.obstacle = &ob;
      hit.nx = -0.6;
      hit.ny = 0.8;
      double from_z_m;
      const Rgb plain = world.ShadePlainSide(ob, hit.nx, hit.ny, shadows, &from_z_m);
      if (ob.kind == ShapeKind::kCylinder) {
        EXPECT_TRUE(std::isinf(from_z_m));  // striped
        continue;
      }
      EXPECT_EQ(from_z_m, ob.kind == ShapeKind::kWall ? (shadows ? 0.25 : 0.08) : -INFINITY);
      int plain_seen = 0, other_seen = 0;
      for (hit.z_m = ob.z_min_m; hit.z_m <= ob.z_max_m; hit.z_m += 0.01) {
        const Rgb shaded = world.Shade(hit, shadows);
        const bool same = shaded.r == plain.r && shaded.g == plain.g && shaded.b == plain.b;
        EXPECT_EQ(same, hit.z_m >= from_z_m) << "z " << hit.z_m;
        (same ? plain_seen : other_seen)++;
      }
      EXPECT_GT(plain_seen, 10);
      if (ob.kind == ShapeKind::kWall) {
        EXPECT_GT(other_seen, 5);  // the skirting board at least
      }
    }
  }
}

TEST(GroundTruthTest, BaseRowsPickTheLowestObstacleOverFloor) {
  ImageGroundTruth truth;
  truth.labels = cv::Mat(6, 2, CV_8U, cv::Scalar(kLabelFloor));
  truth.labels.at<uint8_t>(0, 0) = 3;  // far obstacle over floor at row 0
  truth.labels.at<uint8_t>(3, 0) = 4;  // near obstacle over floor at row 3
  truth.labels.at<uint8_t>(5, 1) = 4;  // bottom row: no floor below
  ComputeBaseRows(&truth);
  EXPECT_EQ(truth.base_row_px[0], 3);
  EXPECT_EQ(truth.base_obstacle_id[0], 4);
  EXPECT_EQ(truth.base_row_px[1], -1);
  EXPECT_EQ(BaseLinePixels(truth.labels).size(), 2u);
}

}  // namespace
}  // namespace mostar::sim
