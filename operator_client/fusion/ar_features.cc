#include "operator_client/fusion/ar_features.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/check/check.h"
#include "operator_client/fusion/color_scale.h"

namespace mostar::fusion {
namespace {

constexpr float kPi = 3.14159265358979f;
constexpr int kMaxCircles = 1000;

bool Fail(std::string* error, const std::string& message) {
  if (error != nullptr) *error = message;
  return false;
}

bool CheckAlpha(const char* name, float alpha, std::string* error) {
  if (alpha >= 0.f && alpha <= 1.f) return true;
  return Fail(error, std::string(name) + " must be in [0, 1] (got " + std::to_string(alpha) + ")");
}

}  // namespace

bool ArFeatureOptions::IsValid(std::string* error) const {
  if (!(std::isfinite(min_distance_m) && min_distance_m >= 0.f)) {
    return Fail(error, "min_distance_m must be >= 0 (got " + std::to_string(min_distance_m) + ")");
  }
  if (!(std::isfinite(max_distance_m) && max_distance_m > min_distance_m)) {
    return Fail(error, "max_distance_m must be > min_distance_m (got " +
                           std::to_string(max_distance_m) +
                           " <= " + std::to_string(min_distance_m) + ")");
  }
  if (!(std::isfinite(laser_height_m) && laser_height_m > 0.f)) {
    return Fail(error, "laser_height_m must be > 0 (got " + std::to_string(laser_height_m) + ")");
  }
  std::string reason;
  if (!segmentation.IsValid(&reason)) return Fail(error, "segmentation." + reason);
  if (!(std::isfinite(wall_height_m) && wall_height_m > 0.f)) {
    return Fail(error, "wall_height_m must be > 0 (got " + std::to_string(wall_height_m) + ")");
  }
  if (!CheckAlpha("wall_bottom_alpha", wall_bottom_alpha, error) ||
      !CheckAlpha("wall_top_alpha", wall_top_alpha, error) ||
      !CheckAlpha("line_alpha", line_alpha, error) ||
      !CheckAlpha("point_alpha", point_alpha, error) ||
      !CheckAlpha("ray_alpha", ray_alpha, error)) {
    return false;
  }
  if (ray_beam_interval < 1) {
    return Fail(error,
                "ray_beam_interval must be >= 1 (got " + std::to_string(ray_beam_interval) + ")");
  }
  if (!(std::isfinite(circle_spacing_m) && circle_spacing_m > 0.f)) {
    return Fail(error,
                "circle_spacing_m must be > 0 (got " + std::to_string(circle_spacing_m) + ")");
  }
  if (!(std::isfinite(circle_max_radius_m) && circle_max_radius_m >= circle_spacing_m)) {
    return Fail(error, "circle_max_radius_m must be >= circle_spacing_m (got " +
                           std::to_string(circle_max_radius_m) + ")");
  }
  if (circle_max_radius_m / circle_spacing_m > kMaxCircles) {
    return Fail(error,
                "circle_max_radius_m / circle_spacing_m must be <= " + std::to_string(kMaxCircles));
  }
  if (!(circle_half_angle_rad > 0.f && circle_half_angle_rad <= kPi + 1e-5f)) {
    return Fail(error, "circle_half_angle_rad must be in (0, pi] (got " +
                           std::to_string(circle_half_angle_rad) + ")");
  }
  if (circle_segments_per_turn < 8) {
    return Fail(error, "circle_segments_per_turn must be >= 8 (got " +
                           std::to_string(circle_segments_per_turn) + ")");
  }
  if (!CheckAlpha("circle_color.a", circle_color.a, error)) return false;
  if (label_count < 0) {
    return Fail(error, "label_count must be >= 0 (got " + std::to_string(label_count) + ")");
  }
  if (!(std::isfinite(label_height_m) && label_height_m >= 0.f)) {
    return Fail(error, "label_height_m must be >= 0 (got " + std::to_string(label_height_m) + ")");
  }
  return true;
}

ArFeatureBuilder::ArFeatureBuilder(const ArFeatureOptions& options) : options_(options) {
  MOSTAR_CHECK(options_.IsValid(nullptr));
  const float floor_z = -options_.laser_height_m;
  const float span = 2.f * options_.circle_half_angle_rad;
  const int segments = std::max(
      1, static_cast<int>(std::ceil(span / (2.f * kPi) * options_.circle_segments_per_turn)));
  const int count = static_cast<int>(
      std::floor(options_.circle_max_radius_m / options_.circle_spacing_m + 1e-4f));
  circles_.Reserve(static_cast<size_t>(count) * 2 * segments);
  for (int c = 1; c <= count; ++c) {
    const float radius = c * options_.circle_spacing_m;
    circle_radii_m_.push_back(radius);
    for (int s = 0; s < segments; ++s) {
      const float a0 = -options_.circle_half_angle_rad + span * s / segments;
      const float a1 = -options_.circle_half_angle_rad + span * (s + 1) / segments;
      circles_.Add(radius * std::cos(a0), radius * std::sin(a0), floor_z, options_.circle_color);
      circles_.Add(radius * std::cos(a1), radius * std::sin(a1), floor_z, options_.circle_color);
    }
  }
}

std::optional<ArFeatureBuilder> ArFeatureBuilder::Create(const ArFeatureOptions& options,
                                                         std::string* error) {
  if (!options.IsValid(error)) return std::nullopt;
  return ArFeatureBuilder(options);
}

ArFeatures ArFeatureBuilder::Build(const LaserScan& scan) const {
  ArFeatures features;
  Build(scan, &features);
  return features;
}

void ArFeatureBuilder::Build(const LaserScan& scan, ArFeatures* features) const {
  BuildFrom(scan, nullptr, features);
}

void ArFeatureBuilder::Build(const LaserScan& scan, const std::vector<PlanarPoint>& beam_points,
                             ArFeatures* features) const {
  MOSTAR_CHECK(beam_points.size() == scan.ranges_m.size())
      << beam_points.size() << " points for " << scan.ranges_m.size() << " beams";
  BuildFrom(scan, &beam_points, features);
}

void ArFeatureBuilder::BuildFrom(const LaserScan& scan, const std::vector<PlanarPoint>* beam_points,
                                 ArFeatures* features) const {
  const ArFeatureOptions& o = options_;
  const size_t n = scan.ranges_m.size();
  features->scan_sequence = scan.sequence;
  SegmentScan(scan, o.segmentation, &features->segmentation);
  const ScanSegmentation& seg = features->segmentation;
  features->invalid_beams = seg.invalid_beams;

  // Per-beam labels.
  features->points.resize(n);
  for (size_t i = 0; i < n; ++i) {
    ScanPointLabel& p = features->points[i];
    const float range = scan.ranges_m[i];
    const float angle = scan.AngleOf(i);
    p.range_m = range;
    p.valid = seg.valid[i] != 0;
    p.at_discontinuity = p.valid && seg.AtDiscontinuity(i);
    p.potential_outlier = seg.potential_outlier[i] != 0;
    p.cluster = -1;
    if (p.valid && beam_points != nullptr) {
      p.x_m = (*beam_points)[i].x_m;
      p.y_m = (*beam_points)[i].y_m;
      p.color = DistanceColor(range, o.min_distance_m, o.max_distance_m);
    } else if (p.valid) {
      p.x_m = range * std::cos(angle);
      p.y_m = range * std::sin(angle);
      p.color = DistanceColor(range, o.min_distance_m, o.max_distance_m);
    } else {
      p.x_m = 0.f;
      p.y_m = 0.f;
      p.color = Rgba{0.5f, 0.5f, 0.5f, 1.f};
    }
  }
  for (size_t c = 0; c < seg.clusters.size(); ++c) {
    for (size_t b = seg.clusters[c].first_beam; b <= seg.clusters[c].last_beam; ++b) {
      features->points[b].cluster = static_cast<int>(c);
    }
  }

  const float floor_z = -o.laser_height_m;
  const float top_z = floor_z + o.wall_height_m;

  features->laser_points.Clear();
  features->laser_points.Reserve(n);
  for (const ScanPointLabel& p : features->points) {
    if (p.valid) features->laser_points.Add(p.x_m, p.y_m, 0.f, p.color.WithAlpha(o.point_alpha));
  }

  features->walls.Clear();
  features->drawn_walls = 0;
  if (o.walls_enabled) {
    features->walls.Reserve(6 * (n > 0 ? n - 1 : 0));
    for (size_t i = 0; i + 1 < n; ++i) {
      if (seg.wall_exists[i] == 0 || seg.wall_discontinuity[i] != 0) continue;
      const ScanPointLabel& a = features->points[i];
      const ScanPointLabel& b = features->points[i + 1];
      const Rgba a_bottom = a.color.WithAlpha(o.wall_bottom_alpha);
      const Rgba b_bottom = b.color.WithAlpha(o.wall_bottom_alpha);
      const Rgba a_top = a.color.WithAlpha(o.wall_top_alpha);
      const Rgba b_top = b.color.WithAlpha(o.wall_top_alpha);
      VertexArray& w = features->walls;
      w.Add(a.x_m, a.y_m, floor_z, a_bottom);
      w.Add(b.x_m, b.y_m, floor_z, b_bottom);
      w.Add(b.x_m, b.y_m, top_z, b_top);
      w.Add(a.x_m, a.y_m, floor_z, a_bottom);
      w.Add(b.x_m, b.y_m, top_z, b_top);
      w.Add(a.x_m, a.y_m, top_z, a_top);
      ++features->drawn_walls;
    }
  }

  features->vertical_lines.Clear();
  if (o.vertical_lines_enabled) {
    features->vertical_lines.Reserve(2 * n);
    for (const ScanPointLabel& p : features->points) {
      if (!p.valid) continue;
      const Rgba color = p.color.WithAlpha(o.line_alpha);
      features->vertical_lines.Add(p.x_m, p.y_m, floor_z, color);
      features->vertical_lines.Add(p.x_m, p.y_m, top_z, color);
    }
  }

  features->rays.Clear();
  if (o.rays_enabled) {
    const size_t interval = static_cast<size_t>(o.ray_beam_interval);
    for (size_t i = 0; i < n; ++i) {
      const ScanPointLabel& p = features->points[i];
      if (!p.valid || (i % interval != 0 && !p.at_discontinuity)) continue;
      const Rgba color = p.color.WithAlpha(o.ray_alpha);
      features->rays.Add(0.f, 0.f, floor_z, color);
      features->rays.Add(p.x_m, p.y_m, floor_z, color);
    }
  }

  if (o.circles_enabled) {
    features->circles.positions.assign(circles_.positions.begin(), circles_.positions.end());
    features->circles.colors.assign(circles_.colors.begin(), circles_.colors.end());
    features->circle_radii_m.assign(circle_radii_m_.begin(), circle_radii_m_.end());
  } else {
    features->circles.Clear();
    features->circle_radii_m.clear();
  }

  BuildLabels(features);
}

void ArFeatureBuilder::BuildLabels(ArFeatures* features) const {
  features->labels.clear();
  if (!options_.labels_enabled || options_.label_count == 0) return;
  const std::vector<Cluster>& clusters = features->segmentation.clusters;
  // Candidate clusters (not only potential outliers), nearest first; partial sort of indices.
  std::vector<size_t> candidates;
  candidates.reserve(clusters.size());
  for (size_t c = 0; c < clusters.size(); ++c) {
    if (features->segmentation.potential_outlier[clusters[c].first_beam] == 0) {
      candidates.push_back(c);
    }
  }
  const size_t count = std::min(candidates.size(), static_cast<size_t>(options_.label_count));
  std::partial_sort(candidates.begin(), candidates.begin() + static_cast<long>(count),
                    candidates.end(), [&clusters](size_t a, size_t b) {
                      return clusters[a].nearest_range_m < clusters[b].nearest_range_m;
                    });
  const float anchor_z = -options_.laser_height_m + options_.label_height_m;
  for (size_t k = 0; k < count; ++k) {
    const Cluster& cluster = clusters[candidates[k]];
    const ScanPointLabel& p = features->points[cluster.nearest_beam];
    DistanceLabel label;
    label.anchor_x_m = p.x_m;
    label.anchor_y_m = p.y_m;
    label.anchor_z_m = anchor_z;
    label.distance_m = cluster.nearest_range_m;
    label.beam = cluster.nearest_beam;
    label.cluster = candidates[k];
    label.color = p.color;
    char text[32];
    std::snprintf(text, sizeof(text), "%.2f m", static_cast<double>(cluster.nearest_range_m));
    label.text = text;
    features->labels.push_back(std::move(label));
  }
}

}  // namespace mostar::fusion
