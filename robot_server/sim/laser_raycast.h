// Simulated SICK LMS200: beams cast in the scan plane against the World.
//
// Beam i has angle angle_min + i * increment in the laser frame (REP-103: x forward, y left,
// counter-clockwise, 0 ahead; the 180 deg scan spans -90..+90 deg). The laser frame is the robot
// base frame raised by `height_m` and pitched down by `pitch_rad` (0 = a horizontal plane, which
// never meets the floor). Range values follow mostar::LaserScan: metres, +Inf = no echo (nothing
// within the maximum range, a NO_ECHO surface, a dark ABSORB_DARK cell, a dark floor square that
// absorbs), NaN = the scanner's error code (a DAZZLE surface). The scan is taken at one pose (the
// motion during the ~13 ms sweep is ignored).
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "common/time/time.h"
#include "common/types/laser_scan.h"
#include "common/types/odometry.h"
#include "robot_server/sim/sim_config.pb.h"
#include "robot_server/sim/world.h"

namespace mostar::sim {

struct LaserParams {
  double height_m = 0.35;
  double pitch_rad = 0.0;
  double fov_rad = M_PI;                // 180 or 100 deg
  double increment_rad = M_PI / 360.0;  // 1, 0.5 or 0.25 deg
  double range_max_m = 8.183;           // 8.183 (mm mode) or 81.83 (cm mode)
  double range_min_m = 0.02;
  double noise_sigma_m = 0.005;
  double scan_period_s = 0.0266667;

  static LaserParams FromProto(const proto::LaserConfig& config);
  size_t BeamCount() const;
  double AngleMin() const { return -fov_rad / 2; }
};

// Noise-free ranges (metres) seen from world_from_base: the distance to the first surface that
// is not TRANSPARENT, whatever its laser response; +Inf when none within range_max_m. This is
// the ground truth of a scan, beam by beam.
std::vector<float> TrueRangesAt(const World& world, const LaserParams& params,
                                const Pose2D& world_from_base);

// Produces scans with the LMS200's noise and failure modes. Not thread-safe (owns the random
// generator); SimWorld serialises calls.
class LaserRaycaster {
 public:
  LaserRaycaster(const World& world, const LaserParams& params, uint64_t seed);

  // One scan from world_from_base, stamped `stamp`. `true_ranges_m` (optional) receives the
  // noise-free ranges of the same beams.
  LaserScan Scan(const Pose2D& world_from_base, Time stamp, std::vector<float>* true_ranges_m);

  // Noisy (and, optionally, true) ranges of `count` beams at angle_min + i * increment (laser
  // frame), for callers that choose their own beam layout (the LMS200 emulator).
  void Measure(const Pose2D& world_from_base, double angle_min_rad, double increment_rad, int count,
               std::vector<float>* ranges_m, std::vector<float>* true_ranges_m);

  const LaserParams& params() const { return params_; }

 private:
  const World& world_;
  LaserParams params_;
  std::mt19937_64 rng_;
  uint64_t sequence_ = 0;
};

}  // namespace mostar::sim
