#include "operator_client/vision/nesc.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/check/check.h"
#include "operator_client/vision/nep_classifier.h"

namespace mostar::vision {
namespace {

double Median(std::vector<double> values) {
  MOSTAR_CHECK(!values.empty());
  const size_t middle = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + middle, values.end());
  double median = values[middle];
  if (values.size() % 2 == 0) {
    median = 0.5 * (median + *std::max_element(values.begin(), values.begin() + middle));
  }
  return median;
}

// The right-image pixel of `nep` (found in either image), or nullopt when not visible.
std::optional<Eigen::Vector2d> RightPixel(const Nep& nep, const math::CameraModel& right_camera) {
  const std::optional<Eigen::Vector2d> pixel = right_camera.Project(nep.floor_point_laser);
  if (!pixel || !right_camera.IsInImage(*pixel)) return std::nullopt;
  return pixel;
}

}  // namespace

bool NescOptions::IsValid(std::string* error) const {
  std::ostringstream why;
  if (!(std::isfinite(stereo_threshold_m) && stereo_threshold_m > 0.0 &&
        stereo_threshold_m <= 5.0)) {
    why << "stereo_threshold_m must be in (0, 5] (got " << stereo_threshold_m << ")";
  } else if (!(offset_max_residual_px > 0.0 && offset_max_residual_px <= 100.0)) {
    why << "offset_max_residual_px must be in (0, 100] (got " << offset_max_residual_px << ")";
  } else if (!(min_threshold_px >= 0.0 && min_threshold_px <= 20.0)) {
    why << "min_threshold_px must be in [0, 20] (got " << min_threshold_px << ")";
  } else if (offset_min_samples < 1) {
    why << "offset_min_samples must be >= 1 (got " << offset_min_samples << ")";
  } else {
    return true;
  }
  if (error != nullptr) *error = why.str();
  return false;
}

const char* StereoNepKindName(StereoNepKind kind) {
  switch (kind) {
    case StereoNepKind::kNone:
      return "none";
    case StereoNepKind::kLeftOnly:
      return "left_only";
    case StereoNepKind::kRightOnly:
      return "right_only";
    case StereoNepKind::kMatched:
      return "matched";
    case StereoNepKind::kDisagree:
      return "disagree";
  }
  return "?";
}

bool RunNesc(const NedResult& left, const NedResult& right, const LaserScan& scan,
             const math::CameraModel& right_camera, const NescOptions& options,
             const NepClassifierOptions& classifier, NescResult* out, std::string* error) {
  MOSTAR_CHECK(out != nullptr);
  const size_t n = scan.ranges_m.size();
  *out = NescResult{};
  out->kinds.assign(n, StereoNepKind::kNone);
  out->selected.assign(n, Nep{});
  if (!options.IsValid(error)) return false;
  if (!classifier.IsValid(error)) return false;
  if (left.neps.size() != n || right.neps.size() != n) {
    if (error != nullptr) {
      std::ostringstream why;
      why << "NESC needs one NEP per beam in each eye (beams " << n << ", left " << left.neps.size()
          << ", right " << right.neps.size() << ")";
      *error = why.str();
    }
    return false;
  }

  std::vector<double> residuals_px;
  residuals_px.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const Nep& l = left.neps[i];
    const Nep& r = right.neps[i];
    Nep& selected = out->selected[i];
    if (!l.found && !r.found) continue;
    if (l.found != r.found) {
      out->kinds[i] = l.found ? StereoNepKind::kLeftOnly : StereoNepKind::kRightOnly;
      ++out->one_eye;
      selected = l.found ? l : r;
      selected.reliable = false;
    } else {
      // Both on the same virtual ray: their floor distance is their 3D distance.
      const double threshold_m =
          std::max(options.stereo_threshold_m,
                   options.min_threshold_px * 0.5 * (l.metres_per_px + r.metres_per_px));
      if (std::abs(l.distance_m - r.distance_m) < threshold_m) {
        out->kinds[i] = StereoNepKind::kMatched;
        ++out->matched;
        selected = r;
        selected.distance_m = 0.5 * (l.distance_m + r.distance_m);
        selected.floor_point_laser = 0.5 * (l.floor_point_laser + r.floor_point_laser);
        selected.reliable = true;
        selected.along_ray = l.along_ray || r.along_ray;
        selected.starts_on_object = l.starts_on_object || r.starts_on_object;
      } else {
        out->kinds[i] = StereoNepKind::kDisagree;
        ++out->disagree;
        const float range_m = scan.ranges_m[i];
        const bool left_agrees = RelateNepToLaser(l, range_m, classifier) == NepRelation::kAgrees;
        const bool right_agrees = RelateNepToLaser(r, range_m, classifier) == NepRelation::kAgrees;
        if (left_agrees || right_agrees) {
          ++out->disagree_resolved;
          const bool take_left = left_agrees && (!right_agrees || l.distance_m <= r.distance_m);
          selected = take_left ? l : r;
        } else {
          // Neither agrees: both would be disregarded; keep the nearer for display/debugging.
          selected = l.distance_m <= r.distance_m ? l : r;
        }
        selected.reliable = false;
      }
      // Stereo offset hint: the row residual of the right NEP against the left NEP's point.
      const std::optional<Eigen::Vector2d> expected = RightPixel(l, right_camera);
      if (expected) {
        const double residual_px = r.pixel.y() - expected->y();
        if (std::abs(residual_px) <= options.offset_max_residual_px) {
          residuals_px.push_back(residual_px);
        }
      }
    }
    // Pixels of the selected NEP are in the right image.
    if (const std::optional<Eigen::Vector2d> pixel = RightPixel(selected, right_camera)) {
      selected.pixel = *pixel;
    }
  }

  out->offset.samples = static_cast<int>(residuals_px.size());
  if (out->offset.samples >= options.offset_min_samples) {
    const double median = Median(residuals_px);
    std::vector<double> deviations;
    deviations.reserve(residuals_px.size());
    for (const double r : residuals_px) deviations.push_back(std::abs(r - median));
    out->offset.valid = true;
    out->offset.vertical_offset_px = median;
    out->offset.spread_px = Median(std::move(deviations));
  }
  return true;
}

}  // namespace mostar::vision
