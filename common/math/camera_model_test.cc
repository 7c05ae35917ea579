#include "common/math/camera_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <vector>

namespace mostar::math {
namespace {

constexpr double kPi = 3.14159265358979323846;

LaserCameraCalibration Morduc() { return LaserCameraCalibration{}; }

LaserCameraCalibration WithLens() {
  LaserCameraCalibration calibration;
  calibration.focal_y_px = 530.0;
  calibration.principal_x_px = 322.5;
  calibration.principal_y_px = 236.0;
  calibration.distortion = {-0.28, 0.09, 0.001, -0.0007, -0.012};
  calibration.pan_rad = 0.05;
  calibration.roll_rad = -0.02;
  calibration.camera_x_m = 0.03;
  return calibration;
}

TEST(CameraModelTest, DefaultCalibrationIsValid) {
  std::string error;
  EXPECT_TRUE(Morduc().IsValid(&error)) << error;
  EXPECT_TRUE(WithLens().IsValid(&error)) << error;
  EXPECT_NEAR(Morduc().laser_height_m + Morduc().camera_y_m, 0.95, 1e-12);
  EXPECT_NEAR(Morduc().baseline_m(), 0.12, 1e-12);
}

TEST(CameraModelTest, LevelCameraSeesPointAheadAtPrincipalPoint) {
  LaserCameraCalibration calibration;
  calibration.tilt_rad = 0.0;
  const CameraModel camera(calibration, kMonoCamera);
  const Eigen::Vector3d ahead(5.0, -calibration.camera_x_m, calibration.camera_y_m);
  const std::optional<Eigen::Vector2d> pixel = camera.Project(ahead);
  ASSERT_TRUE(pixel.has_value());
  EXPECT_NEAR(pixel->x(), 319.5, 1e-9);
  EXPECT_NEAR(pixel->y(), 239.5, 1e-9);
  // A point to the left of the laser (positive laser y) appears left in the image; a point
  // above appears higher.
  EXPECT_LT(camera.Project(ahead + Eigen::Vector3d(0, 0.5, 0))->x(), 319.5);
  EXPECT_LT(camera.Project(ahead + Eigen::Vector3d(0, 0, 0.5))->y(), 239.5);
}

TEST(CameraModelTest, CameraCentreFollowsThesisAxes) {
  LaserCameraCalibration calibration;
  calibration.camera_x_m = 0.2;
  calibration.camera_y_m = 0.5;
  calibration.camera_z_m = -0.1;
  const CameraModel mono(calibration, kMonoCamera);
  EXPECT_TRUE(mono.CameraCenterInLaser().isApprox(Eigen::Vector3d(-0.1, -0.2, 0.5)));
  const CameraModel left(calibration, Eye::kLeft);
  const CameraModel right(calibration, Eye::kRight);
  EXPECT_NEAR(left.CameraCenterInLaser().y(), -0.2 + 0.06, 1e-12);
  EXPECT_NEAR(right.CameraCenterInLaser().y(), -0.2 - 0.06, 1e-12);
  // camera_from_laser maps the camera centre to the origin.
  EXPECT_LT((mono.camera_from_laser() * mono.CameraCenterInLaser()).norm(), 1e-12);
}

TEST(CameraModelTest, RejectsPointsBehindTheCamera) {
  const CameraModel camera(Morduc(), kMonoCamera);
  EXPECT_FALSE(camera.Project(Eigen::Vector3d(-3.0, 0.0, 0.0)).has_value());
  EXPECT_FALSE(camera.Project(camera.CameraCenterInLaser()).has_value());
  EXPECT_FALSE(camera.Project(Eigen::Vector3d(NAN, 0.0, 0.0)).has_value());
  EXPECT_FALSE(camera.ProjectUndistorted(Eigen::Vector3d(-3.0, 0.0, 0.0)).has_value());
  EXPECT_TRUE(camera.Project(Eigen::Vector3d(3.0, 0.0, 0.0)).has_value());
}

TEST(CameraModelTest, TiltedDownCameraSeesFartherFloorPointsHigher) {
  const CameraModel camera(Morduc(), kMonoCamera);
  const double floor_z = -Morduc().laser_height_m;
  double previous_v = 1e9;
  for (double x = 1.5; x <= 8.0; x += 0.5) {
    const std::optional<Eigen::Vector2d> pixel = camera.Project(Eigen::Vector3d(x, 0.0, floor_z));
    ASSERT_TRUE(pixel.has_value());
    EXPECT_LT(pixel->y(), previous_v) << "x=" << x;
    previous_v = pixel->y();
  }
  // Tilted down: the horizon (a very far point at camera height) is above the image centre.
  const Eigen::Vector3d far(1e4, 0.0, Morduc().camera_y_m);
  EXPECT_LT(camera.Project(far)->y(), 239.5 - 100.0);
}

TEST(CameraModelTest, PanAndRollTurnTheRightWay) {
  LaserCameraCalibration calibration;
  calibration.tilt_rad = 0.0;
  calibration.pan_rad = 0.1;  // looking left: a point straight ahead appears right of centre
  const Eigen::Vector3d ahead(5.0, 0.0, calibration.camera_y_m);
  EXPECT_GT(CameraModel(calibration, kMonoCamera).Project(ahead)->x(), 319.5 + 10.0);
  calibration.pan_rad = 0.0;
  calibration.roll_rad = 0.1;  // camera rolls clockwise: the scene turns counter-clockwise
  const Eigen::Vector3d ahead_right(5.0, -1.0, calibration.camera_y_m);
  const Eigen::Vector2d pixel = *CameraModel(calibration, kMonoCamera).Project(ahead_right);
  EXPECT_GT(pixel.x(), 319.5);
  EXPECT_LT(pixel.y(), 239.5 - 5.0);  // counter-clockwise on screen: right side moves up
}

TEST(CameraModelTest, StereoEyesHaveTheExpectedDisparity) {
  LaserCameraCalibration calibration;
  calibration.tilt_rad = 0.0;
  const CameraModel left(calibration, Eye::kLeft);
  const CameraModel right(calibration, Eye::kRight);
  const Eigen::Vector3d point(4.0, 0.3, 0.2);
  const double depth = point.x() - calibration.camera_z_m;
  const double disparity = left.Project(point)->x() - right.Project(point)->x();
  EXPECT_NEAR(disparity, calibration.focal_px * calibration.baseline_m() / depth, 1e-9);
  EXPECT_NEAR(left.Project(point)->y(), right.Project(point)->y(), 1e-9);
}

class RoundTripTest : public ::testing::TestWithParam<int> {
 protected:
  LaserCameraCalibration Calibration() const { return GetParam() == 0 ? Morduc() : WithLens(); }
};

TEST_P(RoundTripTest, FloorPointsSurviveProjectThenUnproject) {
  for (RigCamera eye : {kMonoCamera, RigCamera(Eye::kLeft), RigCamera(Eye::kRight)}) {
    const CameraModel camera(Calibration(), eye);
    const double floor_z = -Calibration().laser_height_m;
    int checked = 0;
    for (double x = 0.5; x <= 12.0; x += 0.25) {
      for (double y = -4.0; y <= 4.0; y += 0.25) {
        const Eigen::Vector3d floor_point(x, y, floor_z);
        const std::optional<Eigen::Vector2d> pixel = camera.Project(floor_point);
        if (!pixel.has_value() || !camera.IsInImage(*pixel)) continue;
        const std::optional<Eigen::Vector3d> back = camera.UnprojectToFloor(*pixel);
        ASSERT_TRUE(back.has_value()) << floor_point.transpose();
        EXPECT_LT((*back - floor_point).norm(), 1e-6) << floor_point.transpose();
        ++checked;
      }
    }
    EXPECT_GT(checked, 200) << RigCameraName(eye);
  }
}

TEST_P(RoundTripTest, PixelsSurviveUnprojectThenProject) {
  const CameraModel camera(Calibration(), Eye::kLeft);
  for (double v = 300.0; v < 480.0; v += 17.0) {
    for (double u = 0.0; u < 640.0; u += 23.0) {
      const Eigen::Vector2d pixel(u, v);
      const std::optional<Eigen::Vector3d> floor_point = camera.UnprojectToFloor(pixel);
      ASSERT_TRUE(floor_point.has_value()) << pixel.transpose();
      EXPECT_NEAR(floor_point->z(), -Calibration().laser_height_m, 1e-12);
      EXPECT_LT((*camera.Project(*floor_point) - pixel).norm(), 1e-7);
      // Any height plane works the same way, e.g. the scan plane.
      const std::optional<Eigen::Vector3d> scan_point = camera.UnprojectToHeight(pixel, 0.0);
      if (scan_point.has_value()) {
        EXPECT_LT((*camera.Project(*scan_point) - pixel).norm(), 1e-7);
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(PinholeAndLens, RoundTripTest, ::testing::Values(0, 1));

TEST(CameraModelTest, PixelsAboveTheHorizonDoNotReachTheFloor) {
  const CameraModel camera(Morduc(), kMonoCamera);
  EXPECT_FALSE(camera.UnprojectToFloor(Eigen::Vector2d(320.0, 0.0)).has_value());
  EXPECT_FALSE(camera.UnprojectToFloor(Eigen::Vector2d(NAN, 200.0)).has_value());
  // Close to the horizon the floor point is beyond max_range_m.
  EXPECT_FALSE(camera.UnprojectToFloor(Eigen::Vector2d(320.0, 300.0), 1.0).has_value());
  EXPECT_TRUE(camera.UnprojectToFloor(Eigen::Vector2d(320.0, 300.0)).has_value());
}

TEST(CameraModelTest, UndistortInvertsDistort) {
  const CameraModel camera(WithLens(), kMonoCamera);
  for (double x = -0.6; x <= 0.6; x += 0.05) {
    for (double y = -0.45; y <= 0.45; y += 0.05) {
      const Eigen::Vector2d p(x, y);
      EXPECT_LT((camera.Undistort(camera.Distort(p)) - p).norm(), 1e-12) << p.transpose();
    }
  }
}

TEST(CameraModelTest, MatchesOpenCvProjectPoints) {
  for (const LaserCameraCalibration& calibration : {Morduc(), WithLens()}) {
    const CameraModel camera(calibration, Eye::kRight);
    const Eigen::Isometry3d& camera_from_laser = camera.camera_from_laser();
    const Eigen::AngleAxisd angle_axis(camera_from_laser.linear());
    const Eigen::Vector3d rotation = angle_axis.angle() * angle_axis.axis();
    const cv::Vec3d rvec(rotation.x(), rotation.y(), rotation.z());
    const cv::Vec3d tvec(camera_from_laser.translation().x(), camera_from_laser.translation().y(),
                         camera_from_laser.translation().z());
    const Eigen::Matrix3d k = camera.IntrinsicMatrix();
    const cv::Matx33d camera_matrix(k(0, 0), k(0, 1), k(0, 2), k(1, 0), k(1, 1), k(1, 2), k(2, 0),
                                    k(2, 1), k(2, 2));
    const DistortionCoefficients& d = calibration.distortion;
    const std::vector<double> dist = {d.k1, d.k2, d.p1, d.p2, d.k3};

    std::vector<cv::Point3d> object_points;
    std::vector<Eigen::Vector2d> ours;
    for (double x = 1.0; x <= 6.0; x += 0.7) {
      for (double y = -2.0; y <= 2.0; y += 0.5) {
        for (double z : {-0.4, 0.0, 0.8}) {
          const std::optional<Eigen::Vector2d> pixel = camera.Project(Eigen::Vector3d(x, y, z));
          if (!pixel.has_value() || !camera.IsInImage(*pixel)) continue;
          object_points.emplace_back(x, y, z);
          ours.push_back(*pixel);
        }
      }
    }
    ASSERT_GT(object_points.size(), 50u);
    std::vector<cv::Point2d> theirs;
    cv::projectPoints(object_points, rvec, tvec, camera_matrix, dist, theirs);
    for (size_t i = 0; i < ours.size(); ++i) {
      EXPECT_NEAR(ours[i].x(), theirs[i].x, 1e-6);
      EXPECT_NEAR(ours[i].y(), theirs[i].y, 1e-6);
    }
  }
}

Eigen::Vector2d ProjectWithGl(const GlMatrices& gl, const Eigen::Vector3d& point_laser,
                              const ImageRegion& region, double* ndc_z) {
  const Eigen::Vector4f clip = gl.projection * gl.view * point_laser.cast<float>().homogeneous();
  const Eigen::Vector3d ndc = (clip.head<3>() / clip.w()).cast<double>();
  *ndc_z = ndc.z();
  return NdcToPixel(ndc.head<2>(), region);
}

TEST(CameraModelTest, GlMatricesDrawWhatProjectComputes) {
  LaserCameraCalibration calibration = WithLens();
  calibration.distortion = DistortionCoefficients{};
  const CameraModel camera(calibration, Eye::kLeft);
  const ImageRegion cropped{10.5, -20.5, 600.0, 450.0};
  for (const ImageRegion& region : {camera.FullImage(), cropped}) {
    const GlMatrices gl = camera.OpenGlMatrices(0.05, 50.0, region);
    for (double x = 0.5; x <= 10.0; x += 0.5) {
      for (double y = -3.0; y <= 3.0; y += 0.75) {
        const Eigen::Vector3d point(x, y, -0.4 + 0.1 * y);
        const std::optional<Eigen::Vector2d> pixel = camera.Project(point);
        if (!pixel.has_value()) continue;
        double ndc_z = 0.0;
        const Eigen::Vector2d gl_pixel = ProjectWithGl(gl, point, region, &ndc_z);
        // float precision: a few thousandths of a pixel.
        EXPECT_NEAR(gl_pixel.x(), pixel->x(), 5e-3) << point.transpose();
        EXPECT_NEAR(gl_pixel.y(), pixel->y(), 5e-3) << point.transpose();
        EXPECT_GT(ndc_z, -1.0);
        EXPECT_LT(ndc_z, 1.0);
      }
    }
  }
  // Default overload = full image.
  EXPECT_TRUE(
      camera.OpenGlMatrices(0.05, 50.0)
          .projection.isApprox(camera.OpenGlMatrices(0.05, 50.0, camera.FullImage()).projection));
}

TEST(CameraModelTest, GlDepthIsMonotonicAlongTheOpticalAxis) {
  const CameraModel camera(Morduc(), kMonoCamera);
  const GlMatrices gl = camera.OpenGlMatrices(0.1, 30.0);
  double near_z = 0.0;
  double far_z = 0.0;
  ProjectWithGl(gl, Eigen::Vector3d(1.5, 0, -0.4), camera.FullImage(), &near_z);
  ProjectWithGl(gl, Eigen::Vector3d(6.0, 0, -0.4), camera.FullImage(), &far_z);
  EXPECT_LT(near_z, far_z);
}

TEST(CameraModelTest, FloorRayFromTheRobotBaseIsClippedToTheImage) {
  for (const LaserCameraCalibration& calibration : {Morduc(), WithLens()}) {
    const CameraModel camera(calibration, kMonoCamera);
    const Eigen::Vector3d base(0.0, 0.0, -calibration.laser_height_m);
    for (double angle = -0.5; angle <= 0.5; angle += 0.1) {
      const Eigen::Vector3d direction =
          Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0).normalized();
      const std::optional<ImageRay> ray = camera.ProjectRayToImage(base, direction, 6.0);
      ASSERT_TRUE(ray.has_value()) << angle;
      EXPECT_GT(ray->start_t_m, 0.5);  // the base itself is below the field of view
      EXPECT_LE(ray->end_t_m, 6.0);
      EXPECT_TRUE(camera.IsInImage(ray->start_px));
      EXPECT_TRUE(camera.IsInImage(ray->end_px));
      // The start lies on the image border (bottom or side).
      const Eigen::Vector2d s = ray->start_px;
      const double border_distance = std::min({s.x() + 0.5, 639.5 - s.x(), 479.5 - s.y()});
      EXPECT_LT(border_distance, 0.05) << angle << " " << s.transpose();
      // Just before the start the ray is outside the image.
      const std::optional<Eigen::Vector2d> before =
          camera.Project(base + (ray->start_t_m - 0.01) * direction);
      EXPECT_TRUE(!before.has_value() || !camera.IsInImage(*before));
      for (double t = ray->start_t_m; t <= ray->end_t_m; t += 0.1) {
        EXPECT_TRUE(camera.IsInImage(*camera.Project(base + t * direction))) << t;
      }
    }
  }
}

TEST(CameraModelTest, RayOutsideTheFieldOfViewIsNotVisible) {
  const CameraModel camera(Morduc(), kMonoCamera);
  const Eigen::Vector3d base(0.0, 0.0, -0.4);
  EXPECT_FALSE(camera.ProjectRayToImage(base, Eigen::Vector3d(-1, 0, 0), 5.0).has_value());
  EXPECT_FALSE(camera.ProjectRayToImage(base, Eigen::Vector3d(0, 1, 0), 5.0).has_value());
  EXPECT_FALSE(camera.ProjectRayToImage(base, Eigen::Vector3d(1, 0, 0), 0.5).has_value());
  EXPECT_FALSE(camera.ProjectRayToImage(base, Eigen::Vector3d::Zero(), 5.0).has_value());
}

TEST(CameraModelTest, IsValidNamesTheViolatedConstraint) {
  struct Case {
    void (*mutate)(LaserCameraCalibration*);
    const char* expected;
  };
  const Case cases[] = {
      {[](LaserCameraCalibration* c) { c->focal_px = 0.0; }, "focal_px must be > 0"},
      {[](LaserCameraCalibration* c) { c->focal_y_px = -1.0; }, "focal_y_px must be > 0"},
      {[](LaserCameraCalibration* c) { c->image_width_px = 0; }, "image_width_px must be > 0"},
      {[](LaserCameraCalibration* c) { c->image_height_px = -5; }, "image_height_px"},
      {[](LaserCameraCalibration* c) { c->principal_x_px = 700.0; }, "principal_x_px"},
      {[](LaserCameraCalibration* c) { c->tilt_rad = 1.6; }, "tilt_rad must be in"},
      {[](LaserCameraCalibration* c) { c->pan_rad = -2.0; }, "pan_rad"},
      {[](LaserCameraCalibration* c) { c->roll_rad = 1.0; }, "roll_rad"},
      {[](LaserCameraCalibration* c) { c->camera_z_m = NAN; }, "camera_z_m must be finite"},
      {[](LaserCameraCalibration* c) { c->distortion.k2 = INFINITY; }, "distortion.k2"},
      {[](LaserCameraCalibration* c) { c->laser_height_m = 0.0; }, "laser_height_m must be > 0"},
      {[](LaserCameraCalibration* c) { c->camera_y_m = -1.0; }, "camera must be above the floor"},
      {[](LaserCameraCalibration* c) { c->left_eye_x_offset_m = 0.1; }, "left eye is on the left"},
  };
  for (const Case& c : cases) {
    LaserCameraCalibration calibration;
    c.mutate(&calibration);
    std::string error;
    EXPECT_FALSE(calibration.IsValid(&error)) << c.expected;
    EXPECT_NE(error.find(c.expected), std::string::npos) << error;
    EXPECT_FALSE(calibration.IsValid(nullptr));
    EXPECT_FALSE(CameraModel::Create(calibration, kMonoCamera, &error).has_value());
  }
  std::string error;
  EXPECT_TRUE(CameraModel::Create(Morduc(), kMonoCamera, &error).has_value()) << error;
}

TEST(CameraModelTest, TiltIsTheAngleOfTheOpticalAxisBelowHorizontal) {
  LaserCameraCalibration calibration;
  calibration.tilt_rad = 12.0 * kPi / 180.0;
  const CameraModel camera(calibration, kMonoCamera);
  const Eigen::Vector3d axis =
      camera.PixelRayInLaser(Eigen::Vector2d(camera.calibration().cx(), camera.calibration().cy()));
  EXPECT_NEAR(std::asin(-axis.z()), calibration.tilt_rad, 1e-12);
  EXPECT_NEAR(axis.y(), 0.0, 1e-12);
}

}  // namespace
}  // namespace mostar::math
