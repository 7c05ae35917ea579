// For tests and benches only (links the simulator): the simulator's true laser-camera
// calibration in the terms of common/math's model, one CameraModel per eye.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "common/math/camera_model.h"
#include "robot_server/sim/ground_truth.h"
#include "robot_server/sim/scene.pb.h"
#include "robot_server/sim/sim_world.h"

namespace mostar::vision {

// The simulator places cameras in laser-frame coordinates (x forward, y left, z up; left eye at
// +baseline/2 along y); common/math uses the thesis' camera_x (right), camera_y (up), camera_z
// (ahead). The right eye may have its own principal point row, hence a calibration per eye.
math::LaserCameraCalibration MathCalibrationFromSim(const sim::LaserCameraCalibration& sim, Eye eye,
                                                    double laser_height_m);

std::shared_ptr<const math::CameraModel> SimCameraModel(const sim::LaserCameraCalibration& sim,
                                                        Eye eye, double laser_height_m);

// The repository root: $MOSTAR_SOURCE_DIR (set by CTest), else ".".
std::string SourceDir();

// Loads deploy/scenes/<name>.pbtxt from SourceDir().
bool LoadSimScene(const std::string& name, sim::proto::Scene* scene, std::string* error);

// Floor distance from the robot base to the nearest obstacle footprint (glass included), per
// beam of the simulated laser (same beams as its scans): a raycast 1 cm above the floor.
// +Inf: none.
std::vector<float> TrueBaseDistances(const sim::SimWorld& world, const Pose2D& world_from_base);

// Pixel distance (CV_32F) from every pixel to the nearest base line of the simulator's `labels`:
// the obstacle pixel sitting on the floor and the floor pixel under it (the edge lies between
// the two; Canny marks either).
cv::Mat DistanceToBaseLines(const cv::Mat& labels);

}  // namespace mostar::vision
