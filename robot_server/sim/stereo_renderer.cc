#include "robot_server/sim/stereo_renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <random>
#include <thread>

namespace mostar::sim {
namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();

// One obstacle crossed by an azimuth bin.
struct BinHit {
  FootprintHit fp;
  const Obstacle* obstacle;
};

uint8_t ClampByte(float v) { return static_cast<uint8_t>(std::clamp(v, 0.f, 255.f) + 0.5f); }

}  // namespace

CameraParams CameraParams::FromProto(const proto::CameraConfig& c) {
  CameraParams p;
  auto& k = p.calibration;
  k.width_px = c.width_px();
  k.height_px = c.height_px();
  k.focal_px = c.focal_px();
  k.cx_px = c.cx_px() >= 0 ? c.cx_px() : (c.width_px() - 1) / 2.0;
  k.cy_px = c.cy_px() >= 0 ? c.cy_px() : (c.height_px() - 1) / 2.0;
  k.right_cy_px = k.cy_px + c.right_vertical_offset_px();
  k.k1 = c.k1();
  k.k2 = c.k2();
  k.camera_x_m = c.x_m();
  k.camera_y_m = c.y_m();
  k.camera_z_m = c.z_m();
  k.tilt_rad = c.tilt_rad();
  k.baseline_m = c.baseline_m();
  p.left_gain = c.left_gain();
  p.right_gain = c.right_gain();
  p.noise_sigma = c.noise_sigma();
  p.blur_sigma_px = c.blur_sigma_px();
  p.vignetting = c.vignetting();
  p.contact_shadows = c.contact_shadows();
  p.seed = c.seed();
  p.artifact = c.artifact();
  return p;
}

StereoRenderer::StereoRenderer(const World& world, const CameraParams& params,
                               double laser_height_m)
    : world_(world), params_(params), laser_height_m_(laser_height_m) {
  BuildTables(Eye::kLeft, &eyes_[0]);
  BuildTables(Eye::kRight, &eyes_[1]);
  // Noise field 1.5 times the image size, so a random window of it differs per frame.
  const auto& k = params_.calibration;
  noise_.create(k.height_px * 3 / 2, k.width_px * 3 / 2, CV_16SC3);
  cv::RNG rng(params_.seed);
  rng.fill(noise_, cv::RNG::NORMAL, cv::Scalar::all(0), cv::Scalar::all(params_.noise_sigma));
}

void StereoRenderer::BuildTables(Eye eye, EyeTables* t) const {
  const auto& k = params_.calibration;
  const int w = k.width_px, h = k.height_px;
  const size_t n = static_cast<size_t>(w) * h;
  t->cam_x_m = k.camera_x_m;
  t->cam_y_m = k.EyeYm(eye);
  t->cam_z_m = laser_height_m_ + k.camera_z_m;
  t->tan_el.resize(n);
  t->h_floor_m.resize(n);
  t->floor_x_m.resize(n);
  t->floor_y_m.resize(n);
  t->vignette.resize(n);
  std::vector<double> azimuth(n);
  const double ct = std::cos(k.tilt_rad), st = std::sin(k.tilt_rad);
  const double cy = k.Cy(eye);
  double az_min = 1e9, az_max = -1e9;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      // Undistort the pixel centre: solve x_d = x (1 + k1 r^2 + k2 r^4) by fixed point.
      const double xd = (u - k.cx_px) / k.focal_px, yd = (v - cy) / k.focal_px;
      double xn = xd, yn = yd;
      for (int it = 0; it < 20 && (k.k1 != 0 || k.k2 != 0); ++it) {
        const double r2 = xn * xn + yn * yn;
        const double d = 1 + k.k1 * r2 + k.k2 * r2 * r2;
        xn = xd / d;
        yn = yd / d;
      }
      // Ray (xn, yn, 1) in the camera frame, expressed in the base frame.
      const double bx = ct - yn * st, by = -xn, bz = -st - yn * ct;
      const double horiz = std::hypot(bx, by);
      const size_t i = static_cast<size_t>(v) * w + u;
      azimuth[i] = std::atan2(by, bx);
      az_min = std::min(az_min, azimuth[i]);
      az_max = std::max(az_max, azimuth[i]);
      const double tan_el = bz / horiz;
      t->tan_el[i] = static_cast<float>(tan_el);
      if (tan_el < 0) {
        const double hf = t->cam_z_m / -tan_el;
        t->h_floor_m[i] = static_cast<float>(hf);
        t->floor_x_m[i] = static_cast<float>(t->cam_x_m + hf * bx / horiz);
        t->floor_y_m[i] = static_cast<float>(t->cam_y_m + hf * by / horiz);
      } else {
        t->h_floor_m[i] = kInfF;
        t->floor_x_m[i] = t->floor_y_m[i] = 0.f;
      }
      // cos^4 fall-off, softened.
      const double cos2 = 1.0 / (1.0 + xn * xn + yn * yn);
      t->vignette[i] = params_.vignetting ? static_cast<float>(0.55 + 0.45 * cos2 * cos2) : 1.f;
    }
  }
  t->bin_width_rad = 0.25 / k.focal_px;
  t->az_min_rad = az_min;
  t->bin_count = static_cast<int>((az_max - az_min) / t->bin_width_rad) + 1;
  t->bin.resize(n);
  for (size_t i = 0; i < n; ++i) {
    t->bin[i] =
        std::min(t->bin_count - 1, static_cast<int>((azimuth[i] - az_min) / t->bin_width_rad));
  }
}

cv::Mat StereoRenderer::RenderEye(Eye eye, const Pose2D& pose, uint64_t frame_index,
                                  ImageGroundTruth* truth) const {
  const EyeTables& t = eyes_[eye == Eye::kLeft ? 0 : 1];
  const auto& k = params_.calibration;
  const int w = k.width_px, h = k.height_px;
  const double c = std::cos(pose.theta_rad), s = std::sin(pose.theta_rad);
  const double ox = pose.x_m + c * t.cam_x_m - s * t.cam_y_m;
  const double oy = pose.y_m + s * t.cam_x_m + c * t.cam_y_m;
  const double oz = t.cam_z_m;

  // Obstacles crossed by each azimuth bin (centre ray), flattened.
  std::vector<BinHit> hits;
  std::vector<int32_t> first(t.bin_count + 1);
  std::vector<double> bin_dx(t.bin_count), bin_dy(t.bin_count);
  FootprintHit fp;
  for (int b = 0; b < t.bin_count; ++b) {
    first[b] = static_cast<int32_t>(hits.size());
    const double az = pose.theta_rad + t.az_min_rad + (b + 0.5) * t.bin_width_rad;
    bin_dx[b] = std::cos(az);
    bin_dy[b] = std::sin(az);
    for (const auto& ob : world_.obstacles()) {
      if (IntersectFootprint(ob, ox, oy, bin_dx[b], bin_dy[b], &fp)) hits.push_back({fp, &ob});
    }
  }
  first[t.bin_count] = static_cast<int32_t>(hits.size());

  cv::Mat image(h, w, CV_8UC3);
  if (truth) truth->labels.create(h, w, CV_8U);
  const double gain = eye == Eye::kLeft ? params_.left_gain : params_.right_gain;
  for (int v = 0; v < h; ++v) {
    auto* row = image.ptr<uint8_t>(v);
    uint8_t* label_row = truth ? truth->labels.ptr<uint8_t>(v) : nullptr;
    for (int u = 0; u < w; ++u) {
      const size_t i = static_cast<size_t>(v) * w + u;
      const double tan_el = t.tan_el[i];
      const int b = t.bin[i];
      RayHit hit;
      double best_h = t.h_floor_m[i];
      if (tan_el > 0 && world_.ceiling_height_m() > oz) {
        best_h = (world_.ceiling_height_m() - oz) / tan_el;
        hit.kind = RayHit::kCeiling;
      } else if (tan_el < 0) {
        hit.kind = RayHit::kFloor;
      }
      const BinHit* best = nullptr;
      Face best_face = Face::kSide;
      for (int j = first[b]; j < first[b + 1]; ++j) {
        const BinHit& bh = hits[j];
        if (bh.fp.h_in_m >= best_h) continue;
        double hh;
        Face face;
        if (ResolveVertical(*bh.obstacle, bh.fp, oz, tan_el, &hh, &face) && hh < best_h) {
          best_h = hh;
          best = &bh;
          best_face = face;
        }
      }
      uint8_t label;
      if (best) {
        hit.kind = RayHit::kObstacle;
        hit.obstacle = best->obstacle;
        hit.face = best_face;
        hit.x_m = ox + best_h * bin_dx[b];
        hit.y_m = oy + best_h * bin_dy[b];
        hit.z_m = oz + best_h * tan_el;
        if (best_face == Face::kSide) {
          hit.nx = best->fp.nx;
          hit.ny = best->fp.ny;
          hit.u_m = best->fp.u_m;
        } else {
          hit.nz = best_face == Face::kTop ? 1 : -1;
        }
        label = static_cast<uint8_t>(std::min(best->obstacle->id, 253));
      } else if (hit.kind == RayHit::kFloor) {
        hit.x_m = pose.x_m + c * t.floor_x_m[i] - s * t.floor_y_m[i];
        hit.y_m = pose.y_m + s * t.floor_x_m[i] + c * t.floor_y_m[i];
        if (!world_.OnFloor(hit.x_m, hit.y_m)) hit.kind = RayHit::kNothing;
        hit.nz = 1;
        label = hit.kind == RayHit::kFloor ? kLabelFloor : kLabelVoid;
      } else {
        label = hit.kind == RayHit::kCeiling ? kLabelCeiling : kLabelVoid;
      }
      if (label_row) label_row[u] = label;
      const Rgb colour = world_.Shade(hit, params_.contact_shadows);
      // Light fades away from the robot (lamps spread along the ceiling).
      const double dist = hit.kind == RayHit::kNothing ? 0.0 : best_h;
      const auto k_px = static_cast<float>(gain * t.vignette[i] / (1.0 + 0.035 * dist));
      row[3 * u + 0] = ClampByte(colour.b * k_px);
      row[3 * u + 1] = ClampByte(colour.g * k_px);
      row[3 * u + 2] = ClampByte(colour.r * k_px);
    }
  }

  if (params_.blur_sigma_px > 0) {
    cv::GaussianBlur(image, image, cv::Size(0, 0), params_.blur_sigma_px);
  }
  // Deterministic per frame and eye.
  std::mt19937_64 rng(params_.seed * 0x9E3779B97F4A7C15ull + frame_index * 2 +
                      (eye == Eye::kLeft ? 0 : 1));
  if (params_.noise_sigma > 0) {
    // A window of the precomputed noise field at a random offset, added with saturation.
    const int dx = static_cast<int>(rng() % static_cast<uint64_t>(noise_.cols - w + 1));
    const int dy = static_cast<int>(rng() % static_cast<uint64_t>(noise_.rows - h + 1));
    cv::add(image, noise_(cv::Rect(dx, dy, w, h)), image, cv::noArray(), CV_8U);
  }
  const auto& a = params_.artifact;
  const bool artifact_eye = (a.eye() == proto::ArtifactConfig::LEFT) == (eye == Eye::kLeft);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  if (truth) truth->artifact_present = false;
  if (a.kind() != proto::ArtifactConfig::NONE && artifact_eye && uniform(rng) < a.probability()) {
    const int size = a.size_px();
    const int x = static_cast<int>(uniform(rng) * w), y = static_cast<int>(uniform(rng) * h);
    cv::Mat mask(h, w, CV_8U, cv::Scalar(0));
    if (a.kind() == proto::ArtifactConfig::DARK_STRIPE) {
      cv::rectangle(mask, cv::Rect(x - size / 2, 0, size, h), cv::Scalar(255), cv::FILLED);
    } else {
      cv::circle(mask, cv::Point(x, y), size, cv::Scalar(255), cv::FILLED);
    }
    const bool bright = a.kind() == proto::ArtifactConfig::BRIGHT_BLOB;
    const cv::Mat target(h, w, CV_8UC3, bright ? cv::Scalar(255, 255, 255) : cv::Scalar(0, 0, 0));
    cv::Mat blended;
    cv::addWeighted(image, 1.0 - a.strength(), target, a.strength(), 0.0, blended);
    blended.copyTo(image, mask);
    if (truth) {
      truth->artifact_present = true;
      truth->artifact_box = cv::boundingRect(mask);
    }
  }
  if (truth) ComputeBaseRows(truth);
  return image;
}

void StereoRenderer::Render(const Pose2D& pose, uint64_t frame_index, bool with_truth,
                            StereoImages* out) const {
  std::thread right([&] {
    out->right =
        RenderEye(Eye::kRight, pose, frame_index, with_truth ? &out->right_truth : nullptr);
  });
  out->left = RenderEye(Eye::kLeft, pose, frame_index, with_truth ? &out->left_truth : nullptr);
  right.join();
}

}  // namespace mostar::sim
