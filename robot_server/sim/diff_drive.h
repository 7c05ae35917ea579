// Differential-drive model of the MORDUC base: two driven wheels on one axle and a castor.
//
// Pure and deterministic: time is injected (Advance), integration uses a fixed step, and the
// only world query is the collision test. Poses are world_from_base (base frame: origin on the
// floor under the laser, x forward); the commanded twist is that of the axle midpoint, which
// sits at `axle_x_m` on the base x axis. Not thread-safe: SimWorld serialises access.
#pragma once

#include <cstdint>
#include <functional>

#include "common/time/time.h"
#include "common/types/odometry.h"
#include "robot_server/sim/sim_config.pb.h"

namespace mostar::sim {

struct DriveParams {
  double wheel_radius_m = 0.08;
  double track_width_m = 0.46;
  double axle_x_m = -0.25;
  double footprint_radius_m = 0.34;
  double footprint_center_x_m = -0.22;
  double max_linear_mps = 0.6;
  double max_angular_radps = 1.2;
  double max_linear_accel_mps2 = 0.8;
  double max_angular_accel_radps2 = 2.5;
  Duration step = FromMilliseconds(5);
  int encoder_pulses_per_turn = 500;
  bool encoder_quadrature_x4 = false;
  int encoder_counter_bits = 16;

  static DriveParams FromProto(const proto::DriveConfig& config);
  // Encoder counts per wheel turn (pulses, times 4 in quadrature mode).
  double CountsPerTurn() const {
    return encoder_pulses_per_turn * (encoder_quadrature_x4 ? 4.0 : 1.0);
  }
};

// Encoder counters as the hardware shows them, plus the unwrapped totals (ground truth).
struct EncoderTicks {
  uint64_t left = 0;  // wrapped to encoder_counter_bits (two's complement of the total)
  uint64_t right = 0;
  int64_t left_total = 0;  // unwrapped count since start; forward = positive
  int64_t right_total = 0;
};

class DiffDrive {
 public:
  // `collides(x, y, radius)` tells whether a footprint circle centred at world (x, y) overlaps
  // an obstacle. The start pose is taken as is (the caller checks it is free).
  DiffDrive(const DriveParams& params, const Pose2D& world_from_base,
            std::function<bool(double, double, double)> collides);

  // Latest command, clamped to the velocity limits; it holds until replaced.
  void SetCommand(double linear_mps, double angular_radps);
  // Runs fixed steps covering `dt` (the remainder is carried to the next call). dt <= 0: no-op.
  void Advance(Duration dt);

  Pose2D world_from_base() const;
  double linear_mps() const { return linear_mps_; }
  double angular_radps() const { return angular_radps_; }
  EncoderTicks encoders() const;
  Duration elapsed() const { return elapsed_; }  // simulated time integrated so far
  // True from a refused step until the footprint is clear of obstacles by 1 cm.
  bool in_collision() const { return in_collision_; }
  uint64_t collision_count() const { return collision_count_; }  // contacts started
  const DriveParams& params() const { return params_; }

 private:
  void Step(double dt_s);

  DriveParams params_;
  std::function<bool(double, double, double)> collides_;
  double x_m_ = 0, y_m_ = 0, theta_rad_ = 0;  // world_from_axle
  double cmd_linear_mps_ = 0, cmd_angular_radps_ = 0;
  double linear_mps_ = 0, angular_radps_ = 0;
  double left_counts_ = 0, right_counts_ = 0;  // unwrapped, fractional
  Duration elapsed_{0};
  Duration pending_{0};
  bool in_collision_ = false;
  uint64_t collision_count_ = 0;
};

}  // namespace mostar::sim
