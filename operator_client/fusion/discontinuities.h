// Discontinuity detection on a laser scan (thesis 6.2): separates objects so that virtual walls
// do not melt them together, and flags isolated points as potential outliers.
//
// Indexing: wall i joins beams i and i + 1 (0 <= i < n - 1). The thesis' slope of the wall
// between points p-1 and p is slope = (d[p-1] - d[p]) / (d[p-1] + d[p]), in [-1, 1].
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/types/laser_scan.h"

namespace mostar::fusion {

// Slope of the wall from a point at `previous_range_m` to the next at `range_m` (both > 0).
inline float WallSlope(float previous_range_m, float range_m) {
  return (previous_range_m - range_m) / (previous_range_m + range_m);
}

struct SegmentationOptions {
  // A wall whose slope differs from the slope of EACH existing adjacent wall by more than this
  // is a discontinuity (thesis slopeTh; 0.05 works in most scenes). In (0, 2].
  float slope_threshold = 0.05f;
  // Runs of at most this many points with discontinuities on both sides are potential outliers.
  // 1 = the thesis' rule (a point between two consecutive discontinuities). >= 0; 0 disables.
  int max_outlier_run_points = 1;

  bool IsValid(std::string* error) const;
};

// A maximal run of valid beams joined by walls that are not discontinuities: one object (or
// one visible piece of one).
struct Cluster {
  size_t first_beam = 0;
  size_t last_beam = 0;     // inclusive
  size_t nearest_beam = 0;  // beam of the smallest range in the cluster
  float nearest_range_m = 0.f;

  size_t size() const { return last_beam - first_beam + 1; }
};

// Result of SegmentScan. Vectors of flags use uint8_t (0/1) so they can be uploaded or copied
// cheaply; reusing one instance avoids allocations.
struct ScanSegmentation {
  std::vector<uint8_t> valid;               // per beam: finite, > 0, within the scan's limits
  std::vector<uint8_t> wall_exists;         // per wall: both beams valid
  std::vector<uint8_t> wall_discontinuity;  // per wall: exists and is a discontinuity
  std::vector<float> wall_slope;            // per wall: slope, NaN when the wall does not exist
  std::vector<uint8_t> potential_outlier;   // per beam
  std::vector<Cluster> clusters;            // in beam order
  size_t invalid_beams = 0;

  size_t beam_count() const { return valid.size(); }
  // True when beam i is an end of a discontinuity wall.
  bool AtDiscontinuity(size_t beam) const;
};

// True when range_m is a usable measurement of `scan`: finite, > 0 and, when the scan states
// its limits (range_max_m > range_min_m), within [range_min_m, range_max_m].
bool IsUsableRange(const LaserScan& scan, float range_m);

// Labels the beams and walls of `scan`. `options` must be valid (asserted). Pure; reuses the
// capacity of `out`.
void SegmentScan(const LaserScan& scan, const SegmentationOptions& options, ScanSegmentation* out);

}  // namespace mostar::fusion
