#include "operator_client/vision/sim_calibration.h"

namespace mostar::vision {

math::LaserCameraCalibration MathCalibrationFromSim(const sim::LaserCameraCalibration& sim,
                                                    Eye eye, double laser_height_m) {
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

}  // namespace mostar::vision
