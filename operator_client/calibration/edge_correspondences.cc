#include "operator_client/calibration/edge_correspondences.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>

namespace mostar::calibration {
namespace {

constexpr double kHalfPi = 1.5707963267948966;

bool Fail(std::string* error, const std::string& message) {
  if (error != nullptr) *error = message;
  return false;
}

// The floor point (laser frame) of beam i, when its range is usable.
bool BeamBase(const LaserScan& scan, size_t i, double laser_height_m, double max_range_m,
              Eigen::Vector3d* out) {
  const float r = scan.ranges_m[i];
  if (!LaserScan::IsValidRange(r) || r < scan.range_min_m || r > max_range_m) return false;
  const double a = scan.AngleOf(i);
  *out = Eigen::Vector3d(r * std::cos(a), r * std::sin(a), -laser_height_m);
  return true;
}

// The straight base line through beam i and its neighbours: where beam i meets it (the laser
// point with the range noise of one beam averaged over the line's) and its horizontal unit
// direction, when every neighbour is usable and close to the line and the line is not seen
// end-on.
bool BaseLine(const LaserScan& scan, size_t i, double laser_height_m,
              const CorrespondenceOptions& options, Eigen::Vector3d* base,
              Eigen::Vector3d* direction) {
  const int half = options.line_half_beams;
  if (static_cast<int>(i) < half || i + half >= scan.ranges_m.size()) return false;
  std::vector<Eigen::Vector2d> points;
  for (size_t j = i - half; j <= i + half; ++j) {
    Eigen::Vector3d p;
    if (!BeamBase(scan, j, laser_height_m, options.max_range_m, &p)) return false;
    points.push_back(p.head<2>());
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& p : points) scatter += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(scatter);
  const Eigen::Vector2d along = solver.eigenvectors().col(1);
  const Eigen::Vector2d across = solver.eigenvectors().col(0);
  for (const Eigen::Vector2d& p : points) {
    if (std::abs(across.dot(p - mean)) > options.max_line_residual_m) return false;
  }
  const double a = scan.AngleOf(i);
  const Eigen::Vector2d beam(std::cos(a), std::sin(a));
  const double incidence = std::acos(std::min(1.0, std::abs(along.dot(beam))));
  if (incidence < options.min_incidence_rad) return false;
  // mean + s along = t beam.
  Eigen::Matrix2d m;
  m << beam, -along;
  const Eigen::Vector2d ts = m.colPivHouseholderQr().solve(mean);
  const Eigen::Vector2d on_line = ts.x() * beam;
  *base = Eigen::Vector3d(on_line.x(), on_line.y(), -laser_height_m);
  *direction = Eigen::Vector3d(along.x(), along.y(), 0.0);
  return true;
}

}  // namespace

bool CorrespondenceOptions::IsValid(std::string* error) const {
  if (line_half_beams < 1 || line_half_beams > 10) {
    return Fail(error, "line_half_beams must be in [1, 10]");
  }
  if (!(max_line_residual_m > 0.0) || !std::isfinite(max_line_residual_m)) {
    return Fail(error, "max_line_residual_m must be > 0");
  }
  if (!(min_incidence_rad >= 0.0 && min_incidence_rad < kHalfPi)) {
    return Fail(error, "min_incidence_rad must be in [0, pi/2)");
  }
  if (!(max_range_m > 0.0) || !std::isfinite(max_range_m)) {
    return Fail(error, "max_range_m must be > 0");
  }
  return true;
}

std::vector<EdgeCorrespondence> ExtractCorrespondences(
    const vision::VisionResult& result, const LaserScan& scan,
    const vision::NepClassifierOptions& classifier, double laser_height_m,
    const CorrespondenceOptions& options) {
  std::vector<EdgeCorrespondence> out;
  const size_t beams = scan.ranges_m.size();
  if (!result.ok || !options.IsValid(nullptr) || !(laser_height_m > 0.0) ||
      result.classification.beams.size() != beams) {
    return out;
  }
  const vision::NedResult* neds[2] = {&result.left_ned, &result.right_ned};
  for (size_t i = 0; i < beams; ++i) {
    if (result.classification.beams[i].relation != vision::NepRelation::kAgrees) continue;
    Eigen::Vector3d base;
    Eigen::Vector3d direction;
    if (!BaseLine(scan, i, laser_height_m, options, &base, &direction)) {
      continue;
    }
    for (int e = 0; e < 2; ++e) {
      if (neds[e]->neps.size() != beams) continue;
      const vision::Nep& nep = neds[e]->neps[i];
      if (!nep.found || vision::RelateNepToLaser(nep, scan.ranges_m[i], classifier) !=
                            vision::NepRelation::kAgrees) {
        continue;
      }
      EdgeCorrespondence c;
      c.eye = e == 0 ? Eye::kLeft : Eye::kRight;
      c.base_laser = base;
      c.direction_laser = direction;
      c.pixel = nep.pixel;
      c.stamp = result.stamp;
      out.push_back(c);
    }
  }
  return out;
}

CorrespondenceWindow::CorrespondenceWindow(size_t capacity, Duration max_age)
    : capacity_(std::max<size_t>(capacity, 1)), max_age_(max_age) {}

void CorrespondenceWindow::Add(const std::vector<EdgeCorrespondence>& correspondences) {
  Time newest = items_.empty() ? Time{} : items_.back().stamp;
  for (const EdgeCorrespondence& c : correspondences) {
    items_.push_back(c);
    newest = std::max(newest, c.stamp);
  }
  while (items_.size() > capacity_) items_.pop_front();
  while (!items_.empty() && items_.front().stamp + max_age_ < newest) items_.pop_front();
}

std::vector<EdgeCorrespondence> CorrespondenceWindow::Snapshot() const {
  return std::vector<EdgeCorrespondence>(items_.begin(), items_.end());
}

}  // namespace mostar::calibration
