// AR cues from the sonar belt: each sonar's cone as a translucent sector on the floor from its
// mount to its first echo, in the walls' distance colours, and the sectors where the sonar hears
// something the laser does not see (glass, black surfaces, objects out of the scan plane)
// highlighted. Plain vertex data in the laser frame (x forward, y left, z up; metres). The base
// frame (base_link) is the floor point under the laser: a mount (x, y) in base_link is (x, y) in
// the laser frame, and the floor is z = -laser_height_m. No OpenGL, no DDS.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "common/time/time.h"
#include "common/types/laser_scan.h"
#include "common/types/sonar.h"
#include "operator_client/fusion/ar_features.h"
#include "operator_client/fusion/vertex_array.h"

namespace mostar::fusion {

struct SonarFeatureOptions {
  bool enabled = true;
  float sector_alpha = 0.25f;  // [0, 1], sectors the laser agrees with
  float unseen_alpha = 0.55f;  // [0, 1], sectors the laser does not see
  int arc_segments = 12;       // >= 1: segments of each sector's far arc
  // A belt cycle received longer ago than this (s, > 0) is not drawn: the belt cycles at about
  // 5 Hz, so an older cycle no longer shows where things are.
  float max_age_s = 1.0f;
  // An echo counts as seen by the laser when a valid laser point lies inside the central part
  // of the sonar's cone (this fraction of its angle: the main lobe, where an echo mostly comes
  // from; (0, 1]) no farther from the sonar than its echo plus the margin (> 0). Only sonars
  // looking into the laser's field of view are compared: behind the scanner nothing is unseen.
  float laser_agreement_margin_m = 0.30f;
  float agreement_cone_fraction = 0.5f;
  // Outline of an unseen sector: the echo arc and the cone's sides, as lines.
  Rgba unseen_outline{1.f, 0.f, 1.f, 1.f};  // magenta, as the obstacles edges find

  bool IsValid(std::string* error) const;
};

// What one sonar of the cycle shows.
struct SonarSector {
  size_t sensor = 0;             // index in SonarRanges::ranges
  bool has_echo = false;         // a finite range in [min_range_m, max_range_m]
  bool compared = false;         // has_echo and the sonar looks into the laser's field of view
  bool unseen_by_laser = false;  // compared and no laser point agrees
  float range_m = 0;
  Rgba color;  // distance colour, opaque
};

struct SonarFeatures {
  std::vector<SonarSector> sectors;  // one per sensor, in the cycle's order
  VertexArray fans;                  // GL_TRIANGLES on the floor: mount to echo arc
  VertexArray outlines;              // GL_LINES on the floor: outlines of unseen sectors
  size_t echoes = 0;                 // sensors with an echo
  size_t unseen = 0;                 // of them, not seen by the laser
};

// The laser's field of view, angles from the laser's x axis, counter-clockwise (LaserScan).
struct LaserFieldOfView {
  float angle_min_rad = 0.f;
  float angle_max_rad = -1.f;  // < angle_min_rad (the default): no scan, nothing is compared
};

// Builds the sonar cues of one belt cycle. `laser_points` are the scan's labelled points
// (ArFeatures::points, laser frame) and `laser_fov` its field of view; a sonar is compared with
// the laser only when its axis points into that field (seen from the laser's origin).
// `colors` gives the distance colour scale (min/max distance) and the floor height.
// Clears `out` first (keeps capacity). Sensors with no echo (+Inf), a failed reading (NaN) or a
// range outside [min_range_m, max_range_m] draw nothing. `options` must be valid (asserted).
void BuildSonarFeatures(const SonarRanges& sonar, const std::vector<ScanPointLabel>& laser_points,
                        const LaserFieldOfView& laser_fov, const ArFeatureOptions& colors,
                        const SonarFeatureOptions& options, SonarFeatures* out);

// How old a belt cycle is for the picture it is drawn over: with an image, the distance between
// the image's capture stamp and the cycle's last ranging, on the robot's clock (so a replay, a
// paused replay or a slow client judges it as the live console did); without one, the time
// since it was received (`since_received`). Zero without a cycle or when it holds no sensor.
Duration SonarAgeAtImage(const std::optional<SonarRanges>& cycle, std::optional<Time> image_stamp,
                         Duration since_received);

// The cues of the latest belt cycle, received `age` ago, when there is one and it is fresh
// (age <= options.max_age_s); false, and `out` untouched, otherwise. `scan`: the scan drawn
// with it (its field of view; null: none, nothing is compared) and `laser_points` its labels.
bool BuildFreshSonarFeatures(const std::optional<SonarRanges>& cycle, Duration age,
                             const LaserScan* scan, const std::vector<ScanPointLabel>& laser_points,
                             const ArFeatureOptions& colors, const SonarFeatureOptions& options,
                             SonarFeatures* out);

}  // namespace mostar::fusion
