// Planar odometry of the robot base in the odom frame (x forward at start, y left; m, rad).
#pragma once

#include <array>

#include "common/time/time.h"

namespace mostar {

struct Pose2D {
  double x_m = 0;
  double y_m = 0;
  double theta_rad = 0;  // counter-clockwise from the odom x axis
};

struct Odometry {
  Time stamp;
  Pose2D pose;                            // odom_from_base
  double linear_mps = 0;                  // base frame, forward
  double angular_radps = 0;               // counter-clockwise
  std::array<double, 3> pose_variance{};  // x (m^2), y (m^2), theta (rad^2); grows with distance
};

}  // namespace mostar
