#include "common/math/camera_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/check/check.h"

namespace mostar::math {
namespace {

constexpr double kHalfPi = 1.5707963267948966;
constexpr double kQuarterPi = 0.7853981633974483;

bool Fail(std::string* error, const std::string& message) {
  if (error != nullptr) *error = message;
  return false;
}

std::string Num(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// Checks that `value` is finite; names it otherwise.
bool CheckFinite(const char* name, double value, std::string* error) {
  if (std::isfinite(value)) return true;
  return Fail(error, std::string(name) + " must be finite (got " + Num(value) + ")");
}

// Checks lo < value < hi (open interval).
bool CheckOpen(const char* name, double value, double lo, double hi, std::string* error) {
  if (!CheckFinite(name, value, error)) return false;
  if (value > lo && value < hi) return true;
  return Fail(error, std::string(name) + " must be in (" + Num(lo) + ", " + Num(hi) + ") (got " +
                         Num(value) + ")");
}

bool CheckPositive(const char* name, double value, std::string* error) {
  if (!CheckFinite(name, value, error)) return false;
  if (value > 0.0) return true;
  return Fail(error, std::string(name) + " must be > 0 (got " + Num(value) + ")");
}

// Right-handed rotations about the x and z axes.
Eigen::Matrix3d RotX(double angle_rad) {
  return Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitX()).toRotationMatrix();
}
Eigen::Matrix3d RotZ(double angle_rad) {
  return Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// Restricts [*lo, *hi] to {t : alpha + beta * t >= 0}. Returns false when the set is empty.
bool ClipLinear(double alpha, double beta, double* lo, double* hi) {
  constexpr double kTiny = 1e-15;
  if (std::abs(beta) < kTiny) return alpha >= 0.0;
  const double bound = -alpha / beta;
  if (beta > 0.0) {
    *lo = std::max(*lo, bound);
  } else {
    *hi = std::min(*hi, bound);
  }
  return *lo <= *hi;
}

// Largest r^2 such that r * radial(r) is increasing on [0, r], i.e. the derivative
// 1 + 3 k1 r^2 + 5 k2 r^4 + 7 k3 r^6 stays positive; infinity when it never vanishes (searched up
// to r = 10, far beyond any lens' field of view in normalised coordinates).
double MonotonicRadius2(const DistortionCoefficients& d) {
  const auto slope = [&d](double r2) {
    return 1.0 + r2 * (3.0 * d.k1 + r2 * (5.0 * d.k2 + r2 * 7.0 * d.k3));
  };
  constexpr double kMaxRadius2 = 100.0;
  constexpr double kStep = 1e-3;
  for (double r2 = kStep; r2 <= kMaxRadius2; r2 += kStep) {
    if (slope(r2) <= 0.0) {
      double lo = r2 - kStep;
      double hi = r2;
      for (int i = 0; i < 50; ++i) {
        const double mid = 0.5 * (lo + hi);
        (slope(mid) > 0.0 ? lo : hi) = mid;
      }
      return lo;
    }
  }
  return std::numeric_limits<double>::infinity();
}

}  // namespace

const char* RigCameraName(RigCamera camera) { return camera ? EyeName(*camera) : "mono"; }

double LaserCameraCalibration::EyeX(RigCamera camera) const {
  if (!camera) return camera_x_m;
  return camera_x_m + (*camera == Eye::kLeft ? left_eye_x_offset_m : right_eye_x_offset_m);
}

bool LaserCameraCalibration::IsValid(std::string* error) const {
  if (image_width_px <= 0) {
    return Fail(error, "image_width_px must be > 0 (got " + std::to_string(image_width_px) + ")");
  }
  if (image_height_px <= 0) {
    return Fail(error, "image_height_px must be > 0 (got " + std::to_string(image_height_px) + ")");
  }
  if (!CheckPositive("focal_px", focal_px, error)) return false;
  if (focal_y_px.has_value() && !CheckPositive("focal_y_px", *focal_y_px, error)) return false;
  if (principal_x_px.has_value() &&
      !CheckOpen("principal_x_px", *principal_x_px, -0.5, image_width_px - 0.5, error)) {
    return false;
  }
  if (principal_y_px.has_value() &&
      !CheckOpen("principal_y_px", *principal_y_px, -0.5, image_height_px - 0.5, error)) {
    return false;
  }
  if (!CheckFinite("distortion.k1", distortion.k1, error) ||
      !CheckFinite("distortion.k2", distortion.k2, error) ||
      !CheckFinite("distortion.p1", distortion.p1, error) ||
      !CheckFinite("distortion.p2", distortion.p2, error) ||
      !CheckFinite("distortion.k3", distortion.k3, error)) {
    return false;
  }
  if (!CheckFinite("camera_x_m", camera_x_m, error) ||
      !CheckFinite("camera_y_m", camera_y_m, error) ||
      !CheckFinite("camera_z_m", camera_z_m, error)) {
    return false;
  }
  if (!CheckOpen("tilt_rad", tilt_rad, -kHalfPi, kHalfPi, error) ||
      !CheckOpen("pan_rad", pan_rad, -kHalfPi, kHalfPi, error) ||
      !CheckOpen("roll_rad", roll_rad, -kQuarterPi, kQuarterPi, error)) {
    return false;
  }
  if (!CheckFinite("left_eye_x_offset_m", left_eye_x_offset_m, error) ||
      !CheckFinite("right_eye_x_offset_m", right_eye_x_offset_m, error)) {
    return false;
  }
  if (left_eye_x_offset_m > right_eye_x_offset_m) {
    return Fail(error, "left_eye_x_offset_m (" + Num(left_eye_x_offset_m) +
                           ") must not exceed right_eye_x_offset_m (" + Num(right_eye_x_offset_m) +
                           "): the left eye is on the left");
  }
  if (!CheckPositive("laser_height_m", laser_height_m, error)) return false;
  if (!(laser_height_m + camera_y_m > 0.0)) {
    return Fail(error,
                "laser_height_m + camera_y_m must be > 0: the camera must be above the "
                "floor (got " +
                    Num(laser_height_m + camera_y_m) + " m)");
  }
  return true;
}

CameraModel::CameraModel(const LaserCameraCalibration& calibration, RigCamera camera)
    : calibration_(calibration), eye_(camera) {
  MOSTAR_CHECK(calibration_.IsValid(nullptr));
  // Columns: the level camera's x (right), y (down), z (forward) axes in the laser frame.
  Eigen::Matrix3d laser_from_level;
  laser_from_level << 0.0, 0.0, 1.0,  //
      -1.0, 0.0, 0.0,                 //
      0.0, -1.0, 0.0;
  const Eigen::Matrix3d rotation = RotZ(calibration_.pan_rad) * laser_from_level *
                                   RotX(-calibration_.tilt_rad) * RotZ(calibration_.roll_rad);
  laser_from_camera_ = Eigen::Isometry3d::Identity();
  laser_from_camera_.linear() = rotation;
  laser_from_camera_.translation() =
      Eigen::Vector3d(calibration_.camera_z_m, -calibration_.EyeX(camera), calibration_.camera_y_m);
  camera_from_laser_ = laser_from_camera_.inverse(Eigen::Isometry);

  max_radius2_ = MonotonicRadius2(calibration_.distortion);
  // Bounding box of the image border in undistorted normalised coordinates.
  const double w = calibration_.image_width_px;
  const double h = calibration_.image_height_px;
  undistorted_min_.setConstant(std::numeric_limits<double>::infinity());
  undistorted_max_.setConstant(-std::numeric_limits<double>::infinity());
  constexpr int kSamples = 64;
  for (int i = 0; i <= kSamples; ++i) {
    const double s = static_cast<double>(i) / kSamples;
    const Eigen::Vector2d border[4] = {{-0.5 + s * w, -0.5},
                                       {-0.5 + s * w, h - 0.5},
                                       {-0.5, -0.5 + s * h},
                                       {w - 0.5, -0.5 + s * h}};
    for (const Eigen::Vector2d& pixel : border) {
      const Eigen::Vector2d distorted((pixel.x() - calibration_.cx()) / calibration_.fx(),
                                      (pixel.y() - calibration_.cy()) / calibration_.fy());
      const Eigen::Vector2d undistorted = Undistort(distorted);
      undistorted_min_ = undistorted_min_.cwiseMin(undistorted);
      undistorted_max_ = undistorted_max_.cwiseMax(undistorted);
    }
  }
}

std::optional<CameraModel> CameraModel::Create(const LaserCameraCalibration& calibration,
                                               RigCamera camera, std::string* error) {
  if (!calibration.IsValid(error)) return std::nullopt;
  return CameraModel(calibration, camera);
}

Eigen::Matrix3d CameraModel::IntrinsicMatrix() const {
  Eigen::Matrix3d k;
  k << calibration_.fx(), 0.0, calibration_.cx(),  //
      0.0, calibration_.fy(), calibration_.cy(),   //
      0.0, 0.0, 1.0;
  return k;
}

std::optional<Eigen::Vector2d> CameraModel::Project(const Eigen::Vector3d& point_laser) const {
  return ProjectCameraPoint(camera_from_laser_ * point_laser);
}

std::optional<Eigen::Vector2d> CameraModel::ProjectCameraPoint(
    const Eigen::Vector3d& point_camera) const {
  if (!point_camera.allFinite() || !(point_camera.z() >= kMinDepthM)) return std::nullopt;
  const Eigen::Vector2d normalised = point_camera.head<2>() / point_camera.z();
  if (!(normalised.squaredNorm() <= max_radius2_)) return std::nullopt;
  const Eigen::Vector2d distorted = Distort(normalised);
  return Eigen::Vector2d(calibration_.fx() * distorted.x() + calibration_.cx(),
                         calibration_.fy() * distorted.y() + calibration_.cy());
}

std::optional<Eigen::Vector2d> CameraModel::ProjectUndistorted(
    const Eigen::Vector3d& point_laser) const {
  const Eigen::Vector3d point_camera = camera_from_laser_ * point_laser;
  if (!point_camera.allFinite() || !(point_camera.z() >= kMinDepthM)) return std::nullopt;
  return Eigen::Vector2d(
      calibration_.fx() * point_camera.x() / point_camera.z() + calibration_.cx(),
      calibration_.fy() * point_camera.y() / point_camera.z() + calibration_.cy());
}

bool CameraModel::IsInImage(const Eigen::Vector2d& pixel) const {
  return pixel.x() >= -0.5 && pixel.x() <= calibration_.image_width_px - 0.5 && pixel.y() >= -0.5 &&
         pixel.y() <= calibration_.image_height_px - 0.5;
}

Eigen::Vector3d CameraModel::PixelRayInLaser(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d distorted((pixel.x() - calibration_.cx()) / calibration_.fx(),
                                  (pixel.y() - calibration_.cy()) / calibration_.fy());
  const Eigen::Vector2d normalised = Undistort(distorted);
  const Eigen::Vector3d ray_camera(normalised.x(), normalised.y(), 1.0);
  return (laser_from_camera_.linear() * ray_camera).normalized();
}

std::optional<Eigen::Vector3d> CameraModel::UnprojectToHeight(const Eigen::Vector2d& pixel,
                                                              double plane_z_m,
                                                              double max_range_m) const {
  if (!pixel.allFinite() || !std::isfinite(plane_z_m)) return std::nullopt;
  const Eigen::Vector3d direction = PixelRayInLaser(pixel);
  const Eigen::Vector3d center = CameraCenterInLaser();
  const double dz = plane_z_m - center.z();
  constexpr double kTiny = 1e-12;
  if (std::abs(direction.z()) < kTiny) return std::nullopt;
  const double t = dz / direction.z();
  if (!(t > 0.0) || t > max_range_m) return std::nullopt;
  Eigen::Vector3d point = center + t * direction;
  point.z() = plane_z_m;  // exact on the plane
  return point;
}

std::optional<Eigen::Vector3d> CameraModel::UnprojectToFloor(const Eigen::Vector2d& pixel,
                                                             double max_range_m) const {
  return UnprojectToHeight(pixel, -calibration_.laser_height_m, max_range_m);
}

bool CameraModel::InsideUndistortedBounds(const Eigen::Vector3d& point_camera) const {
  if (!(point_camera.z() >= kMinDepthM)) return false;
  const Eigen::Vector2d n = point_camera.head<2>() / point_camera.z();
  return (n.array() >= undistorted_min_.array()).all() &&
         (n.array() <= undistorted_max_.array()).all();
}

std::optional<ImageRay> CameraModel::ProjectRayToImage(const Eigen::Vector3d& origin_laser,
                                                       const Eigen::Vector3d& direction_laser,
                                                       double length_m) const {
  if (!origin_laser.allFinite() || !direction_laser.allFinite() || !std::isfinite(length_m) ||
      length_m < 0.0 || direction_laser.norm() <= 0.0) {
    return std::nullopt;
  }
  const Eigen::Vector3d direction = direction_laser.normalized();
  const Eigen::Vector3d a = camera_from_laser_ * origin_laser;
  const Eigen::Vector3d b = camera_from_laser_.linear() * direction;
  double lo = 0.0;
  double hi = length_m;
  // In front of the camera: a.z + t b.z >= kMinDepthM.
  if (!ClipLinear(a.z() - kMinDepthM, b.z(), &lo, &hi)) return std::nullopt;
  // Inside the (undistorted) image bounds: x >= xmin z, x <= xmax z, same for y. With z > 0
  // these are linear in t.
  const Eigen::Vector2d& mn = undistorted_min_;
  const Eigen::Vector2d& mx = undistorted_max_;
  for (int axis = 0; axis < 2; ++axis) {
    if (!ClipLinear(a[axis] - mn[axis] * a.z(), b[axis] - mn[axis] * b.z(), &lo, &hi) ||
        !ClipLinear(mx[axis] * a.z() - a[axis], mx[axis] * b.z() - b[axis], &lo, &hi)) {
      return std::nullopt;
    }
  }

  const auto inside = [&](double t) {
    const std::optional<Eigen::Vector2d> pixel = Project(origin_laser + t * direction);
    return pixel.has_value() && IsInImage(*pixel);
  };
  // The pinhole clip is exact up to rounding; with distortion the box is conservative. Either
  // way: find a visible t, then bisect each end that is not visible to the image border.
  double seed = std::numeric_limits<double>::quiet_NaN();
  if (inside(0.5 * (lo + hi))) {
    seed = 0.5 * (lo + hi);
  } else {
    constexpr int kProbes = 64;
    for (int i = 0; i <= kProbes && std::isnan(seed); ++i) {
      const double t = lo + (hi - lo) * i / kProbes;
      if (inside(t)) seed = t;
    }
  }
  if (std::isnan(seed)) return std::nullopt;
  const auto bisect = [&](double in, double out) {
    if (inside(out)) return out;
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (in + out);
      (inside(mid) ? in : out) = mid;
    }
    return in;
  };
  const double visible_lo = bisect(seed, lo);
  const double visible_hi = bisect(seed, hi);
  lo = visible_lo;
  hi = visible_hi;

  ImageRay ray;
  ray.start_t_m = lo;
  ray.end_t_m = hi;
  ray.start_laser = origin_laser + lo * direction;
  ray.end_laser = origin_laser + hi * direction;
  const std::optional<Eigen::Vector2d> start_px = Project(ray.start_laser);
  const std::optional<Eigen::Vector2d> end_px = Project(ray.end_laser);
  if (!start_px.has_value() || !end_px.has_value()) return std::nullopt;
  ray.start_px = *start_px;
  ray.end_px = *end_px;
  return ray;
}

Eigen::Vector2d CameraModel::Distort(const Eigen::Vector2d& undistorted) const {
  const DistortionCoefficients& d = calibration_.distortion;
  const double x = undistorted.x();
  const double y = undistorted.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  return Eigen::Vector2d(x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x),
                         y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y);
}

Eigen::Vector2d CameraModel::Undistort(const Eigen::Vector2d& distorted) const {
  const DistortionCoefficients& d = calibration_.distortion;
  if (d.IsZero() || !distorted.allFinite()) return distorted;
  // Fixed-point iterations (as OpenCV) for a robust start, then Newton for precision.
  Eigen::Vector2d p = distorted;
  for (int i = 0; i < 5; ++i) {
    const double r2 = p.squaredNorm();
    const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
    const Eigen::Vector2d tangential(
        2.0 * d.p1 * p.x() * p.y() + d.p2 * (r2 + 2.0 * p.x() * p.x()),
        d.p1 * (r2 + 2.0 * p.y() * p.y()) + 2.0 * d.p2 * p.x() * p.y());
    const Eigen::Vector2d next = (distorted - tangential) / radial;
    if (!next.allFinite()) break;
    p = next;
  }
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector2d residual = Distort(p) - distorted;
    if (residual.norm() < 1e-15) break;
    const double x = p.x();
    const double y = p.y();
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
    const double dradial = d.k1 + r2 * (2.0 * d.k2 + 3.0 * d.k3 * r2);
    Eigen::Matrix2d jacobian;
    jacobian << radial + 2.0 * x * x * dradial + 2.0 * d.p1 * y + 6.0 * d.p2 * x,
        2.0 * x * y * dradial + 2.0 * d.p1 * x + 2.0 * d.p2 * y,
        2.0 * x * y * dradial + 2.0 * d.p1 * x + 2.0 * d.p2 * y,
        radial + 2.0 * y * y * dradial + 6.0 * d.p1 * y + 2.0 * d.p2 * x;
    const double det = jacobian.determinant();
    if (!(std::abs(det) > 1e-12)) break;
    const Eigen::Vector2d next = p - jacobian.inverse() * residual;
    if (!next.allFinite()) break;
    p = next;
  }
  return p;
}

ImageRegion CameraModel::FullImage() const {
  return ImageRegion{-0.5, -0.5, static_cast<double>(calibration_.image_width_px),
                     static_cast<double>(calibration_.image_height_px)};
}

GlMatrices CameraModel::OpenGlMatrices(double near_m, double far_m) const {
  return OpenGlMatrices(near_m, far_m, FullImage());
}

GlMatrices CameraModel::OpenGlMatrices(double near_m, double far_m,
                                       const ImageRegion& region) const {
  MOSTAR_CHECK(near_m > 0.0 && far_m > near_m);
  MOSTAR_CHECK(region.width_px > 0.0 && region.height_px > 0.0);
  const double w = region.width_px;
  const double h = region.height_px;
  Eigen::Matrix4d projection = Eigen::Matrix4d::Zero();
  projection(0, 0) = 2.0 * calibration_.fx() / w;
  projection(0, 2) = 1.0 - 2.0 * (calibration_.cx() - region.left_px) / w;
  projection(1, 1) = 2.0 * calibration_.fy() / h;
  projection(1, 2) = 2.0 * (calibration_.cy() - region.top_px) / h - 1.0;
  projection(2, 2) = -(far_m + near_m) / (far_m - near_m);
  projection(2, 3) = -2.0 * far_m * near_m / (far_m - near_m);
  projection(3, 2) = -1.0;
  // OpenGL eye frame from the OpenCV camera frame: flip y and z.
  const Eigen::Matrix4d gl_from_camera = Eigen::Vector4d(1.0, -1.0, -1.0, 1.0).asDiagonal();
  GlMatrices matrices;
  matrices.projection = projection.cast<float>();
  matrices.view = (gl_from_camera * camera_from_laser_.matrix()).cast<float>();
  return matrices;
}

Eigen::Vector2d NdcToPixel(const Eigen::Vector2d& ndc, const ImageRegion& region) {
  return Eigen::Vector2d(region.left_px + 0.5 * (ndc.x() + 1.0) * region.width_px,
                         region.top_px + 0.5 * (1.0 - ndc.y()) * region.height_px);
}

}  // namespace mostar::math
