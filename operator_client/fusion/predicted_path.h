// The robot's predicted path on the floor for a velocity command: constant (v, w) over a
// horizon, for a differential-drive robot turning about the middle of its wheel axle.
#pragma once

#include <string>

#include "operator_client/fusion/vertex_array.h"

namespace mostar::fusion {

struct PredictedPathOptions {
  float horizon_s = 3.0f;            // > 0
  float step_s = 0.1f;               // > 0, <= horizon_s; at most 10000 steps
  float half_width_m = 0.30f;        // >= 0: half the robot's width; 0 = centre line only
  float rotation_center_x_m = 0.0f;  // laser-frame x of the axle middle (negative = behind)
  float laser_height_m = 0.40f;      // > 0; the path lies on the floor z = -laser_height_m
  Rgba color{0.2f, 0.6f, 1.0f, 0.8f};

  bool IsValid(std::string* error) const;
};

// Pose of the rotation centre after t seconds of (v, w), in the frame it started in
// (x forward, y left; theta counter-clockwise). Exact arc; straight when |w| is tiny.
struct PlanarPose {
  double x_m = 0.0;
  double y_m = 0.0;
  double theta_rad = 0.0;
};
PlanarPose PoseAfter(double linear_mps, double angular_radps, double t_s);

// GL_LINES on the floor, laser frame: the centre line of the path and, when half_width_m > 0,
// the left and right edges, each as consecutive segments. Clears `out` first (keeps capacity).
// Non-finite commands give an empty array. `options` must be valid (asserted).
void BuildPredictedPath(double linear_mps, double angular_radps,
                        const PredictedPathOptions& options, VertexArray* out);

}  // namespace mostar::fusion
