#include "robot_server/sim/diff_drive.h"

#include <algorithm>
#include <cmath>

namespace mostar::sim {
namespace {

double Approach(double current, double target, double max_delta) {
  return current + std::clamp(target - current, -max_delta, max_delta);
}

constexpr double kContactMargin_m = 0.01;

uint64_t Wrap(int64_t total, int bits) {
  const uint64_t mask = bits >= 64 ? ~0ull : ((1ull << bits) - 1);
  return static_cast<uint64_t>(total) & mask;
}

}  // namespace

DriveParams DriveParams::FromProto(const proto::DriveConfig& c) {
  DriveParams p;
  p.wheel_radius_m = c.wheel_radius_m();
  p.track_width_m = c.track_width_m();
  p.axle_x_m = c.axle_x_m();
  p.footprint_radius_m = c.footprint_radius_m();
  p.footprint_center_x_m = c.footprint_center_x_m();
  p.max_linear_mps = c.max_linear_mps();
  p.max_angular_radps = c.max_angular_radps();
  p.max_linear_accel_mps2 = c.max_linear_accel_mps2();
  p.max_angular_accel_radps2 = c.max_angular_accel_radps2();
  p.step = FromSeconds(c.step_s());
  p.encoder_pulses_per_turn = c.encoder_pulses_per_turn();
  p.encoder_quadrature_x4 = c.encoder_quadrature_x4();
  p.encoder_counter_bits = c.encoder_counter_bits();
  return p;
}

DiffDrive::DiffDrive(const DriveParams& params, const Pose2D& world_from_base,
                     std::function<bool(double, double, double)> collides)
    : params_(params), collides_(std::move(collides)) {
  theta_rad_ = world_from_base.theta_rad;
  x_m_ = world_from_base.x_m + params_.axle_x_m * std::cos(theta_rad_);
  y_m_ = world_from_base.y_m + params_.axle_x_m * std::sin(theta_rad_);
}

void DiffDrive::SetCommand(double linear_mps, double angular_radps) {
  if (!std::isfinite(linear_mps)) linear_mps = 0;
  if (!std::isfinite(angular_radps)) angular_radps = 0;
  cmd_linear_mps_ = std::clamp(linear_mps, -params_.max_linear_mps, params_.max_linear_mps);
  cmd_angular_radps_ =
      std::clamp(angular_radps, -params_.max_angular_radps, params_.max_angular_radps);
}

void DiffDrive::Advance(Duration dt) {
  if (dt <= Duration::zero()) return;
  pending_ += dt;
  const double step_s = ToSeconds(params_.step);
  while (pending_ >= params_.step) {
    Step(step_s);
    pending_ -= params_.step;
    elapsed_ += params_.step;
  }
}

void DiffDrive::Step(double dt) {
  const double v = Approach(linear_mps_, cmd_linear_mps_, params_.max_linear_accel_mps2 * dt);
  const double w =
      Approach(angular_radps_, cmd_angular_radps_, params_.max_angular_accel_radps2 * dt);
  // Exact integration of a constant twist over the step (an arc).
  const double dtheta = w * dt;
  double dx, dy;
  if (std::abs(dtheta) < 1e-9) {
    dx = v * dt * std::cos(theta_rad_ + dtheta / 2);
    dy = v * dt * std::sin(theta_rad_ + dtheta / 2);
  } else {
    const double r = v / w;
    dx = r * (std::sin(theta_rad_ + dtheta) - std::sin(theta_rad_));
    dy = -r * (std::cos(theta_rad_ + dtheta) - std::cos(theta_rad_));
  }
  const double nx = x_m_ + dx, ny = y_m_ + dy, ntheta = theta_rad_ + dtheta;
  const double off = params_.footprint_center_x_m - params_.axle_x_m;
  const bool blocked = (v != 0 || w != 0) && collides_ &&
                       collides_(nx + off * std::cos(ntheta), ny + off * std::sin(ntheta),
                                 params_.footprint_radius_m);
  if (blocked) {
    if (!in_collision_) ++collision_count_;
    in_collision_ = true;
    linear_mps_ = 0;
    angular_radps_ = 0;
    return;
  }
  // Contact ends once the robot is clear by a margin, so creeping along an obstacle under a
  // standing command is one contact, not one per step.
  in_collision_ = in_collision_ && collides_ &&
                  collides_(nx + off * std::cos(ntheta), ny + off * std::sin(ntheta),
                            params_.footprint_radius_m + kContactMargin_m);
  linear_mps_ = v;
  angular_radps_ = w;
  x_m_ = nx;
  y_m_ = ny;
  theta_rad_ = std::remainder(ntheta, 2 * M_PI);
  // Wheel rotations: each wheel rolls (v -+ w * track / 2) * dt.
  const double counts_per_m = params_.CountsPerTurn() / (2 * M_PI * params_.wheel_radius_m);
  left_counts_ += (v - w * params_.track_width_m / 2) * dt * counts_per_m;
  right_counts_ += (v + w * params_.track_width_m / 2) * dt * counts_per_m;
}

Pose2D DiffDrive::world_from_base() const {
  Pose2D p;
  p.theta_rad = theta_rad_;
  p.x_m = x_m_ - params_.axle_x_m * std::cos(theta_rad_);
  p.y_m = y_m_ - params_.axle_x_m * std::sin(theta_rad_);
  return p;
}

EncoderTicks DiffDrive::encoders() const {
  EncoderTicks t;
  t.left_total = static_cast<int64_t>(std::floor(left_counts_));
  t.right_total = static_cast<int64_t>(std::floor(right_counts_));
  t.left = Wrap(t.left_total, params_.encoder_counter_bits);
  t.right = Wrap(t.right_total, params_.encoder_counter_bits);
  return t;
}

}  // namespace mostar::sim
