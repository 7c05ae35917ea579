#include "operator_client/fusion/predicted_path.h"

#include <algorithm>
#include <cmath>

#include "common/check/check.h"

namespace mostar::fusion {

bool PredictedPathOptions::IsValid(std::string* error) const {
  const auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (!(std::isfinite(horizon_s) && horizon_s > 0.f)) {
    return fail("horizon_s must be > 0 (got " + std::to_string(horizon_s) + ")");
  }
  if (!(std::isfinite(step_s) && step_s > 0.f && step_s <= horizon_s)) {
    return fail("step_s must be in (0, horizon_s] (got " + std::to_string(step_s) + ")");
  }
  if (horizon_s / step_s > 10000.f) return fail("horizon_s / step_s must be <= 10000");
  if (!(std::isfinite(half_width_m) && half_width_m >= 0.f)) {
    return fail("half_width_m must be >= 0 (got " + std::to_string(half_width_m) + ")");
  }
  if (!std::isfinite(rotation_center_x_m)) return fail("rotation_center_x_m must be finite");
  if (!(std::isfinite(laser_height_m) && laser_height_m > 0.f)) {
    return fail("laser_height_m must be > 0 (got " + std::to_string(laser_height_m) + ")");
  }
  return true;
}

PlanarPose PoseAfter(double linear_mps, double angular_radps, double t_s) {
  PlanarPose pose;
  pose.theta_rad = angular_radps * t_s;
  if (std::abs(angular_radps) < 1e-9) {
    pose.x_m = linear_mps * t_s;
    return pose;
  }
  const double radius = linear_mps / angular_radps;
  pose.x_m = radius * std::sin(pose.theta_rad);
  pose.y_m = radius * (1.0 - std::cos(pose.theta_rad));
  return pose;
}

void BuildPredictedPath(double linear_mps, double angular_radps,
                        const PredictedPathOptions& options, VertexArray* out) {
  MOSTAR_CHECK(options.IsValid(nullptr));
  out->Clear();
  if (!std::isfinite(linear_mps) || !std::isfinite(angular_radps)) return;
  const int steps = static_cast<int>(std::ceil(options.horizon_s / options.step_s - 1e-4f));
  const float floor_z = -options.laser_height_m;
  const double offsets[3] = {0.0, options.half_width_m, -options.half_width_m};
  const int lines = options.half_width_m > 0.f ? 3 : 1;
  out->Reserve(static_cast<size_t>(2 * steps * lines));
  for (int line = 0; line < lines; ++line) {
    const double lateral = offsets[line];
    float previous_x = 0.f;
    float previous_y = 0.f;
    for (int s = 0; s <= steps; ++s) {
      const double t = std::min(static_cast<double>(options.horizon_s), s * options.step_s * 1.0);
      const PlanarPose pose = PoseAfter(linear_mps, angular_radps, t);
      // Point `lateral` to the left of the rotation centre, then into the laser frame.
      const float x = static_cast<float>(options.rotation_center_x_m + pose.x_m -
                                         lateral * std::sin(pose.theta_rad));
      const float y = static_cast<float>(pose.y_m + lateral * std::cos(pose.theta_rad));
      if (s > 0) {
        out->Add(previous_x, previous_y, floor_z, options.color);
        out->Add(x, y, floor_z, options.color);
      }
      previous_x = x;
      previous_y = y;
    }
  }
}

}  // namespace mostar::fusion
