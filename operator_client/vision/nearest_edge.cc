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

RayPixels TraceRayPixels(const math::CameraModel& camera, double azimuth_rad,
                         const NearestEdgeOptions& options) {
  RayPixels ray;
  ray.azimuth_rad = azimuth_rad;
  const double laser_height_m = camera.calibration().laser_height_m;
  const Eigen::Vector3d base_laser(0.0, 0.0, -laser_height_m);
  const Eigen::Vector3d direction_laser(std::cos(azimuth_rad), std::sin(azimuth_rad), 0.0);
  const std::optional<math::ImageRay> visible =
      camera.ProjectRayToImage(base_laser, direction_laser, options.max_range_m);
  if (!visible) return ray;
  ray.visible = true;

  const int width = camera.width_px();
  const int height = camera.height_px();
  const auto to_index = [](double coordinate, int size) {
    return std::clamp(static_cast<int>(std::lround(coordinate)), 0, size - 1);
  };
  const RaySampler sampler(camera, base_laser, direction_laser);
  const double t_end = visible->end_t_m;
  constexpr double kMinStepM = 1e-5;
  double t = visible->start_t_m;
  int last_col = -1;
  int last_row = -1;
  double last_t = t;
  while (true) {
    double u = 0, v = 0, speed = 0, du = 0, dv = 0;
    sampler.Sample(t, &u, &v, &speed, &du, &dv);
    const int col = to_index(u, width);
    const int row = to_index(v, height);
    if (col != last_col || row != last_row) {
      // Close the previous pixel's crossing.
      if (!ray.pixels.empty()) {
        RayPixels::Pixel& previous = ray.pixels.back();
        previous.centre_t_m = static_cast<float>(0.5 * (previous.enter_t_m + last_t));
      }
      {  // Rows in the bottom margin are kept for the diagonal checks; is_edge skips them.
        RayPixels::Pixel pixel;
        pixel.col = static_cast<int16_t>(col);
        pixel.row = static_cast<int16_t>(row);
        pixel.previous_col = static_cast<int16_t>(last_col);
        pixel.previous_row = static_cast<int16_t>(last_row);
        pixel.walking_vertically = std::abs(dv) >= std::abs(du);
        pixel.enter_t_m = static_cast<float>(t);
        pixel.centre_t_m = static_cast<float>(t);
        pixel.metres_per_px = static_cast<float>(1.0 / std::max(speed, 1e-9));
        ray.pixels.push_back(pixel);
      }
      last_col = col;
      last_row = row;
    }
    last_t = t;
    if (t >= t_end) break;
    t = std::min(t + std::max(kMinStepM, options.step_px / std::max(speed, 1e-9)), t_end);
  }
  if (!ray.pixels.empty()) {
    RayPixels::Pixel& previous = ray.pixels.back();
    previous.centre_t_m = static_cast<float>(0.5 * (previous.enter_t_m + last_t));
  }
  return ray;
}

Nep FindNearestEdgeOnPixels(const cv::Mat& edges, const RayPixels& ray,
                            const NearestEdgeOptions& options, double laser_height_m) {
  assert(edges.type() == CV_8UC1);
  Nep nep;
  const int width = edges.cols;
  const int max_row = edges.rows - 1 - options.bottom_margin_px;
  const auto is_edge = [&](int col, int row) {
    return col >= 0 && col < width && row >= 0 && row <= max_row &&
           edges.ptr<uint8_t>(row)[col] != 0;
  };
  for (const RayPixels::Pixel& p : ray.pixels) {
    double hit_t = -1.0;
    int hit_col = p.col;
    int hit_row = p.row;
    if (is_edge(p.col, p.row)) {
      hit_t = p.centre_t_m;
    } else if (p.previous_col >= 0 && p.col != p.previous_col && p.row != p.previous_row &&
               (is_edge(p.col, p.previous_row) || is_edge(p.previous_col, p.row))) {
      // A diagonal step: an 8-connected edge may pass between the two pixels.
      hit_t = p.enter_t_m;
      if (is_edge(p.col, p.previous_row)) {
        hit_row = p.previous_row;
      } else {
        hit_col = p.previous_col;
      }
    } else if (options.lateral_tolerance_px > 0) {
      for (int k = 1; k <= options.lateral_tolerance_px && hit_t < 0.0; ++k) {
        for (const int sign : {-1, 1}) {
          const int c = p.walking_vertically ? p.col + sign * k : p.col;
          const int r = p.walking_vertically ? p.row : p.row + sign * k;
          if (is_edge(c, r)) {
            hit_t = p.centre_t_m;
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
      nep.floor_point_laser = FloorPointLaser(ray.azimuth_rad, hit_t, laser_height_m);
      nep.pixel = Eigen::Vector2d(hit_col, hit_row);
      nep.metres_per_px = p.metres_per_px;
      return nep;
    }
  }
  return nep;
}

Nep FindNearestEdgeOnRay(const cv::Mat& edges, const math::CameraModel& camera, double azimuth_rad,
                         const NearestEdgeOptions& options, bool* ray_visible) {
  assert(edges.type() == CV_8UC1 && edges.cols == camera.width_px() &&
         edges.rows == camera.height_px());
  const RayPixels ray = TraceRayPixels(camera, azimuth_rad, options);
  if (ray_visible != nullptr) *ray_visible = ray.visible;
  return FindNearestEdgeOnPixels(edges, ray, options, camera.calibration().laser_height_m);
}

namespace {

// Checks what FindNearestEdges and NearestEdgeFinder::Find need; sets `why` when not met.
bool CheckNedInput(const cv::Mat& edges, const math::CameraModel& camera, const LaserScan& scan,
                   const NearestEdgeOptions& options, std::string* error) {
  if (!options.IsValid(error)) return false;
  std::ostringstream why;
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
    return true;
  }
  if (error != nullptr) *error = why.str();
  return false;
}

}  // namespace

bool NearestEdgeFinder::Find(const cv::Mat& edges,
                             const std::shared_ptr<const math::CameraModel>& camera,
                             const LaserScan& scan, NedResult* out, std::string* error) {
  assert(out != nullptr);
  out->neps.assign(scan.ranges_m.size(), Nep{});
  out->visible_rays = 0;
  out->found = 0;
  if (camera == nullptr) {
    if (error != nullptr) *error = "missing camera model";
    return false;
  }
  if (!CheckNedInput(edges, *camera, scan, options_, error)) return false;
  if (camera != camera_ || scan.angle_min_rad != angle_min_rad_ ||
      scan.angle_increment_rad != angle_increment_rad_ || rays_.size() != scan.ranges_m.size()) {
    camera_ = camera;
    angle_min_rad_ = scan.angle_min_rad;
    angle_increment_rad_ = scan.angle_increment_rad;
    rays_.clear();
    rays_.reserve(scan.ranges_m.size());
    for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
      rays_.push_back(TraceRayPixels(*camera, scan.AngleOf(i), options_));
    }
  }
  const double laser_height_m = camera->calibration().laser_height_m;
  for (size_t i = 0; i < rays_.size(); ++i) {
    out->neps[i] = FindNearestEdgeOnPixels(edges, rays_[i], options_, laser_height_m);
    out->visible_rays += rays_[i].visible ? 1 : 0;
    out->found += out->neps[i].found ? 1 : 0;
  }
  return true;
}

bool FindNearestEdges(const cv::Mat& edges, const math::CameraModel& camera, const LaserScan& scan,
                      const NearestEdgeOptions& options, NedResult* out, std::string* error) {
  assert(out != nullptr);
  out->neps.assign(scan.ranges_m.size(), Nep{});
  out->visible_rays = 0;
  out->found = 0;
  if (!CheckNedInput(edges, camera, scan, options, error)) return false;
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    bool visible = false;
    out->neps[i] = FindNearestEdgeOnRay(edges, camera, scan.AngleOf(i), options, &visible);
    out->visible_rays += visible ? 1 : 0;
    out->found += out->neps[i].found ? 1 : 0;
  }
  return true;
}

}  // namespace mostar::vision
