#include "operator_client/vision/nearest_edge.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/check/check.h"
#include "common/stats/percentile.h"

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
  std::string message;
  if (!std::isfinite(max_range_m) || max_range_m <= 0.0) {
    why << "max_range_m must be finite and > 0 (got " << max_range_m << ")";
  } else if (!(step_px > 0.0 && step_px <= 1.0)) {
    why << "step_px must be in (0, 1] (got " << step_px << ")";
  } else if (lateral_tolerance_px < 0 || lateral_tolerance_px > 10) {
    why << "lateral_tolerance_px must be in [0, 10] (got " << lateral_tolerance_px << ")";
  } else if (!(base_search_m >= 0.0 && base_search_m <= 1.0)) {
    why << "base_search_m must be in [0, 1] (got " << base_search_m << ")";
  } else if (!(min_step_grey >= 0 && min_step_grey <= 255) || step_offset_px < 1 ||
             step_offset_px > 20) {
    why << "min_step_grey must be in [0, 255] and step_offset_px in [1, 20] (got " << min_step_grey
        << ", " << step_offset_px << ")";
  } else if (!(min_crossing_angle_deg >= 0.0 && min_crossing_angle_deg <= 85.0)) {
    why << "min_crossing_angle_deg must be in [0, 85] (got " << min_crossing_angle_deg << ")";
  } else if (start_grey_deviation < 0 || start_grey_deviation > 255) {
    why << "start_grey_deviation must be in [0, 255] (got " << start_grey_deviation << ")";
  } else if (bottom_margin_px < 0) {
    why << "bottom_margin_px must be >= 0 (got " << bottom_margin_px << ")";
  } else if (!floor_stereo.IsValid(&message)) {
    why << message;
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
        const double norm = std::hypot(du, dv);
        if (norm > 0.0) {
          pixel.direction_u = static_cast<float>(du / norm);
          pixel.direction_v = static_cast<float>(dv / norm);
        }
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

namespace {

// L1 Sobel gradient magnitude of `grey` (CV_8UC1) at (col, row), borders replicated: the same
// measure Canny thresholds (without its aperture options).
int SobelL1(const cv::Mat& grey, int col, int row) {
  const int c0 = std::max(col - 1, 0), c2 = std::min(col + 1, grey.cols - 1);
  const uint8_t* up = grey.ptr<uint8_t>(std::max(row - 1, 0));
  const uint8_t* mid = grey.ptr<uint8_t>(row);
  const uint8_t* down = grey.ptr<uint8_t>(std::min(row + 1, grey.rows - 1));
  const int gx = (up[c2] + 2 * mid[c2] + down[c2]) - (up[c0] + 2 * mid[c0] + down[c0]);
  const int gy = (down[c0] + 2 * down[col] + down[c2]) - (up[c0] + 2 * up[col] + up[c2]);
  return std::abs(gx) + std::abs(gy);
}

// Sobel gradient of `grey` summed over the 3x3 neighbourhood of (col, row) (a smoothed 5x5
// derivative, steadier in direction under sensor noise), borders replicated.
Eigen::Vector2d SmoothedGradient(const cv::Mat& grey, int col, int row) {
  const auto at = [&](int c, int r) {
    return static_cast<int>(
        grey.ptr<uint8_t>(std::clamp(r, 0, grey.rows - 1))[std::clamp(c, 0, grey.cols - 1)]);
  };
  // The 3x3 sum of 3x3 Sobel kernels is the outer product of [1 3 4 3 1] (smoothing) and
  // [-1 -1 0 1 1] (derivative).
  static constexpr int kSmooth[5] = {1, 3, 4, 3, 1};
  static constexpr int kDerive[5] = {-1, -1, 0, 1, 1};
  int gx = 0, gy = 0;
  for (int j = 0; j < 5; ++j) {
    for (int i = 0; i < 5; ++i) {
      const int value = at(col + i - 2, row + j - 2);
      gx += kSmooth[j] * kDerive[i] * value;
      gy += kDerive[j] * kSmooth[i] * value;
    }
  }
  return Eigen::Vector2d(gx, gy);
}

}  // namespace

bool EdgeCrossesRay(const cv::Mat& grey, int col, int row, const Eigen::Vector2d& ray_direction,
                    double min_crossing_angle_deg) {
  if (min_crossing_angle_deg <= 0.0) return true;
  const Eigen::Vector2d gradient = SmoothedGradient(grey, col, row);
  const double magnitude = gradient.norm() * ray_direction.norm();
  if (magnitude <= 0.0) return true;
  // The edge is perpendicular to the gradient: sin(crossing angle) = |cos(gradient, ray)|.
  return std::abs(gradient.dot(ray_direction)) >=
         magnitude * std::sin(min_crossing_angle_deg * M_PI / 180.0);
}

Nep FindNearestEdgeOnPixels(const cv::Mat& edges, const RayPixels& ray,
                            const NearestEdgeOptions& options, double laser_height_m,
                            const cv::Mat& grey, const FloorStereoImages* floor, int* floor_edges) {
  MOSTAR_CHECK(edges.type() == CV_8UC1);
  MOSTAR_CHECK(grey.empty() || (grey.type() == CV_8UC1 && grey.size() == edges.size()));
  const int width = edges.cols;
  const int max_row = edges.rows - 1 - options.bottom_margin_px;
  const auto is_edge = [&](int col, int row) {
    return col >= 0 && col < width && row >= 0 && row <= max_row &&
           edges.ptr<uint8_t>(row)[col] != 0;
  };
  struct Hit {
    double t = -1.0;
    int col = 0;
    int row = 0;
  };
  // The edge pixel the walk meets at ray pixel `p`, if any.
  const auto hit_at = [&](const RayPixels::Pixel& p, Hit* hit) {
    hit->col = p.col;
    hit->row = p.row;
    if (is_edge(p.col, p.row)) {
      hit->t = p.centre_t_m;
      return true;
    }
    if (p.previous_col >= 0 && p.col != p.previous_col && p.row != p.previous_row &&
        (is_edge(p.col, p.previous_row) || is_edge(p.previous_col, p.row))) {
      // A diagonal step: an 8-connected edge may pass between the two pixels.
      hit->t = p.enter_t_m;
      if (is_edge(p.col, p.previous_row)) {
        hit->row = p.previous_row;
      } else {
        hit->col = p.previous_col;
      }
      return true;
    }
    for (int k = 1; k <= options.lateral_tolerance_px; ++k) {
      for (const int sign : {-1, 1}) {
        const int c = p.walking_vertically ? p.col + sign * k : p.col;
        const int r = p.walking_vertically ? p.row : p.row + sign * k;
        if (is_edge(c, r)) {
          hit->t = p.centre_t_m;
          hit->col = c;
          hit->row = r;
          return true;
        }
      }
    }
    return false;
  };

  Nep nep;
  const std::vector<RayPixels::Pixel>& pixels = ray.pixels;
  // Mean grey of the ray pixels [first, last] (clipped); false when none.
  const auto mean_grey = [&](ptrdiff_t first, ptrdiff_t last, double* mean) {
    first = std::max<ptrdiff_t>(first, 0);
    last = std::min<ptrdiff_t>(last, static_cast<ptrdiff_t>(pixels.size()) - 1);
    if (first > last) return false;
    int sum = 0;
    for (ptrdiff_t k = first; k <= last; ++k) {
      sum +=
          grey.ptr<uint8_t>(pixels[static_cast<size_t>(k)].row)[pixels[static_cast<size_t>(k)].col];
    }
    *mean = static_cast<double>(sum) / static_cast<double>(last - first + 1);
    return true;
  };
  // A thin line on the floor (tile joint, drawing) has floor on both sides; an obstacle base
  // separates the floor from something else. An edge within step_offset_px of the ray's start
  // (the image border) has no floor pixels before it: it cannot be told from a line and fails.
  // One within step_offset_px of the ray's end has nothing visible beyond it and passes.
  const auto is_step = [&](size_t i) {
    if (options.min_step_grey <= 0 || grey.empty()) return true;
    const auto centre = static_cast<ptrdiff_t>(i);
    const ptrdiff_t near = options.step_offset_px, far = 2 * options.step_offset_px;
    double before = 0.0, after = 0.0;
    if (!mean_grey(centre - far, centre - near, &before)) return false;
    if (!mean_grey(centre + near, centre + far, &after)) return true;
    return std::abs(after - before) >= options.min_step_grey;
  };
  const auto crosses = [&](const RayPixels::Pixel& p, const Hit& hit) {
    return grey.empty() ||
           EdgeCrossesRay(grey, hit.col, hit.row, Eigen::Vector2d(p.direction_u, p.direction_v),
                          options.min_crossing_angle_deg);
  };
  // The floor test: the region beyond the edge at ray pixel i, from near_px ray pixels beyond it
  // up to the next edge pixel (at least 3 beyond: an edge curve may be that thick) or far_px,
  // every second ray pixel, and half_width_m of floor across (every second pixel), judged
  // against the other eye.
  const FloorStereoOptions& floor_options = options.floor_stereo;
  const bool floor_test = floor != nullptr && floor_options.enabled;
  const auto on_floor = [&](size_t i, const Hit& edge) {
    if (!floor_test || floor->valid.ptr<uint8_t>(edge.row)[edge.col] == 0) return false;
    const cv::Vec2f edge_shift = floor->shift.ptr<cv::Vec2f>(edge.row)[edge.col];
    FloorEvidence evidence;
    const size_t last = std::min(pixels.size() - 1, i + static_cast<size_t>(floor_options.far_px));
    for (size_t k = i + static_cast<size_t>(floor_options.near_px); k <= last; ++k) {
      const RayPixels::Pixel& p = pixels[k];
      Hit next;
      if (k >= i + 3 && hit_at(p, &next)) break;
      if ((k - i) % 2 != 0) continue;  // every second ray pixel
      // Across the ray's image: (-v, u) of its direction.
      const float across_u = -p.direction_v;
      const float across_v = p.direction_u;
      // The half width: half_width_m of floor across the ray here (at least 4 px, at most
      // half_width_px), the distance to the camera taken as the floor distance.
      const int half_width =
          std::clamp(static_cast<int>(floor_options.half_width_m * floor->focal_px /
                                      std::max(0.3f, p.centre_t_m)),
                     4, floor_options.half_width_px);
      for (int o = -half_width; o <= half_width; o += 2) {
        JudgePixel(*floor, p.col + static_cast<int>(std::lround(o * across_u)),
                   p.row + static_cast<int>(std::lround(o * across_v)), edge_shift, floor_options,
                   &evidence);
      }
    }
    if (Verdict(evidence, floor_options) != FloorVerdict::kFloor) return false;
    if (floor_edges != nullptr) ++*floor_edges;
    return true;
  };
  for (size_t i = 0; i < pixels.size(); ++i) {
    Hit hit;
    if (!hit_at(pixels[i], &hit) || !is_step(i) || on_floor(i, hit)) continue;
    nep.along_ray = !crosses(pixels[i], hit);
    size_t best_index = i;
    if (options.base_search_m > 0.0 && !grey.empty()) {
      // Base refinement: the first edge is often the outer rim of the obstacle's contact shadow
      // or of the optics' blur; the base is the strongest edge just beyond it.
      int best_gradient = SobelL1(grey, hit.col, hit.row);
      const double limit_t = hit.t + options.base_search_m;
      for (size_t j = i + 1; j < pixels.size() && pixels[j].enter_t_m <= limit_t; ++j) {
        Hit next;
        if (!hit_at(pixels[j], &next)) continue;
        const int gradient = SobelL1(grey, next.col, next.row);
        if (gradient > best_gradient) {
          best_gradient = gradient;
          best_index = j;
          hit = next;
        }
      }
    }
    nep.found = true;
    nep.distance_m = hit.t;
    nep.floor_point_laser = FloorPointLaser(ray.azimuth_rad, hit.t, laser_height_m);
    nep.pixel = Eigen::Vector2d(hit.col, hit.row);
    nep.metres_per_px = pixels[best_index].metres_per_px;
    return nep;
  }
  return nep;
}

Nep FindNearestEdgeOnRay(const cv::Mat& edges, const math::CameraModel& camera, double azimuth_rad,
                         const NearestEdgeOptions& options, bool* ray_visible) {
  MOSTAR_CHECK(edges.type() == CV_8UC1 && edges.cols == camera.width_px() &&
               edges.rows == camera.height_px());
  const RayPixels ray = TraceRayPixels(camera, azimuth_rad, options);
  if (ray_visible != nullptr) *ray_visible = ray.visible;
  return FindNearestEdgeOnPixels(edges, ray, options, camera.calibration().laser_height_m);
}

namespace {

// Checks what FindNearestEdges and NearestEdgeFinder::Find need; sets `why` when not met.
bool CheckNedInput(const cv::Mat& edges, const cv::Mat& grey, const math::CameraModel& camera,
                   const LaserScan& scan, const NearestEdgeOptions& options, std::string* error) {
  if (!options.IsValid(error)) return false;
  std::ostringstream why;
  if (edges.type() != CV_8UC1 || edges.cols != camera.width_px() ||
      edges.rows != camera.height_px()) {
    why << "edge image must be CV_8UC1 of the camera's size " << camera.width_px() << "x"
        << camera.height_px() << " (got " << edges.cols << "x" << edges.rows << ", type "
        << edges.type() << ")";
  } else if (!grey.empty() && (grey.type() != CV_8UC1 || grey.size() != edges.size())) {
    why << "grey image must be empty or CV_8UC1 of the edge image's size (got " << grey.cols << "x"
        << grey.rows << ", type " << grey.type() << ")";
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

bool NearestEdgeFinder::Prepare(const std::shared_ptr<const math::CameraModel>& camera,
                                const LaserScan& scan, std::string* error) {
  if (camera == nullptr) {
    if (error != nullptr) *error = "missing camera model";
    return false;
  }
  if (!options_.IsValid(error)) return false;
  if (!std::isfinite(scan.angle_min_rad) || !std::isfinite(scan.angle_increment_rad)) {
    if (error != nullptr) *error = "scan angles must be finite";
    return false;
  }
  if (camera != camera_ || scan.angle_min_rad != angle_min_rad_ ||
      scan.angle_increment_rad != angle_increment_rad_ || rays_.size() != scan.ranges_m.size()) {
    camera_ = camera;
    angle_min_rad_ = scan.angle_min_rad;
    angle_increment_rad_ = scan.angle_increment_rad;
    rays_.clear();
    rays_.reserve(scan.ranges_m.size());
    top_row_ = camera->height_px();
    for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
      rays_.push_back(TraceRayPixels(*camera, scan.AngleOf(i), options_));
      for (const RayPixels::Pixel& p : rays_.back().pixels) {
        top_row_ = std::min(top_row_, static_cast<int>(p.row));
      }
    }
    // Lateral tolerance (walking horizontally), diagonal checks, the step test and the 3x3
    // Sobel of the base refinement read a few rows above.
    top_row_ = std::max(0, top_row_ - options_.lateral_tolerance_px - 2);
  }
  return true;
}

namespace {

// NearestEdgeOptions::start_grey_deviation over one image's NEPs: `rays[i]` is beam i's ray.
void MarkRaysStartingOnObjects(const std::vector<const RayPixels*>& rays, const cv::Mat& grey,
                               const NearestEdgeOptions& options, std::vector<Nep>* neps) {
  if (options.start_grey_deviation <= 0 || grey.empty()) return;
  constexpr size_t kStartPixels = 4;  // the mean grey of the ray's first pixels
  const int bottom_row = grey.rows - 1 - options.bottom_margin_px;
  std::vector<double> start(rays.size(), -1.0);
  std::vector<double> starts;
  for (size_t i = 0; i < rays.size(); ++i) {
    const RayPixels& ray = *rays[i];
    if (!ray.visible) continue;
    // The first pixels above the rows that show the robot (bottom_margin_px), as NED walks.
    size_t first = 0;
    while (first < ray.pixels.size() && ray.pixels[first].row > bottom_row) ++first;
    if (ray.pixels.size() - first < kStartPixels || ray.pixels[first].row < bottom_row - 2) {
      continue;  // too short, or it enters the image elsewhere than at the bottom
    }
    double sum = 0.0;
    for (size_t k = first; k < first + kStartPixels; ++k) {
      sum += grey.at<uint8_t>(ray.pixels[k].row, ray.pixels[k].col);
    }
    start[i] = sum / kStartPixels;
    starts.push_back(start[i]);
  }
  if (starts.size() < static_cast<size_t>(NearestEdgeOptions::kMinStartRays)) return;
  const double floor_grey = Percentile(starts, 0.5).value_or(0.0);
  for (size_t i = 0; i < rays.size(); ++i) {
    Nep& nep = (*neps)[i];
    nep.starts_on_object = nep.found && start[i] >= 0.0 &&
                           std::abs(start[i] - floor_grey) > options.start_grey_deviation;
  }
}

}  // namespace

bool NearestEdgeFinder::Find(const cv::Mat& edges,
                             const std::shared_ptr<const math::CameraModel>& camera,
                             const LaserScan& scan, NedResult* out, std::string* error,
                             const cv::Mat& grey, const FloorStereoImages* floor) {
  MOSTAR_CHECK(out != nullptr);
  out->neps.assign(scan.ranges_m.size(), Nep{});
  out->visible_rays = 0;
  out->found = 0;
  out->floor_edges = 0;
  if (camera == nullptr) {
    if (error != nullptr) *error = "missing camera model";
    return false;
  }
  if (!CheckNedInput(edges, grey, *camera, scan, options_, error)) return false;
  if (!Prepare(camera, scan, error)) return false;
  const double laser_height_m = camera->calibration().laser_height_m;
  for (size_t i = 0; i < rays_.size(); ++i) {
    out->neps[i] = FindNearestEdgeOnPixels(edges, rays_[i], options_, laser_height_m, grey, floor,
                                           &out->floor_edges);
    out->visible_rays += rays_[i].visible ? 1 : 0;
    out->found += out->neps[i].found ? 1 : 0;
  }
  std::vector<const RayPixels*> rays;
  for (const RayPixels& ray : rays_) rays.push_back(&ray);
  MarkRaysStartingOnObjects(rays, grey, options_, &out->neps);
  return true;
}

bool FindNearestEdges(const cv::Mat& edges, const math::CameraModel& camera, const LaserScan& scan,
                      const NearestEdgeOptions& options, NedResult* out, std::string* error,
                      const cv::Mat& grey) {
  MOSTAR_CHECK(out != nullptr);
  out->neps.assign(scan.ranges_m.size(), Nep{});
  out->visible_rays = 0;
  out->found = 0;
  if (!CheckNedInput(edges, grey, camera, scan, options, error)) return false;
  const double laser_height_m = camera.calibration().laser_height_m;
  std::vector<RayPixels> rays;
  rays.reserve(scan.ranges_m.size());
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    rays.push_back(TraceRayPixels(camera, scan.AngleOf(i), options));
    out->neps[i] = FindNearestEdgeOnPixels(edges, rays.back(), options, laser_height_m, grey);
    out->visible_rays += rays.back().visible ? 1 : 0;
    out->found += out->neps[i].found ? 1 : 0;
  }
  std::vector<const RayPixels*> ray_pointers;
  for (const RayPixels& ray : rays) ray_pointers.push_back(&ray);
  MarkRaysStartingOnObjects(ray_pointers, grey, options, &out->neps);
  return true;
}

}  // namespace mostar::vision
