// AR features from one laser scan (thesis 6): coloured laser points, virtual walls, vertical
// lines, virtual rays on the floor, distance circles and distance labels, as plain vertex data
// in the laser frame (x forward, y left, z up; metres). The floor is z = -laser_height_m; the
// robot base is (0, 0, -laser_height_m). No OpenGL here: the renderer uploads the arrays and
// draws them with the camera model's GL matrices (common/math/camera_model.h).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/types/laser_scan.h"
#include "operator_client/fusion/discontinuities.h"
#include "operator_client/fusion/vertex_array.h"

namespace mostar::fusion {

struct ArFeatureOptions {
  // Colour scale (thesis 6.1): red at or below min, green at or above max, yellow in between.
  float min_distance_m = 0.5f;  // >= 0
  float max_distance_m = 3.0f;  // > min_distance_m
  // Height of the scan plane above the floor; must equal the calibration's laser_height_m.
  float laser_height_m = 0.40f;  // > 0

  SegmentationOptions segmentation;

  // Virtual walls between consecutive valid points, not drawn across discontinuities.
  bool walls_enabled = true;
  float wall_height_m = 0.60f;      // above the floor; > 0
  float wall_bottom_alpha = 0.50f;  // [0, 1]
  float wall_top_alpha = 0.20f;     // [0, 1]
  // Vertical lines at the laser points, from the floor to wall_height_m.
  bool vertical_lines_enabled = false;
  float line_alpha = 0.90f;  // [0, 1]
  // Laser points themselves, in the scan plane.
  float point_alpha = 1.0f;  // [0, 1]

  // Virtual rays on the floor from the robot base to the points: every ray_beam_interval-th
  // valid beam (beam index % interval == 0), plus always at both ends of a discontinuity.
  bool rays_enabled = true;
  int ray_beam_interval = 10;  // >= 1
  float ray_alpha = 0.80f;     // [0, 1]

  // Concentric distance circles on the floor around the robot base.
  bool circles_enabled = true;
  float circle_spacing_m = 0.5f;              // > 0
  float circle_max_radius_m = 4.0f;           // >= circle_spacing_m; at most 1000 circles
  float circle_half_angle_rad = 3.14159265f;  // arcs span [-this, +this] around ahead; (0, pi]
  int circle_segments_per_turn = 96;          // >= 8
  Rgba circle_color{1.f, 1.f, 1.f, 0.5f};

  // Absolute distance labels on the nearest clusters.
  bool labels_enabled = true;
  int label_count = 3;  // >= 0: labels on the label_count nearest clusters
  // Clusters made only of potential outliers get no label.
  float label_height_m = 0.70f;  // anchor height above the floor; >= 0

  bool IsValid(std::string* error) const;
};

// Per-beam labels.
struct ScanPointLabel {
  float x_m = 0.f;  // laser frame; the point is in the scan plane z = 0
  float y_m = 0.f;
  float range_m = 0.f;  // the measurement (possibly NaN/Inf when not valid)
  Rgba color;           // distance colour, opaque; grey when not valid
  bool valid = false;
  bool at_discontinuity = false;   // an end of a discontinuity wall
  bool potential_outlier = false;  // thesis 6.2; confirmed or not later with edges (thesis 8.4)
  int cluster = -1;                // index into ArFeatures::segmentation.clusters, -1 if invalid
};

// A text label for the renderer: draw `text` at the projection of the anchor.
struct DistanceLabel {
  float anchor_x_m = 0.f;  // laser frame: above the nearest point, at label_height_m above floor
  float anchor_y_m = 0.f;
  float anchor_z_m = 0.f;
  float distance_m = 0.f;  // range of the nearest point of the cluster
  size_t beam = 0;
  size_t cluster = 0;
  Rgba color;
  std::string text;  // e.g. "1.35 m"
};

struct ArFeatures {
  uint64_t scan_sequence = 0;
  std::vector<ScanPointLabel> points;  // one per beam
  ScanSegmentation segmentation;       // walls, discontinuities, clusters
  VertexArray laser_points;            // GL_POINTS: valid points at z = 0
  VertexArray walls;                   // GL_TRIANGLES: 2 triangles (6 vertices) per drawn wall
  VertexArray vertical_lines;          // GL_LINES: floor to wall top at valid points
  VertexArray rays;                    // GL_LINES: robot base to the point's floor projection
  VertexArray circles;                 // GL_LINES: each arc as consecutive segments on the floor
  std::vector<float> circle_radii_m;
  std::vector<DistanceLabel> labels;  // nearest first
  size_t drawn_walls = 0;
  size_t invalid_beams = 0;  // NaN/Inf/out-of-limits beams in this scan
};

// Builds ArFeatures from scans. Immutable and thread-compatible: Build() is const.
class ArFeatureBuilder {
 public:
  // `options` must be valid (asserted); use Create() for options from outside.
  explicit ArFeatureBuilder(const ArFeatureOptions& options);
  static std::optional<ArFeatureBuilder> Create(const ArFeatureOptions& options,
                                                std::string* error);

  const ArFeatureOptions& options() const { return options_; }

  // Fills `features` from `scan`, reusing the capacity of its arrays (only the labels
  // allocate in steady state). Never fails: invalid beams are labelled and counted, an empty scan
  // gives empty geometry (circles still drawn).
  void Build(const LaserScan& scan, ArFeatures* features) const;
  // The same, with each valid beam drawn at `beam_points[i]` instead of where its range and
  // angle put it (a scan moved to an image's time, motion_compensation.h). Colours, labels and
  // discontinuities still come from the measured ranges. `beam_points` has one point per beam
  // (asserted).
  void Build(const LaserScan& scan, const std::vector<PlanarPoint>& beam_points,
             ArFeatures* features) const;
  ArFeatures Build(const LaserScan& scan) const;

 private:
  void BuildFrom(const LaserScan& scan, const std::vector<PlanarPoint>* beam_points,
                 ArFeatures* features) const;
  void BuildLabels(ArFeatures* features) const;

  ArFeatureOptions options_;
  VertexArray circles_;  // independent of the scan: built once
  std::vector<float> circle_radii_m_;
};

}  // namespace mostar::fusion
