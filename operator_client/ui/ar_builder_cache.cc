#include "operator_client/ui/ar_builder_cache.h"

namespace mostar::ui {

namespace {

bool Same(const fusion::Rgba& a, const fusion::Rgba& b) {
  return a.r == b.r && a.g == b.g && a.b == b.b && a.a == b.a;
}

}  // namespace

fusion::ArFeatureOptions OverlayArOptions(const fusion::ArFeatureOptions& ar, double laser_height_m,
                                          bool calibrating) {
  fusion::ArFeatureOptions options = ar;
  options.laser_height_m = static_cast<float>(laser_height_m);
  if (calibrating) {
    options.rays_enabled = true;
    options.vertical_lines_enabled = true;
  }
  return options;
}

// A field added to ArFeatureOptions (or SegmentationOptions) must be compared here.
static_assert(sizeof(fusion::ArFeatureOptions) == 108, "compare the new field in SameArOptions");
static_assert(sizeof(fusion::SegmentationOptions) == 8, "compare the new field in SameArOptions");

bool SameArOptions(const fusion::ArFeatureOptions& a, const fusion::ArFeatureOptions& b) {
  return a.min_distance_m == b.min_distance_m && a.max_distance_m == b.max_distance_m &&
         a.laser_height_m == b.laser_height_m &&
         a.segmentation.slope_threshold == b.segmentation.slope_threshold &&
         a.segmentation.max_outlier_run_points == b.segmentation.max_outlier_run_points &&
         a.walls_enabled == b.walls_enabled && a.wall_height_m == b.wall_height_m &&
         a.wall_bottom_alpha == b.wall_bottom_alpha && a.wall_top_alpha == b.wall_top_alpha &&
         a.vertical_lines_enabled == b.vertical_lines_enabled && a.line_alpha == b.line_alpha &&
         a.point_alpha == b.point_alpha && a.rays_enabled == b.rays_enabled &&
         a.ray_beam_interval == b.ray_beam_interval && a.ray_alpha == b.ray_alpha &&
         a.circles_enabled == b.circles_enabled && a.circle_spacing_m == b.circle_spacing_m &&
         a.circle_max_radius_m == b.circle_max_radius_m &&
         a.circle_half_angle_rad == b.circle_half_angle_rad &&
         a.circle_segments_per_turn == b.circle_segments_per_turn &&
         Same(a.circle_color, b.circle_color) && a.labels_enabled == b.labels_enabled &&
         a.label_count == b.label_count && a.label_height_m == b.label_height_m;
}

std::vector<bool> PotentialOutliers(const fusion::ArFeatureBuilder& builder,
                                    const LaserScan& scan) {
  const fusion::ArFeatures features = builder.Build(scan);
  std::vector<bool> labels;
  labels.reserve(features.points.size());
  for (const fusion::ScanPointLabel& p : features.points) labels.push_back(p.potential_outlier);
  return labels;
}

ArBuilderCache::ArBuilderCache(const fusion::ArFeatureOptions& configured)
    : configured_(configured) {}

const fusion::ArFeatureBuilder& ArBuilderCache::For(const fusion::ArFeatureOptions& options,
                                                    std::string* error) {
  if (!asked_ || !SameArOptions(options, requested_)) {
    asked_ = true;
    requested_ = options;
    error_.clear();
    current_ = fusion::ArFeatureBuilder::Create(options, &error_);
    if (current_) ++builds_;
  }
  if (!current_) {
    *error = error_;
    return configured_;
  }
  return *current_;
}

}  // namespace mostar::ui
