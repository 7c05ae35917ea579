#include "robot_server/sim/stereo_renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <random>

namespace mostar::sim {
namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();
constexpr int kBandRows = 32;  // rows per parallel task

// One obstacle crossed by an azimuth bin, with the colour of its plain side (lit, before the
// fall-off) and the height from which the side is plain (World::ShadePlainSide).
struct BinHit {
  FootprintHit fp;
  const Obstacle* obstacle;
  Rgb plain;
  double plain_from_z_m;
};

// Light fades away from the robot (lamps spread along the ceiling): gain at horizontal distance.
float FallOff(float h_m) { return 1.f / (1.f + 0.035f * h_m); }

}  // namespace

// Per-frame state of one eye: the camera in the world and the obstacles each bin crosses.
struct StereoRenderer::EyeFrame {
  const EyeTables* tables = nullptr;
  Pose2D pose;
  double c = 1, s = 0;    // cos, sin of the heading
  double ox = 0, oy = 0;  // camera centre, world frame
  std::vector<BinHit> hits;
  std::vector<int32_t> first;          // hits of bin b: [first[b], first[b + 1])
  std::vector<double> bin_dx, bin_dy;  // bin centre direction, world frame
};

CameraParams CameraParams::FromProto(const proto::CameraConfig& c) {
  CameraParams p;
  auto& k = p.calibration;
  k.width_px = c.width_px();
  k.height_px = c.height_px();
  k.focal_px = c.focal_px();
  k.cx_px = c.cx_px() >= 0 ? c.cx_px() : (c.width_px() - 1) / 2.0;
  k.cy_px = c.cy_px() >= 0 ? c.cy_px() : (c.height_px() - 1) / 2.0;
  k.right_cy_px = k.cy_px + c.right_vertical_offset_px();
  k.right_roll_rad = c.right_roll_deg() * M_PI / 180.0;
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
  RayHit ceiling;
  ceiling.kind = RayHit::kCeiling;
  ceiling.nz = -1;
  ceiling_colour_ = world_.Shade(ceiling, params_.contact_shadows);
  void_colour_ = world_.Shade(RayHit{}, params_.contact_shadows);
  BuildTables(Eye::kLeft, &eyes_[0]);
  BuildTables(Eye::kRight, &eyes_[1]);
  // Noise field 1.5 times the image size, so a random window of it differs per frame.
  const auto& k = params_.calibration;
  cv::Mat noise(k.height_px * 3 / 2, k.width_px * 3 / 2, CV_16SC3);
  cv::RNG rng(params_.seed);
  rng.fill(noise, cv::RNG::NORMAL, cv::Scalar::all(0), cv::Scalar::all(params_.noise_sigma));
  noise.convertTo(noise_up_, CV_8U);  // saturates the negative part to 0
  cv::Mat negated = -noise;
  negated.convertTo(noise_down_, CV_8U);
}

void StereoRenderer::BuildTables(Eye eye, EyeTables* t) const {
  const auto& k = params_.calibration;
  const int w = k.width_px, h = k.height_px;
  const size_t n = static_cast<size_t>(w) * h;
  t->cam_x_m = k.camera_x_m;
  t->cam_y_m = k.EyeYm(eye);
  t->cam_z_m = laser_height_m_ + k.camera_z_m;
  t->rays.assign(n, PixelRay{});
  std::vector<double> azimuth(n);
  const double ct = std::cos(k.tilt_rad), st = std::sin(k.tilt_rad);
  const double cy = k.Cy(eye);
  const double roll_cos = std::cos(k.Roll(eye)), roll_sin = std::sin(k.Roll(eye));
  const double gain = eye == Eye::kLeft ? params_.left_gain : params_.right_gain;
  const double ceiling_m = world_.ceiling_height_m();
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
      // Ray (xn, yn, 1) in the camera frame, turned into the unrolled camera's frame
      // (p_unrolled = RotZ(roll) p_camera), expressed in the base frame.
      const double xu = roll_cos * xn - roll_sin * yn, yu = roll_sin * xn + roll_cos * yn;
      const double bx = ct - yu * st, by = -xu, bz = -st - yu * ct;
      const double horiz = std::hypot(bx, by);
      const size_t i = static_cast<size_t>(v) * w + u;
      PixelRay& ray = t->rays[i];
      azimuth[i] = std::atan2(by, bx);
      az_min = std::min(az_min, azimuth[i]);
      az_max = std::max(az_max, azimuth[i]);
      const double tan_el = bz / horiz;
      ray.tan_el = static_cast<float>(tan_el);
      // cos^4 fall-off, softened.
      const double cos2 = 1.0 / (1.0 + xn * xn + yn * yn);
      const double vignette = params_.vignetting ? 0.55 + 0.45 * cos2 * cos2 : 1.0;
      ray.gain = static_cast<float>(gain * vignette);
      double h_m = std::numeric_limits<double>::infinity();
      if (tan_el < 0) {
        h_m = t->cam_z_m / -tan_el;
        ray.backdrop = Backdrop::kFloor;
        ray.floor_x_m = static_cast<float>(t->cam_x_m + h_m * bx / horiz);
        ray.floor_y_m = static_cast<float>(t->cam_y_m + h_m * by / horiz);
      } else if (tan_el > 0 && ceiling_m > t->cam_z_m) {
        h_m = (ceiling_m - t->cam_z_m) / tan_el;
        ray.backdrop = Backdrop::kCeiling;
      }
      ray.h_backdrop_m = static_cast<float>(h_m);
      ray.gain_backdrop = ray.backdrop == Backdrop::kNothing
                              ? ray.gain
                              : ray.gain * FallOff(static_cast<float>(h_m));
    }
  }
  t->bin_width_rad = 0.25 / k.focal_px;
  t->az_min_rad = az_min;
  t->bin_count = static_cast<int>((az_max - az_min) / t->bin_width_rad) + 1;
  for (size_t i = 0; i < n; ++i) {
    t->rays[i].bin =
        std::min(t->bin_count - 1, static_cast<int>((azimuth[i] - az_min) / t->bin_width_rad));
  }
}

void StereoRenderer::PrepareEye(Eye eye, const Pose2D& pose, EyeFrame* f) const {
  const EyeTables& t = eyes_[eye == Eye::kLeft ? 0 : 1];
  f->tables = &t;
  f->pose = pose;
  f->c = std::cos(pose.theta_rad);
  f->s = std::sin(pose.theta_rad);
  f->ox = pose.x_m + f->c * t.cam_x_m - f->s * t.cam_y_m;
  f->oy = pose.y_m + f->s * t.cam_x_m + f->c * t.cam_y_m;
  // Obstacles crossed by each azimuth bin (centre ray), flattened.
  f->hits.clear();
  f->first.resize(t.bin_count + 1);
  f->bin_dx.resize(t.bin_count);
  f->bin_dy.resize(t.bin_count);
  FootprintHit fp;
  for (int b = 0; b < t.bin_count; ++b) {
    f->first[b] = static_cast<int32_t>(f->hits.size());
    const double az = pose.theta_rad + t.az_min_rad + (b + 0.5) * t.bin_width_rad;
    f->bin_dx[b] = std::cos(az);
    f->bin_dy[b] = std::sin(az);
    for (const auto& ob : world_.obstacles()) {
      if (IntersectFootprint(ob, f->ox, f->oy, f->bin_dx[b], f->bin_dy[b], &fp)) {
        BinHit hit{fp, &ob, {}, 0};
        hit.plain =
            world_.ShadePlainSide(ob, fp.nx, fp.ny, params_.contact_shadows, &hit.plain_from_z_m);
        f->hits.push_back(hit);
      }
    }
    // Nearest first: a pixel stops at the first crossing beyond what it already hit.
    std::sort(f->hits.begin() + f->first[b], f->hits.end(),
              [](const BinHit& a, const BinHit& c) { return a.fp.h_in_m < c.fp.h_in_m; });
  }
  f->first[t.bin_count] = static_cast<int32_t>(f->hits.size());
}

void StereoRenderer::ShadeRows(const EyeFrame& f, int row_begin, int row_end, cv::Mat* image,
                               cv::Mat* labels) const {
  const EyeTables& t = *f.tables;
  const int w = params_.calibration.width_px;
  const double oz = t.cam_z_m;
  const Pose2D& pose = f.pose;
  const bool contact_shadows = params_.contact_shadows;
  std::vector<float> lit(3 * static_cast<size_t>(w));  // one row, BGR, before rounding
  for (int v = row_begin; v < row_end; ++v) {
    auto* row = image->ptr<uint8_t>(v);
    uint8_t* label_row = labels ? labels->ptr<uint8_t>(v) : nullptr;
    const PixelRay* rays = &t.rays[static_cast<size_t>(v) * w];
    for (int u = 0; u < w; ++u) {
      const PixelRay& ray = rays[u];
      const double tan_el = ray.tan_el;
      const int b = ray.bin;
      double best_h = ray.h_backdrop_m;
      const BinHit* best = nullptr;
      Face best_face = Face::kSide;
      for (int j = f.first[b]; j < f.first[b + 1]; ++j) {
        const BinHit& bh = f.hits[j];
        if (bh.fp.h_in_m >= best_h) break;
        double hh;
        Face face;
        if (ResolveVertical(*bh.obstacle, bh.fp, oz, tan_el, &hh, &face) && hh < best_h) {
          best_h = hh;
          best = &bh;
          best_face = face;
        }
      }
      // Nothing (beyond the floor, or no ceiling) unless one of the cases below applies.
      Rgb colour = void_colour_;
      float k_px = ray.gain;
      uint8_t label = kLabelVoid;
      if (best) {
        const double z_m = oz + best_h * tan_el;
        if (best_face == Face::kSide && z_m >= best->plain_from_z_m) {
          colour = best->plain;
        } else {
          RayHit hit;
          hit.kind = RayHit::kObstacle;
          hit.obstacle = best->obstacle;
          hit.face = best_face;
          hit.x_m = f.ox + best_h * f.bin_dx[b];
          hit.y_m = f.oy + best_h * f.bin_dy[b];
          hit.z_m = z_m;
          if (best_face == Face::kSide) {
            hit.nx = best->fp.nx;
            hit.ny = best->fp.ny;
            hit.u_m = best->fp.u_m;
          } else {
            hit.nz = best_face == Face::kTop ? 1 : -1;
          }
          colour = world_.Shade(hit, contact_shadows);
        }
        k_px = ray.gain * FallOff(static_cast<float>(best_h));
        label = static_cast<uint8_t>(std::min(best->obstacle->id, 253));
      } else if (ray.backdrop == Backdrop::kFloor) {
        const double x_m = pose.x_m + f.c * ray.floor_x_m - f.s * ray.floor_y_m;
        const double y_m = pose.y_m + f.s * ray.floor_x_m + f.c * ray.floor_y_m;
        if (world_.OnFloor(x_m, y_m)) {
          colour = world_.ShadeFloor(x_m, y_m, contact_shadows);
          k_px = ray.gain_backdrop;
          label = kLabelFloor;
        }
      } else if (ray.backdrop == Backdrop::kCeiling) {
        colour = ceiling_colour_;
        k_px = ray.gain_backdrop;
        label = kLabelCeiling;
      }
      if (label_row) label_row[u] = label;
      lit[3 * u + 0] = colour.b * k_px;
      lit[3 * u + 1] = colour.g * k_px;
      lit[3 * u + 2] = colour.r * k_px;
    }
    // Rounded and saturated to bytes (SIMD).
    cv::Mat(1, 3 * w, CV_32F, lit.data()).convertTo(cv::Mat(1, 3 * w, CV_8U, row), CV_8U);
  }
}

void StereoRenderer::FinishEye(Eye eye, uint64_t frame_index, cv::Mat* image,
                               ImageGroundTruth* truth) const {
  const int w = image->cols, h = image->rows;
  if (params_.blur_sigma_px > 0) {
    cv::GaussianBlur(*image, *image, cv::Size(0, 0), params_.blur_sigma_px);
  }
  // Deterministic per frame and eye.
  std::mt19937_64 rng(params_.seed * 0x9E3779B97F4A7C15ull + frame_index * 2 +
                      (eye == Eye::kLeft ? 0 : 1));
  if (params_.noise_sigma > 0) {
    // A window of the precomputed noise field at a random offset, added with saturation.
    const int dx = static_cast<int>(rng() % static_cast<uint64_t>(noise_up_.cols - w + 1));
    const int dy = static_cast<int>(rng() % static_cast<uint64_t>(noise_up_.rows - h + 1));
    const cv::Rect window(dx, dy, w, h);
    cv::add(*image, noise_up_(window), *image);
    cv::subtract(*image, noise_down_(window), *image);
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
    cv::addWeighted(*image, 1.0 - a.strength(), target, a.strength(), 0.0, blended);
    blended.copyTo(*image, mask);
    if (truth) {
      truth->artifact_present = true;
      truth->artifact_box = cv::boundingRect(mask);
    }
  }
  if (truth) ComputeBaseRows(truth);
}

cv::Mat StereoRenderer::RenderEye(Eye eye, const Pose2D& pose, uint64_t frame_index,
                                  ImageGroundTruth* truth) const {
  const auto& k = params_.calibration;
  EyeFrame frame;
  PrepareEye(eye, pose, &frame);
  cv::Mat image(k.height_px, k.width_px, CV_8UC3);
  if (truth) truth->labels.create(k.height_px, k.width_px, CV_8U);
  ShadeRows(frame, 0, k.height_px, &image, truth ? &truth->labels : nullptr);
  FinishEye(eye, frame_index, &image, truth);
  return image;
}

void StereoRenderer::Render(const Pose2D& pose, uint64_t frame_index, bool with_truth,
                            StereoImages* out) const {
  const auto& k = params_.calibration;
  EyeFrame frames[2];
  cv::Mat* images[2] = {&out->left, &out->right};
  ImageGroundTruth* truths[2] = {with_truth ? &out->left_truth : nullptr,
                                 with_truth ? &out->right_truth : nullptr};
  const Eye eyes[2] = {Eye::kLeft, Eye::kRight};
  cv::parallel_for_(cv::Range(0, 2), [&](const cv::Range& range) {
    for (int e = range.start; e < range.end; ++e) {
      PrepareEye(eyes[e], pose, &frames[e]);
      *images[e] = cv::Mat(k.height_px, k.width_px, CV_8UC3);
      if (truths[e]) truths[e]->labels.create(k.height_px, k.width_px, CV_8U);
    }
  });
  // Bands of rows of both eyes, so both cores stay busy when one of them is interrupted.
  const int bands = (k.height_px + kBandRows - 1) / kBandRows;
  cv::parallel_for_(cv::Range(0, 2 * bands), [&](const cv::Range& range) {
    for (int task = range.start; task < range.end; ++task) {
      const int e = task / bands, row = (task % bands) * kBandRows;
      ShadeRows(frames[e], row, std::min(k.height_px, row + kBandRows), images[e],
                truths[e] ? &truths[e]->labels : nullptr);
    }
  });
  cv::parallel_for_(cv::Range(0, 2), [&](const cv::Range& range) {
    for (int e = range.start; e < range.end; ++e) {
      FinishEye(eyes[e], frame_index, images[e], truths[e]);
    }
  });
}

}  // namespace mostar::sim
