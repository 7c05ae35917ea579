// For tests and benches only (links the simulator): the simulator's true laser-camera
// calibration in the terms of common/math's model, one CameraModel per eye.
#pragma once

#include <memory>

#include "common/math/camera_model.h"
#include "robot_server/sim/ground_truth.h"

namespace mostar::vision {

// The simulator places cameras in laser-frame coordinates (x forward, y left, z up; left eye at
// +baseline/2 along y); common/math uses the thesis' camera_x (right), camera_y (up), camera_z
// (ahead). The right eye may have its own principal point row, hence a calibration per eye.
math::LaserCameraCalibration MathCalibrationFromSim(const sim::LaserCameraCalibration& sim,
                                                    Eye eye, double laser_height_m);

std::shared_ptr<const math::CameraModel> SimCameraModel(const sim::LaserCameraCalibration& sim,
                                                        Eye eye, double laser_height_m);

}  // namespace mostar::vision
