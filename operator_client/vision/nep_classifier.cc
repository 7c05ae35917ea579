#include "operator_client/vision/nep_classifier.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <sstream>

namespace mostar::vision {

bool NepClassifierOptions::IsValid(std::string* error) const {
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
  assert(out != nullptr);
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

  for (size_t i = 0; i < n; ++i) {
    BeamDecision& decision = out->beams[i];
    decision.potential_outlier = !potential_outliers.empty() && potential_outliers[i];
    const Nep& nep = neps[i];
    const float range_m = scan.ranges_m[i];
    NepRelation relation = nep.found ? RelateNepToLaser(nep, range_m, options) : NepRelation::kNone;
    if (relation != NepRelation::kNone && relation != NepRelation::kAgrees && !nep.reliable) {
      relation = NepRelation::kNone;  // thesis 9.2: unreliable NEPs never contradict the laser
      ++out->unreliable_ignored;
    }
    decision.relation = relation;
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
      case NepRelation::kNone:
        break;
    }
    if (decision.potential_outlier) {
      // A NEP that disagrees (nearer or further) casts doubt on the laser point (thesis 8.4).
      if (relation == NepRelation::kNearer || relation == NepRelation::kFurther) {
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
