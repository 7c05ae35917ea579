#include "operator_client/vision/nep_classifier.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/check/check.h"

namespace mostar::vision {

bool NepClassifierOptions::IsValid(std::string* error) const {
  if (neighbour_beams < 0 || neighbour_beams > 10 || min_obstacle_beams < 1 ||
      min_obstacle_beams > 20) {
    if (error != nullptr) {
      std::ostringstream why;
      why << "neighbour_beams must be in [0, 10] and min_obstacle_beams in [1, 20] (got "
          << neighbour_beams << ", " << min_obstacle_beams << ")";
      *error = why.str();
    }
    return false;
  }
  if (std::isfinite(edge_threshold_m) && edge_threshold_m > 0.0 && edge_threshold_m <= 5.0 &&
      min_threshold_px >= 0.0 && min_threshold_px <= 20.0) {
    return true;
  }
  if (error != nullptr && !(min_threshold_px >= 0.0 && min_threshold_px <= 20.0)) {
    std::ostringstream why;
    why << "min_threshold_px must be in [0, 20] (got " << min_threshold_px << ")";
    *error = why.str();
    return false;
  }
  if (error != nullptr) {
    std::ostringstream why;
    why << "edge_threshold_m must be in (0, 5] (got " << edge_threshold_m << ")";
    *error = why.str();
  }
  return false;
}

const char* NepRelationName(NepRelation relation) {
  switch (relation) {
    case NepRelation::kNone:
      return "none";
    case NepRelation::kAgrees:
      return "agrees";
    case NepRelation::kNearer:
      return "nearer";
    case NepRelation::kFurther:
      return "further";
    case NepRelation::kNeighbour:
      return "neighbour";
    case NepRelation::kIsolated:
      return "isolated";
  }
  return "?";
}

NepRelation RelateNepToLaser(double nep_distance_m, float laser_range_m, double edge_threshold_m) {
  if (!std::isfinite(nep_distance_m)) return NepRelation::kNone;
  if (!LaserScan::IsValidRange(laser_range_m)) return NepRelation::kNearer;
  const double difference_m = nep_distance_m - static_cast<double>(laser_range_m);
  if (std::abs(difference_m) <= edge_threshold_m) return NepRelation::kAgrees;
  return difference_m < 0.0 ? NepRelation::kNearer : NepRelation::kFurther;
}

NepRelation RelateNepToLaser(const Nep& nep, float laser_range_m,
                             const NepClassifierOptions& options) {
  return RelateNepToLaser(
      nep.distance_m, laser_range_m,
      std::max(options.edge_threshold_m, options.min_threshold_px * nep.metres_per_px));
}

bool ClassifyNeps(const LaserScan& scan, const std::vector<Nep>& neps,
                  const std::vector<bool>& potential_outliers, const NepClassifierOptions& options,
                  double laser_height_m, NepClassification* out, std::string* error) {
  MOSTAR_CHECK(out != nullptr);
  const size_t n = scan.ranges_m.size();
  *out = NepClassification{};
  out->corrected_scan = scan;
  out->beams.assign(n, BeamDecision{});
  std::ostringstream why;
  if (!options.IsValid(error)) return false;
  if (neps.size() != n) {
    why << "got " << neps.size() << " NEPs for " << n << " beams";
  } else if (!potential_outliers.empty() && potential_outliers.size() != n) {
    why << "got " << potential_outliers.size() << " outlier labels for " << n << " beams";
  } else if (!std::isfinite(laser_height_m) || laser_height_m <= 0.0) {
    why << "laser_height_m must be finite and > 0 (got " << laser_height_m << ")";
  }
  if (!why.str().empty()) {
    if (error != nullptr) *error = why.str();
    return false;
  }

  const auto threshold_m = [&](const Nep& nep) {
    return std::max(options.edge_threshold_m, options.min_threshold_px * nep.metres_per_px);
  };
  const auto laser_point = [&](size_t j) {
    return FloorPointLaser(scan.AngleOf(j), scan.ranges_m[j], laser_height_m);
  };
  // Pass 1: each NEP against its own laser point, then nearer ones against the neighbours'.
  for (size_t i = 0; i < n; ++i) {
    BeamDecision& decision = out->beams[i];
    decision.potential_outlier = !potential_outliers.empty() && potential_outliers[i];
    const Nep& nep = neps[i];
    NepRelation relation =
        nep.found ? RelateNepToLaser(nep, scan.ranges_m[i], options) : NepRelation::kNone;
    if (relation != NepRelation::kNone && relation != NepRelation::kAgrees && !nep.reliable) {
      relation = NepRelation::kNone;  // thesis 9.2: unreliable NEPs never contradict the laser
      ++out->unreliable_ignored;
    } else if (relation == NepRelation::kNearer && nep.along_ray) {
      relation = NepRelation::kNone;  // a silhouette, not a base on this beam: no dot
      ++out->along_ray_ignored;
    } else if (relation == NepRelation::kNearer && nep.starts_on_object) {
      relation = NepRelation::kNone;  // an object's top edge, its base below the image: no dot
      ++out->starts_on_object_ignored;
    }
    if (relation == NepRelation::kNearer && options.neighbour_beams > 0) {
      const size_t k = static_cast<size_t>(options.neighbour_beams);
      for (size_t j = i > k ? i - k : 0; j < std::min(n, i + k + 1); ++j) {
        if (j != i && LaserScan::IsValidRange(scan.ranges_m[j]) &&
            (laser_point(j) - nep.floor_point_laser).norm() <= threshold_m(nep)) {
          relation = NepRelation::kNeighbour;
          break;
        }
      }
    }
    decision.relation = relation;
  }
  // Pass 2: groups of nearer NEPs along the scan; small groups are isolated.
  if (options.min_obstacle_beams > 1) {
    const double increment_rad = std::abs(static_cast<double>(scan.angle_increment_rad));
    std::vector<size_t> group;
    const auto close_group = [&] {
      if (static_cast<int>(group.size()) < options.min_obstacle_beams) {
        for (const size_t g : group) out->beams[g].relation = NepRelation::kIsolated;
      }
      group.clear();
    };
    for (size_t i = 0; i < n; ++i) {
      if (out->beams[i].relation != NepRelation::kNearer) continue;
      if (!group.empty()) {
        const size_t last = group.back();
        const double gap = static_cast<double>(i - last);
        const double link_m = std::max(2.0 * options.edge_threshold_m,
                                       2.0 * neps[i].distance_m * increment_rad * gap);
        if (i - last > 2 ||
            (neps[i].floor_point_laser - neps[last].floor_point_laser).norm() > link_m) {
          close_group();
        }
      }
      group.push_back(i);
    }
    close_group();
  }
  // Pass 3: apply the decisions.
  for (size_t i = 0; i < n; ++i) {
    BeamDecision& decision = out->beams[i];
    const Nep& nep = neps[i];
    const NepRelation relation = decision.relation;
    switch (relation) {
      case NepRelation::kAgrees:
        out->corrected_scan.ranges_m[i] = static_cast<float>(nep.distance_m);
        ++out->corrected;
        break;
      case NepRelation::kNearer:
        out->possible_obstacles.push_back(
            PossibleObstacle{static_cast<int>(i), nep.distance_m,
                             FloorPointLaser(scan.AngleOf(i), nep.distance_m, laser_height_m)});
        ++out->nearer;
        break;
      case NepRelation::kFurther:
        ++out->further;
        break;
      case NepRelation::kNeighbour:
        ++out->neighbour;
        break;
      case NepRelation::kIsolated:
        ++out->isolated;
        break;
      case NepRelation::kNone:
        break;
    }
    if (decision.potential_outlier) {
      // A NEP that disagrees casts doubt on the laser point (thesis 8.4); an isolated one is
      // taken for a false edge.
      if (relation == NepRelation::kNearer || relation == NepRelation::kFurther ||
          relation == NepRelation::kNeighbour) {
        decision.confirmed_outlier = true;
        out->corrected_scan.ranges_m[i] = std::numeric_limits<float>::quiet_NaN();
        ++out->confirmed_outliers;
      } else {
        ++out->potential_outliers_kept;
      }
    }
  }
  return true;
}

}  // namespace mostar::vision
