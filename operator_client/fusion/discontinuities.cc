#include "operator_client/fusion/discontinuities.h"

#include <cmath>
#include <limits>

#include "common/check/check.h"

namespace mostar::fusion {

bool SegmentationOptions::IsValid(std::string* error) const {
  const auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (!(slope_threshold > 0.f && slope_threshold <= 2.f)) {
    return fail("slope_threshold must be in (0, 2] (got " + std::to_string(slope_threshold) + ")");
  }
  if (max_outlier_run_points < 0) {
    return fail("max_outlier_run_points must be >= 0 (got " +
                std::to_string(max_outlier_run_points) + ")");
  }
  return true;
}

bool ScanSegmentation::AtDiscontinuity(size_t beam) const {
  const size_t walls = wall_discontinuity.size();
  return (beam < walls && wall_discontinuity[beam] != 0) ||
         (beam > 0 && beam - 1 < walls && wall_discontinuity[beam - 1] != 0);
}

bool IsUsableRange(const LaserScan& scan, float range_m) {
  if (!LaserScan::IsValidRange(range_m)) return false;
  if (scan.range_max_m > scan.range_min_m) {
    return range_m >= scan.range_min_m && range_m <= scan.range_max_m;
  }
  return true;
}

void SegmentScan(const LaserScan& scan, const SegmentationOptions& options, ScanSegmentation* out) {
  MOSTAR_CHECK(options.IsValid(nullptr));
  const std::vector<float>& ranges = scan.ranges_m;
  const size_t n = ranges.size();
  const size_t walls = n > 0 ? n - 1 : 0;
  out->valid.assign(n, 0);
  out->wall_exists.assign(walls, 0);
  out->wall_discontinuity.assign(walls, 0);
  out->wall_slope.assign(walls, std::numeric_limits<float>::quiet_NaN());
  out->potential_outlier.assign(n, 0);
  out->clusters.clear();
  out->invalid_beams = 0;

  const bool angles_finite =
      std::isfinite(scan.angle_min_rad) && std::isfinite(scan.angle_increment_rad);
  for (size_t i = 0; i < n; ++i) {
    out->valid[i] = angles_finite && IsUsableRange(scan, ranges[i]) ? 1 : 0;
    if (out->valid[i] == 0) ++out->invalid_beams;
  }
  for (size_t i = 0; i < walls; ++i) {
    if (out->valid[i] != 0 && out->valid[i + 1] != 0) {
      out->wall_exists[i] = 1;
      out->wall_slope[i] = WallSlope(ranges[i], ranges[i + 1]);
    }
  }
  // A wall is a discontinuity when its slope differs from every existing neighbour's by more
  // than the threshold (a wall without neighbours has nothing to differ from).
  for (size_t i = 0; i < walls; ++i) {
    if (out->wall_exists[i] == 0) continue;
    int neighbours = 0;
    bool differs_from_all = true;
    for (const long j : {static_cast<long>(i) - 1, static_cast<long>(i) + 1}) {
      if (j < 0 || j >= static_cast<long>(walls)) continue;
      const size_t k = static_cast<size_t>(j);
      if (out->wall_exists[k] == 0) continue;
      ++neighbours;
      if (!(std::abs(out->wall_slope[i] - out->wall_slope[k]) > options.slope_threshold)) {
        differs_from_all = false;
      }
    }
    out->wall_discontinuity[i] = neighbours > 0 && differs_from_all ? 1 : 0;
  }
  // Clusters: runs of valid beams joined by existing, continuous walls.
  size_t i = 0;
  while (i < n) {
    if (out->valid[i] == 0) {
      ++i;
      continue;
    }
    Cluster cluster;
    cluster.first_beam = i;
    cluster.nearest_beam = i;
    cluster.nearest_range_m = ranges[i];
    while (i + 1 < n && out->wall_exists[i] != 0 && out->wall_discontinuity[i] == 0) {
      ++i;
      if (ranges[i] < cluster.nearest_range_m) {
        cluster.nearest_range_m = ranges[i];
        cluster.nearest_beam = i;
      }
    }
    cluster.last_beam = i;
    out->clusters.push_back(cluster);
    ++i;
  }
  // Potential outliers: short clusters bounded by discontinuity walls on both sides.
  const size_t max_run = static_cast<size_t>(options.max_outlier_run_points);
  for (const Cluster& cluster : out->clusters) {
    if (cluster.size() > max_run) continue;
    const bool before = cluster.first_beam > 0 && out->wall_discontinuity[cluster.first_beam - 1];
    const bool after = cluster.last_beam < walls && out->wall_discontinuity[cluster.last_beam];
    if (!before || !after) continue;
    for (size_t b = cluster.first_beam; b <= cluster.last_beam; ++b) out->potential_outlier[b] = 1;
  }
}

}  // namespace mostar::fusion
