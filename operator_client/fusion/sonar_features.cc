#include "operator_client/fusion/sonar_features.h"

#include <algorithm>
#include <cmath>

#include "common/check/check.h"
#include "operator_client/fusion/color_scale.h"

namespace mostar::fusion {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool Fail(std::string* error, const std::string& message) {
  if (error != nullptr) *error = message;
  return false;
}

// Angle in (-pi, pi].
double Wrap(double a) {
  a = std::fmod(a + kPi, 2 * kPi);
  if (a <= 0) a += 2 * kPi;
  return a - kPi;
}

bool HasEcho(const SonarRange& r) {
  return std::isfinite(r.range_m) && r.range_m >= r.min_range_m && r.range_m <= r.max_range_m &&
         r.range_m > 0.f;
}

// True when a valid laser point lies in the central `fraction` of the sonar's cone, no farther
// than its echo + margin.
bool LaserAgrees(const SonarRange& r, const std::vector<ScanPointLabel>& points, float margin_m,
                 float fraction) {
  const double half_fov = 0.5 * fraction * r.field_of_view_rad;
  for (const ScanPointLabel& p : points) {
    if (!p.valid) continue;
    const double dx = p.x_m - r.mount.x_m;
    const double dy = p.y_m - r.mount.y_m;
    const double distance = std::hypot(dx, dy);
    if (distance > r.range_m + margin_m) continue;
    if (std::abs(Wrap(std::atan2(dy, dx) - r.mount.yaw_rad)) <= half_fov) return true;
  }
  return false;
}

}  // namespace

bool SonarFeatureOptions::IsValid(std::string* error) const {
  if (!(sector_alpha >= 0.f && sector_alpha <= 1.f)) {
    return Fail(error, "sector_alpha must be in [0, 1] (got " + std::to_string(sector_alpha) + ")");
  }
  if (!(unseen_alpha >= 0.f && unseen_alpha <= 1.f)) {
    return Fail(error, "unseen_alpha must be in [0, 1] (got " + std::to_string(unseen_alpha) + ")");
  }
  if (arc_segments < 1 || arc_segments > 256) {
    return Fail(error,
                "arc_segments must be in [1, 256] (got " + std::to_string(arc_segments) + ")");
  }
  if (!(agreement_cone_fraction > 0.f && agreement_cone_fraction <= 1.f)) {
    return Fail(error, "agreement_cone_fraction must be in (0, 1] (got " +
                           std::to_string(agreement_cone_fraction) + ")");
  }
  if (!(std::isfinite(max_age_s) && max_age_s > 0.f)) {
    return Fail(error, "max_age_s must be > 0 (got " + std::to_string(max_age_s) + ")");
  }
  if (!(std::isfinite(laser_agreement_margin_m) && laser_agreement_margin_m > 0.f)) {
    return Fail(error, "laser_agreement_margin_m must be > 0 (got " +
                           std::to_string(laser_agreement_margin_m) + ")");
  }
  return true;
}

void BuildSonarFeatures(const SonarRanges& sonar, const std::vector<ScanPointLabel>& laser_points,
                        const LaserFieldOfView& laser_fov, const ArFeatureOptions& colors,
                        const SonarFeatureOptions& options, SonarFeatures* out) {
  MOSTAR_CHECK(options.IsValid(nullptr));
  out->sectors.clear();
  out->fans.Clear();
  out->outlines.Clear();
  out->echoes = 0;
  out->unseen = 0;
  if (!options.enabled) return;
  const float floor_z = -colors.laser_height_m;
  for (size_t i = 0; i < sonar.ranges.size(); ++i) {
    const SonarRange& r = sonar.ranges[i];
    SonarSector sector;
    sector.sensor = i;
    sector.range_m = r.range_m;
    sector.has_echo = HasEcho(r);
    if (sector.has_echo) {
      ++out->echoes;
      // Where the sonar looks: a point on its axis at the echo, seen from the laser's origin.
      const double axis_x = r.mount.x_m + r.range_m * std::cos(r.mount.yaw_rad);
      const double axis_y = r.mount.y_m + r.range_m * std::sin(r.mount.yaw_rad);
      const double bearing = std::atan2(axis_y, axis_x);
      sector.compared = laser_fov.angle_max_rad >= laser_fov.angle_min_rad &&
                        bearing >= laser_fov.angle_min_rad && bearing <= laser_fov.angle_max_rad;
      sector.unseen_by_laser =
          sector.compared && !LaserAgrees(r, laser_points, options.laser_agreement_margin_m,
                                          options.agreement_cone_fraction);
      if (sector.unseen_by_laser) ++out->unseen;
      sector.color = DistanceColor(r.range_m, colors.min_distance_m, colors.max_distance_m);
    }
    out->sectors.push_back(sector);
    if (!sector.has_echo) continue;

    const Rgba fill = sector.color.WithAlpha(sector.unseen_by_laser ? options.unseen_alpha
                                                                    : options.sector_alpha);
    const float mx = static_cast<float>(r.mount.x_m);
    const float my = static_cast<float>(r.mount.y_m);
    const double start = r.mount.yaw_rad - 0.5 * r.field_of_view_rad;
    const double step = r.field_of_view_rad / options.arc_segments;
    auto arc_x = [&](int k) {
      return mx + r.range_m * static_cast<float>(std::cos(start + k * step));
    };
    auto arc_y = [&](int k) {
      return my + r.range_m * static_cast<float>(std::sin(start + k * step));
    };
    for (int k = 0; k < options.arc_segments; ++k) {
      out->fans.Add(mx, my, floor_z, fill);
      out->fans.Add(arc_x(k), arc_y(k), floor_z, fill);
      out->fans.Add(arc_x(k + 1), arc_y(k + 1), floor_z, fill);
    }
    if (!sector.unseen_by_laser) continue;
    out->outlines.Add(mx, my, floor_z, options.unseen_outline);
    out->outlines.Add(arc_x(0), arc_y(0), floor_z, options.unseen_outline);
    out->outlines.Add(mx, my, floor_z, options.unseen_outline);
    out->outlines.Add(arc_x(options.arc_segments), arc_y(options.arc_segments), floor_z,
                      options.unseen_outline);
    for (int k = 0; k < options.arc_segments; ++k) {
      out->outlines.Add(arc_x(k), arc_y(k), floor_z, options.unseen_outline);
      out->outlines.Add(arc_x(k + 1), arc_y(k + 1), floor_z, options.unseen_outline);
    }
  }
}

Duration SonarAgeAtImage(const std::optional<SonarRanges>& cycle, std::optional<Time> image_stamp,
                         Duration since_received) {
  if (!cycle || cycle->ranges.empty()) return Duration::zero();
  if (!image_stamp) return since_received;
  Time last = cycle->ranges.front().stamp;
  for (const SonarRange& range : cycle->ranges) last = std::max(last, range.stamp);
  const Duration apart = *image_stamp - last;
  return apart < Duration::zero() ? -apart : apart;
}

bool BuildFreshSonarFeatures(const std::optional<SonarRanges>& cycle, Duration age,
                             const LaserScan* scan, const std::vector<ScanPointLabel>& laser_points,
                             const ArFeatureOptions& colors, const SonarFeatureOptions& options,
                             SonarFeatures* out) {
  if (!cycle || ToSeconds(age) > options.max_age_s) return false;
  LaserFieldOfView fov;  // none without a scan: nothing compared
  if (scan) fov = {scan->angle_min_rad, scan->angle_max_rad()};
  BuildSonarFeatures(*cycle, laser_points, fov, colors, options, out);
  return true;
}

}  // namespace mostar::fusion
