// Laser double-check with nearest edge points (thesis 8.3 and 8.4): each beam's NEP is compared
// with its laser point, the overlay is moved onto agreeing NEPs, NEPs much nearer than the laser
// become "possible obstacle" dots, and disagreeing NEPs confirm potential laser outliers.
//
// Pure functions: safe to call from any thread.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "common/types/laser_scan.h"
#include "operator_client/vision/nearest_edge.h"

namespace mostar::vision {

struct NepClassifierOptions {
  // edgeTh, metres: a NEP within this floor distance of its laser point is the same object;
  // in (0, 5]. The thesis found about 0.10 m to work well.
  double edge_threshold_m = 0.10;
  // Far away one pixel spans more floor than edgeTh (at 5 m about 7 cm for the MORDUC
  // cameras), so a NEP is also taken to agree when within this many pixels of its laser point
  // (its Nep::metres_per_px). 0 = the thesis' rule alone; in [0, 20].
  double min_threshold_px = 2.0;
  // A NEP much nearer than its own laser point but within edgeTh (and min_threshold_px) of the
  // laser point of a beam up to this many beams away is the same object as that point: the laser
  // sees it, the ray only passes beside it (thin legs, corners, their contact shadows). It is
  // not a possible obstacle. 0 = the thesis' rule (own beam only); in [0, 10].
  int neighbour_beams = 2;
  // Possible obstacles are shown only in groups of at least this many beams: nearer NEPs of
  // beams at most two apart whose floor points lie within max(2 edgeTh, 2 d dtheta gap) of
  // each other (d: floor distance, dtheta: beam increment, gap: beams apart). Thesis 8.5:
  // obstacles the laser misses give lines of dots, false edges isolated ones. 1 = every dot
  // (the thesis); in [1, 20].
  int min_obstacle_beams = 2;

  bool IsValid(std::string* error) const;
};

// How a beam's NEP relates to its laser point.
enum class NepRelation : uint8_t {
  kNone,     // no NEP, or an unreliable one that disagrees with the laser (disregarded)
  kAgrees,   // |d_nep - d_laser| <= edgeTh: the overlay is moved onto the NEP
  kNearer,   // d_nep < d_laser - edgeTh (or the beam has no valid range): possible obstacle
  kFurther,  // d_nep > d_laser + edgeTh: the laser is trusted, the NEP ignored
  // Nearer than its own laser point but within edgeTh of a neighbouring beam's laser point
  // (NepClassifierOptions::neighbour_beams): the laser sees that object; no dot, no correction.
  kNeighbour,
  // Nearer, but fewer than NepClassifierOptions::min_obstacle_beams beams see the same edge:
  // taken for a false edge; no dot, and it confirms no outlier.
  kIsolated,
};

const char* NepRelationName(NepRelation relation);

struct BeamDecision {
  NepRelation relation = NepRelation::kNone;
  bool potential_outlier = false;  // input label (fusion's discontinuity detection)
  // A potential outlier whose (reliable) NEP disagrees with it: excluded from the rendering.
  bool confirmed_outlier = false;
};

// A NEP much nearer than the laser: drawn as a coloured dot (thesis fig. 33).
struct PossibleObstacle {
  int beam = 0;                                                 // beam index in the scan
  double distance_m = 0.0;                                      // floor distance from the base
  Eigen::Vector3d floor_point_laser = Eigen::Vector3d::Zero();  // laser frame, on the floor
};

struct NepClassification {
  std::vector<BeamDecision> beams;  // one per beam
  // The input scan with agreeing beams' ranges replaced by their NEP distance (the laser point
  // moved onto the NEP, along its beam) and confirmed outliers set to NaN (not drawn). Feed this
  // to the AR features instead of the raw scan.
  LaserScan corrected_scan;
  std::vector<PossibleObstacle> possible_obstacles;
  int corrected = 0;                 // beams with NepRelation::kAgrees
  int nearer = 0;                    // == possible_obstacles.size()
  int further = 0;                   // ignored NEPs
  int neighbour = 0;                 // NepRelation::kNeighbour
  int isolated = 0;                  // NepRelation::kIsolated
  int unreliable_ignored = 0;        // unreliable NEPs that did not agree with the laser
  int along_ray_ignored = 0;         // nearer NEPs along their ray (silhouettes, Nep::along_ray)
  int starts_on_object_ignored = 0;  // nearer NEPs on rays starting on an object (its top)
  int confirmed_outliers = 0;
  int potential_outliers_kept = 0;  // potential outliers whose NEP agreed or that had none
};

// Classifies neps[i] against beam i of `scan`. `potential_outliers` is empty (no labels) or has
// one flag per beam. Ranges: a finite range > 0 is a laser point at that floor distance (the
// scan plane is horizontal, so its floor projection is at the same distance); NaN (no echo) and
// +Inf (nothing within range) make any reliable NEP a possible obstacle. Unreliable NEPs count
// only when they agree. Returns false with `error` on size mismatches or invalid options (then
// `out` holds the uncorrected scan and no decisions are "confirmed").
bool ClassifyNeps(const LaserScan& scan, const std::vector<Nep>& neps,
                  const std::vector<bool>& potential_outliers, const NepClassifierOptions& options,
                  double laser_height_m, NepClassification* out, std::string* error);

// The relation of one NEP distance to one laser range (no reliability logic).
NepRelation RelateNepToLaser(double nep_distance_m, float laser_range_m, double edge_threshold_m);
// The same for a NEP, with the threshold max(edge_threshold_m, min_threshold_px *
// nep.metres_per_px).
NepRelation RelateNepToLaser(const Nep& nep, float laser_range_m,
                             const NepClassifierOptions& options);

}  // namespace mostar::vision
