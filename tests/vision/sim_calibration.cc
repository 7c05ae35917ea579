#include "tests/vision/sim_calibration.h"

#include <cstdlib>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "robot_server/sim/laser_raycast.h"
#include "robot_server/sim/scene.h"

namespace mostar::vision {

math::LaserCameraCalibration MathCalibrationFromSim(const sim::LaserCameraCalibration& sim, Eye eye,
                                                    double laser_height_m) {
  math::LaserCameraCalibration c;
  c.image_width_px = sim.width_px;
  c.image_height_px = sim.height_px;
  c.focal_px = sim.focal_px;
  c.principal_x_px = sim.cx_px;
  c.principal_y_px = sim.Cy(eye);
  c.distortion.k1 = sim.k1;
  c.distortion.k2 = sim.k2;
  c.camera_x_m = -sim.camera_y_m;  // right of the laser = -laser y
  c.camera_y_m = sim.camera_z_m;   // above the scan plane = laser z
  c.camera_z_m = sim.camera_x_m;   // ahead = laser x
  c.tilt_rad = sim.tilt_rad;
  c.roll_rad = sim.Roll(eye);
  c.left_eye_x_offset_m = -0.5 * sim.baseline_m;
  c.right_eye_x_offset_m = 0.5 * sim.baseline_m;
  c.laser_height_m = laser_height_m;
  return c;
}

std::shared_ptr<const math::CameraModel> SimCameraModel(const sim::LaserCameraCalibration& sim,
                                                        Eye eye, double laser_height_m) {
  return std::make_shared<const math::CameraModel>(
      MathCalibrationFromSim(sim, eye, laser_height_m),
      eye == Eye::kLeft ? math::Eye::kLeft : math::Eye::kRight);
}

std::string SourceDir() {
  const char* dir = std::getenv("MOSTAR_SOURCE_DIR");
  return dir != nullptr ? dir : ".";
}

bool LoadSimScene(const std::string& name, sim::proto::Scene* scene, std::string* error) {
  return sim::LoadScene(SourceDir() + "/deploy/scenes/" + name + ".pbtxt", scene, error);
}

std::vector<float> TrueBaseDistances(const sim::SimWorld& world, const Pose2D& world_from_base) {
  // Transparent obstacles (glass) count: the cameras see their bases even if the laser does not.
  const sim::LaserParams& laser = world.laser_params();
  std::vector<float> out(laser.BeamCount());
  for (size_t i = 0; i < out.size(); ++i) {
    const double azimuth_rad =
        world_from_base.theta_rad + laser.AngleMin() + static_cast<double>(i) * laser.increment_rad;
    const sim::RayHit hit =
        world.world().Trace(world_from_base.x_m, world_from_base.y_m, 0.01, azimuth_rad, 0.0, 100.0,
                            /*skip_transparent=*/false);
    out[i] = hit.kind == sim::RayHit::kObstacle ? static_cast<float>(hit.h_m)
                                                : std::numeric_limits<float>::infinity();
  }
  return out;
}

cv::Mat DistanceToBaseLines(const cv::Mat& labels) {
  cv::Mat not_base(labels.size(), CV_8U, cv::Scalar(255));
  for (const cv::Point& p : sim::BaseLinePixels(labels)) {
    not_base.at<uint8_t>(p) = 0;
    not_base.at<uint8_t>(p + cv::Point(0, 1)) = 0;
  }
  cv::Mat distance;
  cv::distanceTransform(not_base, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  return distance;
}

}  // namespace mostar::vision
