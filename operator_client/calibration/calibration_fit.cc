#include "operator_client/calibration/calibration_fit.h"

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <memory>
#include <sstream>

#include "common/stats/percentile.h"

namespace mostar::calibration {
namespace {

// Central-difference steps (px, m, m, m, rad, rad, rad): far above rounding, far below the
// scale on which the projection bends.
constexpr ParameterVector kSteps = {1e-2, 1e-5, 1e-5, 1e-5, 1e-6, 1e-6, 1e-6};
// Half length of the base line segment whose image gives the line's direction, metres.
constexpr double kTangentHalfM = 0.05;

bool Fail(std::string* error, const std::string& message) {
  if (error != nullptr) *error = message;
  return false;
}

// `value` with `digits` decimals.
std::string Fixed(double value, int digits) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

// The eyes' models for a parameter vector. Memoises the last few vectors: the solver evaluates
// every point at the same parameters (and the same difference steps), and building a model is
// far dearer than projecting with it. Single-threaded (the solver runs with one thread).
class ModelCache {
 public:
  struct Models {
    ParameterVector key;
    std::optional<math::CameraModel> eye[2];  // left, right; unset = invalid calibration
  };

  explicit ModelCache(const FitInput& input) : input_(input), start_(ParametersOf(input.left)) {}

  const Models& Get(const ParameterVector& p) {
    for (const Models& m : entries_) {
      if (m.key == p) return m;
    }
    if (entries_.size() >= kEntries) entries_.erase(entries_.begin());
    Models m;
    m.key = p;
    m.eye[0] =
        math::CameraModel::Create(MoveParameters(input_.left, start_, p), Eye::kLeft, nullptr);
    if (input_.right) {
      m.eye[1] =
          math::CameraModel::Create(MoveParameters(*input_.right, start_, p), Eye::kRight, nullptr);
    }
    entries_.push_back(std::move(m));
    return entries_.back();
  }

 private:
  static constexpr size_t kEntries = 2 * kParameterCount + 4;
  const FitInput& input_;
  const ParameterVector start_;
  std::vector<Models> entries_;
};

// Signed distance (px) from the correspondence's pixel to the image of its base line, tangent
// at the base point's image; false when the line does not project.
bool Residual(const EdgeCorrespondence& c, const ModelCache::Models& models, double* residual) {
  const std::optional<math::CameraModel>& model = models.eye[c.eye == Eye::kLeft ? 0 : 1];
  if (!model) return false;
  const std::optional<Eigen::Vector2d> p0 = model->Project(c.base_laser);
  const std::optional<Eigen::Vector2d> a =
      model->Project(c.base_laser - kTangentHalfM * c.direction_laser);
  const std::optional<Eigen::Vector2d> b =
      model->Project(c.base_laser + kTangentHalfM * c.direction_laser);
  if (!p0 || !a || !b) return false;
  const Eigen::Vector2d d = *b - *a;
  const double length = d.norm();
  if (!(length > 1e-6)) return false;
  const Eigen::Vector2d normal(-d.y() / length, d.x() / length);
  *residual = normal.dot(c.pixel - *p0);
  return std::isfinite(*residual);
}

bool Gradient(const EdgeCorrespondence& c, ModelCache* cache, const ParameterVector& p,
              Eigen::Matrix<double, 1, kParameterCount>* gradient) {
  for (int j = 0; j < kParameterCount; ++j) {
    ParameterVector plus = p;
    ParameterVector minus = p;
    plus[j] += kSteps[j];
    minus[j] -= kSteps[j];
    double r_plus = 0.0;
    double r_minus = 0.0;
    if (!Residual(c, cache->Get(plus), &r_plus) || !Residual(c, cache->Get(minus), &r_minus)) {
      return false;
    }
    (*gradient)(0, j) = (r_plus - r_minus) / (2.0 * kSteps[j]);
  }
  return true;
}

class LineCost : public ceres::SizedCostFunction<1, kParameterCount> {
 public:
  LineCost(const EdgeCorrespondence& c, ModelCache* cache) : c_(c), cache_(cache) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    ParameterVector p;
    std::copy(parameters[0], parameters[0] + kParameterCount, p.begin());
    if (!Residual(c_, cache_->Get(p), residuals)) return false;
    if (jacobians == nullptr || jacobians[0] == nullptr) return true;
    Eigen::Matrix<double, 1, kParameterCount> gradient;
    if (!Gradient(c_, cache_, p, &gradient)) return false;
    std::copy(gradient.data(), gradient.data() + kParameterCount, jacobians[0]);
    return true;
  }

 private:
  const EdgeCorrespondence& c_;
  ModelCache* cache_;
};

// (p - start) / sigma for the free parameters.
class PriorCost : public ceres::SizedCostFunction<kParameterCount, kParameterCount> {
 public:
  PriorCost(const ParameterVector& start, const ParameterVector& sigma)
      : start_(start), sigma_(sigma) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    for (int j = 0; j < kParameterCount; ++j) {
      residuals[j] = (parameters[0][j] - start_[j]) / sigma_[j];
    }
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      std::fill(jacobians[0], jacobians[0] + kParameterCount * kParameterCount, 0.0);
      for (int j = 0; j < kParameterCount; ++j) {
        jacobians[0][j * kParameterCount + j] = 1.0 / sigma_[j];
      }
    }
    return true;
  }

 private:
  ParameterVector start_;
  ParameterVector sigma_;
};

// One robust solve from `p`; returns the iterations used, -1 when the solver failed.
int Solve(const std::vector<EdgeCorrespondence>& points, ModelCache* cache,
          const ParameterVector& start, const FitOptions& options, ceres::LossFunction* loss,
          ParameterVector* p) {
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  for (const EdgeCorrespondence& c : points) {
    problem.AddResidualBlock(new LineCost(c, cache), loss, p->data());
  }
  const double f = start[kFocal];
  const ParameterVector prior_sigma = {options.prior_focal_fraction * f, options.prior_position_m,
                                       options.prior_position_m,         options.prior_position_m,
                                       options.prior_angle_rad,          options.prior_angle_rad,
                                       options.prior_angle_rad};
  problem.AddResidualBlock(new PriorCost(start, prior_sigma), nullptr, p->data());
  std::vector<int> fixed;
  for (int j = 0; j < kParameterCount; ++j) {
    if (!options.free[j]) fixed.push_back(j);
  }
  if (!fixed.empty()) {
    problem.SetManifold(p->data(), new ceres::SubsetManifold(kParameterCount, fixed));
  }
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.max_solver_time_in_seconds = options.max_solver_time_s;
  solver_options.num_threads = 1;  // ModelCache is single-threaded
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  if (!summary.IsSolutionUsable()) return -1;
  return static_cast<int>(summary.iterations.size());
}

ReprojectionError ErrorOf(const std::vector<double>& residuals) {
  std::vector<double> magnitudes;
  for (const double r : residuals) magnitudes.push_back(std::abs(r));
  ReprojectionError e;
  e.p50_px = Percentile(magnitudes, 0.5).value_or(0.0);
  e.p95_px = Percentile(magnitudes, 0.95).value_or(0.0);
  return e;
}

double Span(std::vector<double> values) {
  const std::optional<double> lo = Percentile(values, 0.05);
  const std::optional<double> hi = Percentile(std::move(values), 0.95);
  return lo && hi ? *hi - *lo : 0.0;
}

// Standard deviations of the free parameters from the inliers' gradients and residual spread;
// false with `reason` when some combination of free parameters is not determined.
bool Uncertainty(const std::vector<EdgeCorrespondence>& inliers,
                 const std::vector<double>& residuals, ModelCache* cache, const ParameterVector& p,
                 const FitOptions& options, ParameterVector* sigma, std::string* reason) {
  std::vector<int> free;
  for (int j = 0; j < kParameterCount; ++j) {
    if (options.free[j]) free.push_back(j);
  }
  const int k = static_cast<int>(free.size());
  sigma->fill(0.0);
  if (k == 0) return true;
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(k, k);
  for (size_t i = 0; i < inliers.size(); ++i) {
    Eigen::Matrix<double, 1, kParameterCount> g;
    if (!Gradient(inliers[i], cache, p, &g)) continue;
    Eigen::VectorXd gf(k);
    for (int a = 0; a < k; ++a) gf[a] = g(0, free[a]);
    normal += gf * gf.transpose();
  }
  // The residual spread, robustly (1.4826 MAD: wrong points within inlier_px do not inflate it),
  // at least the NEP's pixel quantisation (a uniform pixel: 1/sqrt(12)).
  std::vector<double> magnitudes;
  for (const double r : residuals) magnitudes.push_back(std::abs(r));
  const double mad_sigma = 1.4826 * Percentile(std::move(magnitudes), 0.5).value_or(0.0);
  const double variance = std::max(mad_sigma * mad_sigma, 1.0 / 12.0);
  // Scaled so that every parameter's bound is 1.
  const ParameterVector bound = {options.max_sigma_focal_fraction * p[kFocal],
                                 options.max_sigma_position_m,
                                 options.max_sigma_position_m,
                                 options.max_sigma_position_m,
                                 options.max_sigma_angle_rad,
                                 options.max_sigma_angle_rad,
                                 options.max_sigma_angle_rad};
  Eigen::VectorXd scale(k);
  for (int a = 0; a < k; ++a) scale[a] = bound[free[a]];
  const Eigen::MatrixXd scaled = scale.asDiagonal() * normal * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(scaled);
  const double largest = solver.eigenvalues().maxCoeff();
  if (!(solver.eigenvalues().minCoeff() > 1e-9 * largest) || !(largest > 0.0)) {
    Eigen::Index worst = 0;
    solver.eigenvectors().col(0).cwiseAbs().maxCoeff(&worst);
    *reason = std::string("not determined by the points: ") + FitParameterName(free[worst]);
    return false;
  }
  const Eigen::MatrixXd covariance = variance * scaled.inverse();
  for (int a = 0; a < k; ++a) {
    (*sigma)[free[a]] = std::sqrt(std::max(0.0, covariance(a, a))) * scale[a];
  }
  for (int a = 0; a < k; ++a) {
    if ((*sigma)[free[a]] > bound[free[a]]) {
      const bool angle = free[a] >= kTilt;
      const bool focal = free[a] == kFocal;
      const double shown = (*sigma)[free[a]] * (angle ? 180.0 / M_PI : (focal ? 1.0 : 1000.0));
      *reason = std::string(FitParameterName(free[a])) + " uncertain: +-" +
                Fixed(shown, angle ? 2 : 1) + (angle ? " deg" : (focal ? " px" : " mm"));
      return false;
    }
  }
  return true;
}

}  // namespace

const char* FitParameterName(int parameter) {
  switch (parameter) {
    case kFocal:
      return "focal length";
    case kCameraX:
      return "camera x";
    case kCameraY:
      return "camera y";
    case kCameraZ:
      return "camera z";
    case kTilt:
      return "tilt";
    case kPan:
      return "pan";
    case kRoll:
      return "roll";
    default:
      return "?";
  }
}

bool FitOptions::IsValid(std::string* error) const {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(coarse_loss_px) || !positive(loss_px) || !positive(inlier_px)) {
    return Fail(error, "loss scales and inlier_px must be > 0");
  }
  if (max_points < 1 || max_iterations < 1 || !positive(max_solver_time_s)) {
    return Fail(error, "max_points, max_iterations and max_solver_time_s must be > 0");
  }
  if (!positive(prior_focal_fraction) || !positive(prior_position_m) ||
      !positive(prior_angle_rad)) {
    return Fail(error, "prior standard deviations must be > 0");
  }
  if (!positive(max_sigma_focal_fraction) || !positive(max_sigma_position_m) ||
      !positive(max_sigma_angle_rad)) {
    return Fail(error, "standard deviation bounds must be > 0");
  }
  if (std::none_of(free.begin(), free.end(), [](bool f) { return f; })) {
    return Fail(error, "no parameter is free");
  }
  if (!(min_width_fraction >= 0.0 && min_width_fraction <= 1.0) ||
      !(min_height_fraction >= 0.0 && min_height_fraction <= 1.0) ||
      !(min_inlier_fraction >= 0.0 && min_inlier_fraction <= 1.0)) {
    return Fail(error, "fractions must be in [0, 1]");
  }
  return true;
}

ParameterVector ParametersOf(const math::LaserCameraCalibration& c) {
  return {c.focal_px, c.camera_x_m, c.camera_y_m, c.camera_z_m, c.tilt_rad, c.pan_rad, c.roll_rad};
}

math::LaserCameraCalibration MoveParameters(const math::LaserCameraCalibration& base,
                                            const ParameterVector& from,
                                            const ParameterVector& to) {
  math::LaserCameraCalibration c = base;
  const double ratio = to[kFocal] / from[kFocal];
  c.focal_px *= ratio;
  if (c.focal_y_px) *c.focal_y_px *= ratio;
  c.camera_x_m += to[kCameraX] - from[kCameraX];
  c.camera_y_m += to[kCameraY] - from[kCameraY];
  c.camera_z_m += to[kCameraZ] - from[kCameraZ];
  c.tilt_rad += to[kTilt] - from[kTilt];
  c.pan_rad += to[kPan] - from[kPan];
  c.roll_rad += to[kRoll] - from[kRoll];
  return c;
}

FitResult FitCalibration(const FitInput& input, const FitOptions& options) {
  FitResult result;
  result.start = input.left;
  result.proposal = input.left;
  std::string error;
  if (!options.IsValid(&error) || !input.left.IsValid(&error) ||
      (input.right && !input.right->IsValid(&error))) {
    result.reason = "invalid input: " + error;
    return result;
  }
  const ParameterVector start = ParametersOf(input.left);
  ModelCache cache(input);
  // The newest points that project with the start calibration.
  std::vector<EdgeCorrespondence> points;
  const size_t first =
      input.points.size() > options.max_points ? input.points.size() - options.max_points : 0;
  std::vector<double> before;
  for (size_t i = first; i < input.points.size(); ++i) {
    double r = 0.0;
    if (Residual(input.points[i], cache.Get(start), &r)) {
      points.push_back(input.points[i]);
      before.push_back(r);
    }
  }
  result.points = points.size();
  if (points.size() < options.min_points) {
    result.reason = "too few correspondences: " + std::to_string(points.size()) + " of " +
                    std::to_string(options.min_points);
    return result;
  }

  ParameterVector p = start;
  ceres::HuberLoss coarse(options.coarse_loss_px);
  ceres::CauchyLoss fine(options.loss_px);
  const int coarse_iterations = Solve(points, &cache, start, options, &coarse, &p);
  const int fine_iterations =
      coarse_iterations < 0 ? -1 : Solve(points, &cache, start, options, &fine, &p);
  if (fine_iterations < 0) {
    result.reason = "the solver found no usable solution";
    return result;
  }
  result.iterations = coarse_iterations + fine_iterations;
  result.proposal = MoveParameters(input.left, start, p);
  if (!result.proposal.IsValid(&error)) {
    result.reason = "the proposal is not a valid calibration: " + error;
    return result;
  }
  result.ok = true;

  // Errors over the proposal's inliers, before and after.
  std::vector<EdgeCorrespondence> inliers;
  std::vector<double> after_in;
  std::vector<double> before_in;
  std::vector<double> u;
  std::vector<double> v;
  for (size_t i = 0; i < points.size(); ++i) {
    double r = 0.0;
    if (!Residual(points[i], cache.Get(p), &r) || std::abs(r) > options.inlier_px) continue;
    inliers.push_back(points[i]);
    after_in.push_back(r);
    before_in.push_back(before[i]);
    u.push_back(points[i].pixel.x());
    v.push_back(points[i].pixel.y());
  }
  result.inliers = inliers.size();
  result.before = ErrorOf(before_in);
  result.after = ErrorOf(after_in);

  const double inlier_fraction = static_cast<double>(inliers.size()) / points.size();
  if (inliers.size() < options.min_points) {
    result.reason = "too few points fit: " + std::to_string(inliers.size()) + " of " +
                    std::to_string(options.min_points);
  } else if (inlier_fraction < options.min_inlier_fraction) {
    result.reason = "only " + Fixed(100.0 * inlier_fraction, 0) + " % of the points fit";
  } else if (Span(u) < options.min_width_fraction * input.left.image_width_px) {
    result.reason = "the points cover too little of the image width (" + Fixed(Span(u), 0) + " px)";
  } else if (Span(v) < options.min_height_fraction * input.left.image_height_px) {
    result.reason =
        "the points cover too little of the image height (" + Fixed(Span(v), 0) + " px)";
  } else if (Uncertainty(inliers, after_in, &cache, p, options, &result.sigma, &result.reason)) {
    result.trustworthy = true;
  }
  return result;
}

}  // namespace mostar::calibration
