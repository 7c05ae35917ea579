// Differential-drive dead reckoning from successive wheel encoder readings.
//
// Model. Between two readings the left and right wheels roll ds_l and ds_r metres
// (ticks * 2*pi*r / ticks_per_turn). The base moves ds = (ds_r + ds_l) / 2 and turns
// dtheta = (ds_r - ds_l) / track_width along a circular arc (exact for constant wheel speeds):
//   x += chord * cos(theta + dtheta/2),  y += chord * sin(theta + dtheta/2),  theta += dtheta
// with chord = ds * sin(dtheta/2) / (dtheta/2) (= ds when dtheta = 0).
//
// Uncertainty. Each wheel's travel error is zero-mean with variance proportional to the
// distance that wheel rolled: var(ds_l) = k * |ds_l|, var(ds_r) = k * |ds_r|
// (k = `wheel_variance_m2_per_m`; uncorrelated wheels, after Siegwart & Nourbakhsh,
// "Introduction to Autonomous Mobile Robots", 5.2.4). The 3x3 pose covariance is propagated
// with the Jacobians of the motion above: P' = Fp P Fp^T + Fw diag(k|ds_r|, k|ds_l|) Fw^T. It
// only grows with travelled distance (rotation in place also rolls the wheels); it never shrinks,
// since nothing here observes the world. `Odometry::pose_variance` is its diagonal.
//
// Frames: odom frame = base pose at the first reading (or at `Reset`), x forward, y left.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "common/types/odometry.h"
#include "robot_server/drive/wheel_encoders.h"

namespace mostar::drive {

struct OdometryOptions {
  double wheel_radius_m = 0.10;  // rolling radius of both drive wheels
  // Where the wheel axle's midpoint (the point the differential drive turns about) lies in
  // base_link (x forward from the point under the laser; negative = behind the laser). The
  // reported pose is base_link's; 0 puts base_link on the axle.
  double axle_x_m = 0.0;
  double track_width_m = 0.50;            // distance between the wheel contact points
  double ticks_per_turn = 500;            // encoder ticks per wheel turn
  int counter_bits = 16;                  // significant bits of the raw counters, [8, 32]
  double wheel_variance_m2_per_m = 1e-4;  // k above: 1 cm standard deviation per metre
  // A tick delta implying a faster wheel is a glitch: the reading is refused and counted, and
  // becomes the new reference.
  double max_wheel_speed_mps = 3.0;

  bool IsValid(std::string* error) const;
  double metres_per_tick() const;
};

struct OdometryStats {
  uint64_t readings = 0;      // integrated
  uint64_t out_of_order = 0;  // steady stamp not after the previous reading: ignored
  uint64_t glitches = 0;      // implausible jumps: reference reset, not integrated
};

// Not thread-safe: owned by the drive thread.
class OdometryIntegrator {
 public:
  explicit OdometryIntegrator(const OdometryOptions& options);

  // Integrates one reading. The first reading (and the first after a glitch or `Reset`) only
  // becomes the reference. Returns false for a reading that was not integrated (first,
  // out of order, glitch; see `stats()`).
  bool AddReading(const EncoderReading& reading);

  // Latest estimate; velocities are those between the last two integrated readings.
  const Odometry& odometry() const { return odometry_; }
  // Full covariance of (x, y, theta), row-major.
  const std::array<double, 9>& pose_covariance() const { return covariance_; }
  const OdometryStats& stats() const { return stats_; }

  // Restarts at `pose` with zero covariance; the next reading is a reference.
  void Reset(const Pose2D& pose = {});

 private:
  OdometryOptions options_;
  double metres_per_tick_;
  std::optional<EncoderReading> previous_;
  Pose2D axle_pose_;   // odom_from_axle: what the wheels integrate
  Odometry odometry_;  // odom_from_base
  std::array<double, 9> covariance_{};
  OdometryStats stats_;
};

}  // namespace mostar::drive
