#include "operator_client/vision/nearest_edge.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <sstream>

namespace mostar::vision {
namespace {

// The virtual ray in the camera frame with the camera's intrinsics, for fast sampling. The
// projection repeats math::CameraModel::ProjectCameraPoint (checked by nearest_edge_test) without
// its range checks, which ProjectRayToImage already guarantees for the visible interval.
class RaySampler {
 public:
  RaySampler(const math::CameraModel& camera, const Eigen::Vector3d& origin_laser,
             const Eigen::Vector3d& direction_laser)
      : calibration_(camera.calibration()),
        origin_(camera.camera_from_laser() * origin_laser),
        direction_(camera.camera_from_laser().linear() * direction_laser) {}

  // Pixel at distance t (metres) along the ray, and the pixel speed |d pixel / dt| (px/m).
  void Sample(double t, double* u, double* v, double* speed_px_per_m, double* du_dt,
              double* dv_dt) const {
    const Eigen::Vector3d p = origin_ + t * direction_;
    const double inv_z = 1.0 / p.z();
    const double x = p.x() * inv_z;
    const double y = p.y() * inv_z;
    const double dx = (direction_.x() - x * direction_.z()) * inv_z;
    const double dy = (direction_.y() - y * direction_.z()) * inv_z;
    const math::DistortionCoefficients& d = calibration_.distortion;
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
    const double xd = x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x);
    const double yd = y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y;
    *u = calibration_.fx() * xd + calibration_.cx();
    *v = calibration_.fy() * yd + calibration_.cy();
    // Growth of the distorted radius with the undistorted one: d(r * radial) / dr.
    const double gain =
        std::max(0.25, std::abs(radial + 2.0 * r2 * (d.k1 + r2 * (2.0 * d.k2 + 3.0 * d.k3 * r2))));
    *du_dt = calibration_.fx() * dx * gain;
    *dv_dt = calibration_.fy() * dy * gain;
    *speed_px_per_m = std::hypot(*du_dt, *dv_dt);
  }

 private:
  const math::LaserCameraCalibration& calibration_;
  Eigen::Vector3d origin_;
  Eigen::Vector3d direction_;
};

}  // namespace

bool NearestEdgeOptions::IsValid(std::string* error) const {
  std::ostringstream why;
  if (!std::isfinite(max_range_m) || max_range_m <= 0.0) {
    why << "max_range_m must be finite and > 0 (got " << max_range_m << ")";
  } else if (!(step_px > 0.0 && step_px <= 1.0)) {
    why << "step_px must be in (0, 1] (got " << step_px << ")";
  } else if (lateral_tolerance_px < 0 || lateral_tolerance_px > 10) {
    why << "lateral_tolerance_px must be in [0, 10] (got " << lateral_tolerance_px << ")";
  } else if (bottom_margin_px < 0) {
    why << "bottom_margin_px must be >= 0 (got " << bottom_margin_px << ")";
  } else {
    return true;
  }
  if (error != nullptr) *error = why.str();
  return false;
}

Eigen::Vector3d FloorPointLaser(double azimuth_rad, double distance_m, double laser_height_m) {
  return Eigen::Vector3d(distance_m * std::cos(azimuth_rad), distance_m * std::sin(azimuth_rad),
                         -laser_height_m);
}

Nep FindNearestEdgeOnRay(const cv::Mat& edges, const math::CameraModel& camera, double azimuth_rad,
                         const NearestEdgeOptions& options, bool* ray_visible) {
  assert(edges.type() == CV_8UC1 && edges.cols == camera.width_px() &&
         edges.rows == camera.height_px());
  if (ray_visible != nullptr) *ray_visible = false;
  Nep nep;
  const double laser_height_m = camera.calibration().laser_height_m;
  const Eigen::Vector3d base_laser(0.0, 0.0, -laser_height_m);
  const Eigen::Vector3d direction_laser(std::cos(azimuth_rad), std::sin(azimuth_rad), 0.0);
  const std::optional<math::ImageRay> visible =
      camera.ProjectRayToImage(base_laser, direction_laser, options.max_range_m);
  if (!visible) return nep;
  if (ray_visible != nullptr) *ray_visible = true;

  const int width = edges.cols;
  const int max_row = edges.rows - 1 - options.bottom_margin_px;
  if (max_row < 0) return nep;
  const auto is_edge = [&](int col, int row) {
    return col >= 0 && col < width && row >= 0 && row <= max_row &&
           edges.ptr<uint8_t>(row)[col] != 0;
  };
  const auto to_index = [](double coordinate, int size) {
    return std::clamp(static_cast<int>(std::lround(coordinate)), 0, size - 1);
  };

  const RaySampler sampler(camera, base_laser, direction_laser);
  const double t_end = visible->end_t_m;
  double t = visible->start_t_m;
  int last_col = -1;
  int last_row = -1;
  constexpr double kMinStepM = 1e-5;
  while (true) {
    double u = 0, v = 0, speed = 0, du = 0, dv = 0;
    sampler.Sample(t, &u, &v, &speed, &du, &dv);
    const double step_m = std::max(kMinStepM, options.step_px / std::max(speed, 1e-9));
    const int col = to_index(u, width);
    const int row = to_index(v, edges.rows);
    if (col != last_col || row != last_row) {
      double hit_t = -1.0;
      int hit_col = col;
      int hit_row = row;
      if (is_edge(col, row)) {
        // Centre of the crossing of this pixel: walk on to where the ray leaves it.
        double exit_t = t;
        for (double s = t + step_m; s <= t_end; s += step_m) {
          double su = 0, sv = 0, sspeed = 0, sdu = 0, sdv = 0;
          sampler.Sample(s, &su, &sv, &sspeed, &sdu, &sdv);
          if (to_index(su, width) != col || to_index(sv, edges.rows) != row) break;
          exit_t = s;
        }
        hit_t = 0.5 * (t + exit_t);
      } else if (last_col >= 0 && col != last_col && row != last_row &&
                 (is_edge(col, last_row) || is_edge(last_col, row))) {
        // A diagonal step: an 8-connected edge may pass between the two pixels.
        hit_t = t;
        if (is_edge(col, last_row)) {
          hit_row = last_row;
        } else {
          hit_col = last_col;
        }
      } else if (options.lateral_tolerance_px > 0 && row <= max_row) {
        const bool walking_vertically = std::abs(dv) >= std::abs(du);
        for (int k = 1; k <= options.lateral_tolerance_px && hit_t < 0.0; ++k) {
          for (const int sign : {-1, 1}) {
            const int c = walking_vertically ? col + sign * k : col;
            const int r = walking_vertically ? row : row + sign * k;
            if (is_edge(c, r)) {
              hit_t = t;
              hit_col = c;
              hit_row = r;
              break;
            }
          }
        }
      }
      if (hit_t >= 0.0) {
        nep.found = true;
        nep.distance_m = hit_t;
        nep.floor_point_laser = base_laser + hit_t * direction_laser;
        nep.pixel = Eigen::Vector2d(hit_col, hit_row);
        return nep;
      }
      last_col = col;
      last_row = row;
    }
    if (t >= t_end) break;
    t = std::min(t + step_m, t_end);
  }
  return nep;
}

bool FindNearestEdges(const cv::Mat& edges, const math::CameraModel& camera, const LaserScan& scan,
                      const NearestEdgeOptions& options, NedResult* out, std::string* error) {
  assert(out != nullptr);
  out->neps.assign(scan.ranges_m.size(), Nep{});
  out->visible_rays = 0;
  out->found = 0;
  std::ostringstream why;
  if (!options.IsValid(error)) return false;
  if (edges.type() != CV_8UC1 || edges.cols != camera.width_px() ||
      edges.rows != camera.height_px()) {
    why << "edge image must be CV_8UC1 of the camera's size " << camera.width_px() << "x"
        << camera.height_px() << " (got " << edges.cols << "x" << edges.rows << ", type "
        << edges.type() << ")";
  } else if (options.bottom_margin_px >= edges.rows) {
    why << "bottom_margin_px (" << options.bottom_margin_px << ") must be < the image height ("
        << edges.rows << ")";
  } else if (!std::isfinite(scan.angle_min_rad) || !std::isfinite(scan.angle_increment_rad)) {
    why << "scan angles must be finite";
  } else {
    for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
      bool visible = false;
      out->neps[i] = FindNearestEdgeOnRay(edges, camera, scan.AngleOf(i), options, &visible);
      out->visible_rays += visible ? 1 : 0;
      out->found += out->neps[i].found ? 1 : 0;
    }
    return true;
  }
  if (error != nullptr) *error = why.str();
  return false;
}

}  // namespace mostar::vision
