// Overlay registration against the simulator's ground truth, through the real eye renderer
// (OpenGL, Xvfb + llvmpipe in CI; skipped without an X display).
//
// For each ground-truth point (wall bases: where each laser beam meets the nearest obstacle
// footprint on the floor; circle points: the floor at 1, 1.5, 2 and 3 m), the simulator's own
// projection (sim::ProjectLaserPoint, its lens distortion written independently of common/math)
// gives the pixel of that point in the camera image. A small Gaussian dot is drawn there in a
// black camera image, the image goes through EyeRenderer (undistortion, stereo offset), and the
// dot's centroid in the read-back framebuffer is where the display shows that point. The
// overlay draws the point where the eye's display matrices send it (clip -> NDC -> pixel, the
// transform GL applies to the vertex). The registration error is the distance of the two.
//
// Scenarios: lens distortion k1 = -0.28 (the example calibration's), and the right camera
// mounted 5 px low, aligned with the right eye's vertical offset, under the shared-parameter
// model (thesis 9.1) and with per-eye intrinsics. The "pinhole over the camera image" row is the
// former drawing (camera image shown as received, pinhole overlay): computed from the simulator's
// projection, no GL needed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/stats/percentile.h"
#include "operator_client/render/eye_geometry.h"
#include "operator_client/render/eye_renderer.h"
#include "operator_client/render/eye_viewports.h"
#include "operator_client/render/gl.h"
#include "operator_client/render/screenshot.h"
#include "operator_client/render/stereo_compositor.h"
#include "operator_client/ui/window.h"
#include "operator_client/vision/vision_pipeline.h"
#include "robot_server/sim/sim_world.h"
#include "tests/vision/sim_calibration.h"

namespace mostar::vision {
namespace {

const Time kStart = FromUnixNanos(1'700'000'000'000'000'000);
constexpr double kDotSigmaPx = 1.5;
constexpr int kSearchPx = 12;  // the dot is looked for this far from the overlay's pixel

struct TruthPoint {
  Eigen::Vector3d laser;  // laser frame, m
  bool wall_base = false;
};

struct Scenario {
  std::string name;
  double k1 = -0.28;
  double right_low_px = 0.0;  // the simulator's right camera principal point moved down
  render::AlignmentModel model = render::AlignmentModel::kSharedModel;
  float right_offset_y_px = 0.f;   // the operator's vertical alignment of the right image
  bool former_drawing = false;     // the image shown as received (no undistortion): a control
  double right_roll_deg = 0.0;     // the simulator's right camera rolled
  float right_rotation_deg = 0.f;  // the operator's rotation of the right image
  bool unaligned_control = false;  // the roll left unaligned: a control
};

struct EyeErrors {
  std::vector<double> wall_px;
  std::vector<double> circle_px;
  std::vector<double> displayed_v;  // per point (NaN when not measured): for the between-eyes row
};

class RegistrationTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (std::getenv("DISPLAY") == nullptr) return;
    ui::WindowOptions options;
    options.width = kWindowW;
    options.height = kWindowH;
    options.visible = false;
    window_ = ui::Window::Create(options, &window_error_).release();
  }
  static void TearDownTestSuite() {
    delete window_;
    window_ = nullptr;
  }

  void SetUp() override {
    if (std::getenv("DISPLAY") == nullptr) {
      GTEST_SKIP() << "no X display: run under xvfb-run (as deploy/test.sh does)";
    }
    ASSERT_NE(window_, nullptr) << window_error_;
    std::string error;
    ASSERT_TRUE(eye_.Init(&error)) << error;
    ASSERT_TRUE(right_eye_.Init(&error)) << error;
    ASSERT_TRUE(compositor_.Init(&error)) << error;
  }

  // The window (640 x 480) after `mode` composed the eyes with `image` shown by `eye` and the
  // other eye black, as the brightest channel of each pixel (anaglyphs put each eye in its own
  // channels, interlacing in its own rows).
  cv::Mat Composed(render::DisplayMode mode, Eye eye, const cv::Mat& image,
                   const render::EyeView& view) {
    const cv::Mat black(image.size(), image.type(), cv::Scalar::all(0));
    eye_.Render(eye == Eye::kLeft ? image : black, view, {}, {});
    right_eye_.Render(eye == Eye::kRight ? image : black, view, {}, {});
    compositor_.Compose(mode, eye_.texture(), right_eye_.texture(), kWindowW, kWindowH, false);
    const cv::Mat bgr = render::ReadFramebuffer(kWindowW, kWindowH);
    std::vector<cv::Mat> channels;
    cv::split(bgr, channels);
    cv::Mat brightest;
    cv::max(channels[0], channels[1], brightest);
    cv::max(brightest, channels[2], brightest);
    return brightest;
  }

  // Where `mode` shows the eye image's pixel `p` (pixel centres) in the window; nullopt when
  // the mode does not show `eye`.
  std::optional<Eigen::Vector2d> InWindow(render::DisplayMode mode, Eye eye,
                                          const Eigen::Vector2d& p) const {
    for (const render::EyeViewport& v : render::EyeViewports(mode, kWindowW, kWindowH)) {
      if (v.eye != eye) continue;
      return Eigen::Vector2d(v.x_px + (p.x() + 0.5) * v.width_px / eye_.width() - 0.5,
                             v.y_px + (p.y() + 0.5) * v.height_px / eye_.height() - 0.5);
    }
    return std::nullopt;
  }

  cv::Mat ReadEye() const {
    cv::Mat rgba(eye_.height(), eye_.width(), CV_8UC4);
    glBindTexture(GL_TEXTURE_2D, eye_.texture());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_BGRA, GL_UNSIGNED_BYTE, rgba.data);
    cv::Mat grey;
    cv::cvtColor(rgba, grey, cv::COLOR_BGRA2GRAY);
    cv::flip(grey, grey, 0);
    return grey;
  }

  static std::unique_ptr<sim::SimWorld> MakeWorld(const Scenario& s) {
    sim::proto::Scene scene;
    std::string error;
    EXPECT_TRUE(LoadSimScene("corridor", &scene, &error)) << error;
    sim::proto::SimConfig config;
    config.mutable_camera()->set_k1(s.k1);
    config.mutable_camera()->set_right_vertical_offset_px(s.right_low_px);
    config.mutable_camera()->set_right_roll_deg(s.right_roll_deg);
    auto world = sim::SimWorld::Create(scene, config, kStart, &error);
    EXPECT_NE(world, nullptr) << error;
    return world;
  }

  static std::vector<TruthPoint> TruthPoints(sim::SimWorld& world) {
    std::vector<TruthPoint> points;
    const sim::LaserParams& laser = world.laser_params();
    const double h = laser.height_m;
    const Pose2D pose = world.StateAt(kStart).world_from_base;
    const std::vector<float> bases = TrueBaseDistances(world, pose);
    for (size_t i = 0; i < bases.size(); ++i) {
      if (!std::isfinite(bases[i])) continue;
      const double a = laser.AngleMin() + static_cast<double>(i) * laser.increment_rad;
      points.push_back({Eigen::Vector3d(bases[i] * std::cos(a), bases[i] * std::sin(a), -h), true});
    }
    for (const double r : {1.0, 1.5, 2.0, 3.0}) {
      for (int deg = -60; deg <= 60; deg += 4) {
        const double a = deg * M_PI / 180.0;
        points.push_back({Eigen::Vector3d(r * std::cos(a), r * std::sin(a), -h), false});
      }
    }
    return points;
  }

  // The client's calibration of `eye` in the scenario: the shared model takes the left eye's
  // (the simulator's nominal rig), per-eye intrinsics take each eye's own.
  static math::LaserCameraCalibration ClientCalibration(const Scenario& s,
                                                        const sim::LaserCameraCalibration& truth,
                                                        Eye eye, double laser_height_m) {
    const Eye source = s.model == render::AlignmentModel::kSharedModel ? Eye::kLeft : eye;
    math::LaserCameraCalibration c = MathCalibrationFromSim(truth, source, laser_height_m);
    return c;
  }

  // Registration errors of one eye, in the eye's image or, with `mode`, in the window that mode
  // composes (window pixels; `expected_as`, a control: the overlay placed as another mode
  // places it); `before` (optional) gets the former drawing's errors.
  EyeErrors Measure(const Scenario& s, const sim::SimWorld& world, Eye eye,
                    const std::vector<TruthPoint>& points, EyeErrors* before,
                    std::optional<render::DisplayMode> mode = std::nullopt,
                    std::optional<render::DisplayMode> expected_as = std::nullopt) {
    EyeErrors out;
    const sim::LaserCameraCalibration& truth = world.calibration();
    const double h = world.laser_params().height_m;
    render::EyeAlignment alignment;
    if (eye == Eye::kRight) {
      alignment.offset_y_px = s.right_offset_y_px;
      alignment.rotation_rad = static_cast<float>(s.right_rotation_deg * M_PI / 180.0);
    }
    std::string error;
    const std::optional<render::EyeGeometry> geometry = render::MakeEyeGeometry(
        ClientCalibration(s, truth, eye, h), eye, alignment, s.model, &error);
    EXPECT_TRUE(geometry.has_value()) << error;
    if (!geometry) return out;
    render::EyeView view = render::MakeEyeView(*geometry);
    if (s.former_drawing) {
      view.warp.k1 = view.warp.k2 = view.warp.k3 = view.warp.p1 = view.warp.p2 = 0.f;
    }
    const math::ImageRegion full = geometry->display.FullImage();
    const int w = truth.width_px;
    const int hgt = truth.height_px;

    // Camera-image and overlay pixels of every point.
    struct Sample {
      Eigen::Vector2d raw;
      Eigen::Vector2d overlay;
      bool ok = false;
    };
    std::vector<Sample> samples(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d& p = points[i].laser;
      Sample& sample = samples[i];
      if (!sim::ProjectLaserPoint(truth, eye, p.x(), p.y(), p.z(), &sample.raw.x(),
                                  &sample.raw.y())) {
        continue;
      }
      const Eigen::Vector4f clip =
          view.matrices.projection * view.matrices.view * p.cast<float>().homogeneous();
      if (!(clip.w() > 0.f)) continue;
      sample.overlay =
          math::NdcToPixel(Eigen::Vector2d(clip.x() / clip.w(), clip.y() / clip.w()), full);
      constexpr double kMargin = kSearchPx + 4;
      sample.ok = sample.raw.x() > kMargin && sample.raw.x() < w - kMargin &&
                  sample.raw.y() > kMargin && sample.raw.y() < hgt - kMargin &&
                  sample.overlay.x() > kMargin && sample.overlay.x() < w - kMargin &&
                  sample.overlay.y() > kMargin && sample.overlay.y() < hgt - kMargin;
      if (sample.ok && before != nullptr && eye == Eye::kLeft) {
        // Former drawing: the camera image as received under a pinhole overlay.
        const math::CameraModel pinhole(ClientCalibration(s, truth, eye, h), eye);
        const auto px = pinhole.ProjectUndistorted(p);
        if (px) {
          (points[i].wall_base ? before->wall_px : before->circle_px)
              .push_back((*px - sample.raw).norm());
        }
      }
    }
    out.displayed_v.assign(points.size(), std::nan(""));

    // Dots in batches far enough apart that search windows never see two.
    std::vector<bool> done(points.size(), false);
    for (;;) {
      std::vector<size_t> batch;
      for (size_t i = 0; i < points.size(); ++i) {
        if (done[i] || !samples[i].ok) continue;
        bool clear = true;
        for (size_t j : batch) {
          clear &= (samples[j].raw - samples[i].raw).norm() > 3 * kSearchPx &&
                   (samples[j].overlay - samples[i].overlay).norm() > 3 * kSearchPx;
        }
        if (clear) batch.push_back(i);
      }
      if (batch.empty()) break;
      cv::Mat image(hgt, w, CV_8UC3, cv::Scalar::all(0));
      for (size_t i : batch) {
        done[i] = true;
        const Eigen::Vector2d& c = samples[i].raw;
        for (int r = static_cast<int>(c.y()) - 6; r <= static_cast<int>(c.y()) + 7; ++r) {
          for (int col = static_cast<int>(c.x()) - 6; col <= static_cast<int>(c.x()) + 7; ++col) {
            const double d2 = (Eigen::Vector2d(col, r) - c).squaredNorm();
            const double value = 250.0 * std::exp(-0.5 * d2 / (kDotSigmaPx * kDotSigmaPx));
            image.at<cv::Vec3b>(r, col) = cv::Vec3b::all(static_cast<uint8_t>(value + 0.5));
          }
        }
      }
      cv::Mat shown;
      if (mode) {
        shown = Composed(*mode, eye, image, view);
      } else {
        eye_.Render(image, view, {}, {});
        shown = ReadEye();
      }
      for (size_t i : batch) {
        const std::optional<Eigen::Vector2d> where =
            mode ? InWindow(expected_as.value_or(*mode), eye, samples[i].overlay)
                 : samples[i].overlay;
        if (!where) continue;
        const Eigen::Vector2d& o = *where;
        const cv::Rect window(static_cast<int>(o.x()) - kSearchPx,
                              static_cast<int>(o.y()) - kSearchPx, 2 * kSearchPx + 1,
                              2 * kSearchPx + 1);
        double total = 0, su = 0, sv = 0;
        for (int r = window.y; r < window.y + window.height; ++r) {
          for (int col = window.x; col < window.x + window.width; ++col) {
            const double value = shown.at<uint8_t>(r, col);
            if (value < 3) continue;
            total += value;
            su += value * col;
            sv += value * r;
          }
        }
        double error_px = kSearchPx;  // not found near the overlay: counted as the search radius
        if (total > 500) {
          const Eigen::Vector2d centroid(su / total, sv / total);
          error_px = (centroid - o).norm();
          out.displayed_v[i] = centroid.y();
        }
        (points[i].wall_base ? out.wall_px : out.circle_px).push_back(error_px);
      }
    }
    return out;
  }

  static double P(const std::vector<double>& v, double q) { return Percentile(v, q).value_or(-1); }

  static constexpr int kWindowW = 640;
  static constexpr int kWindowH = 480;
  static ui::Window* window_;
  static std::string window_error_;
  render::EyeRenderer eye_;  // the left eye's when composing
  render::EyeRenderer right_eye_;
  render::StereoCompositor compositor_;
};

ui::Window* RegistrationTest::window_ = nullptr;
std::string RegistrationTest::window_error_;

TEST_F(RegistrationTest, OverlaySitsOnTheImageWithLensDistortionAndStereoOffset) {
  const std::vector<Scenario> scenarios = {
      {"k1 -0.28", -0.28, 0.0, render::AlignmentModel::kSharedModel, 0.f},
      {"k1 -0.28, right 5 px low, shared model, dy -5", -0.28, 5.0,
       render::AlignmentModel::kSharedModel, -5.f},
      {"k1 -0.28, right 5 px low, per-eye intrinsics, dy -5", -0.28, 5.0,
       render::AlignmentModel::kPerEyeIntrinsics, -5.f},
      // The right camera also rolled 1 degree, aligned by rotating its image -1 degree; with
      // per-eye intrinsics its calibration knows the roll (as a stereo calibration gives it).
      {"k1 -0.28, right 5 px low and rolled 1 deg, shared model, dy -5, rotation -1 deg", -0.28,
       5.0, render::AlignmentModel::kSharedModel, -5.f, false, 1.0, -1.f},
      {"k1 -0.28, right 5 px low and rolled 1 deg, per-eye intrinsics, dy -5, rotation -1 deg",
       -0.28, 5.0, render::AlignmentModel::kPerEyeIntrinsics, -5.f, false, 1.0, -1.f},
      // Controls: the same measurement sees the former drawing's error (capped at the search
      // radius, kSearchPx), and a roll left unaligned.
      {"control: k1 -0.28, image not undistorted", -0.28, 0.0, render::AlignmentModel::kSharedModel,
       0.f, true},
      {"control: right 5 px low and rolled 1 deg, shared model, dy -5, no rotation", -0.28, 5.0,
       render::AlignmentModel::kSharedModel, -5.f, false, 1.0, 0.f, true},
  };
  std::printf(
      "| scenario | eye | wall bases p50 / p95 px (n) | circle points p50 / p95 px (n) |\n"
      "|---|---|---|---|\n");
  for (const Scenario& s : scenarios) {
    auto world = MakeWorld(s);
    ASSERT_NE(world, nullptr);
    const std::vector<TruthPoint> points = TruthPoints(*world);
    EyeErrors before;
    EyeErrors eyes[2];
    for (int e = 0; e < 2; ++e) {
      const Eye eye = e == 0 ? Eye::kLeft : Eye::kRight;
      const bool nominal = s.right_low_px == 0.0 && !s.former_drawing && s.right_roll_deg == 0.0;
      eyes[e] = Measure(s, *world, eye, points, nominal ? &before : nullptr);
      const EyeErrors& m = eyes[e];
      std::printf("| %s | %s | %.2f / %.2f (%zu) | %.2f / %.2f (%zu) |\n", s.name.c_str(),
                  EyeName(eye), P(m.wall_px, 0.5), P(m.wall_px, 0.95), m.wall_px.size(),
                  P(m.circle_px, 0.5), P(m.circle_px, 0.95), m.circle_px.size());
      ASSERT_GT(m.wall_px.size(), 50u) << s.name;
      ASSERT_GT(m.circle_px.size(), 50u) << s.name;
      if (s.former_drawing) {
        EXPECT_GT(P(m.wall_px, 0.95), 5.0) << s.name << ", " << EyeName(eye);
        EXPECT_GT(P(m.circle_px, 0.95), 5.0) << s.name << ", " << EyeName(eye);
        continue;
      }
      if (s.unaligned_control && eye == Eye::kRight) {
        EXPECT_GT(P(m.wall_px, 0.95), 2.0) << s.name;  // 1 degree is 4.9 px 280 px off centre
        continue;
      }
      EXPECT_LE(P(m.wall_px, 0.95), 0.5) << s.name << ", " << EyeName(eye);
      EXPECT_LE(P(m.circle_px, 0.95), 0.5) << s.name << ", " << EyeName(eye);
    }
    if (!before.wall_px.empty()) {
      std::printf(
          "| %s, pinhole over the camera image (before) | left | %.2f / %.2f (%zu) | "
          "%.2f / %.2f (%zu) |\n",
          s.name.c_str(), P(before.wall_px, 0.5), P(before.wall_px, 0.95), before.wall_px.size(),
          P(before.circle_px, 0.5), P(before.circle_px, 0.95), before.circle_px.size());
    }
    // Between the eyes: the same floor point on the same displayed row (aim 1 of thesis 9.1; the
    // rig's cameras are parallel and level, so vertical disparity is the misalignment).
    std::vector<double> between;
    for (size_t i = 0; i < points.size(); ++i) {
      if (!std::isnan(eyes[0].displayed_v[i]) && !std::isnan(eyes[1].displayed_v[i])) {
        between.push_back(std::abs(eyes[0].displayed_v[i] - eyes[1].displayed_v[i]));
      }
    }
    std::printf("| %s | between eyes, vertical | %.2f / %.2f (%zu), wall bases and circles |  |\n",
                s.name.c_str(), P(between, 0.5), P(between, 0.95), between.size());
    if (s.former_drawing) continue;
    ASSERT_GT(between.size(), 50u);
    if (s.unaligned_control) {
      EXPECT_GT(P(between, 0.95), 2.0) << s.name;
      continue;
    }
    EXPECT_LE(P(between, 0.95), 1.0) << s.name;
  }
}

// Every display mode: each eye's dots composed into the 640 x 480 window as the console does
// (StereoCompositor, EyeViewports), measured in window pixels against where the mode puts the
// overlay's pixel. Side-by-side (full) shows each eye 1:1 in its half of a window twice as wide,
// as mono does; quad-buffer falls back to mono-left without a stereo driver (Mesa).
TEST_F(RegistrationTest, OverlaySitsOnTheImageInEveryDisplayMode) {
  const Scenario s{"k1 -0.28, right 5 px low, shared model, dy -5", -0.28, 5.0,
                   render::AlignmentModel::kSharedModel, -5.f};
  auto world = MakeWorld(s);
  ASSERT_NE(world, nullptr);
  const std::vector<TruthPoint> points = TruthPoints(*world);
  std::printf(
      "| display mode | eye | wall bases p50 / p95 window px (n) | circle points p50 / p95 window "
      "px (n) |\n|---|---|---|---|\n");
  for (const render::DisplayMode mode :
       {render::DisplayMode::kMonoLeft, render::DisplayMode::kMonoRight,
        render::DisplayMode::kAnaglyphGrey, render::DisplayMode::kAnaglyphColor,
        render::DisplayMode::kSideBySideHalf, render::DisplayMode::kTopBottom,
        render::DisplayMode::kRowInterlaced}) {
    for (const Eye eye : {Eye::kLeft, Eye::kRight}) {
      const bool shown = InWindow(mode, eye, Eigen::Vector2d(0, 0)).has_value();
      const EyeErrors m = Measure(s, *world, eye, points, nullptr, mode);
      if (!shown) {
        EXPECT_TRUE(m.wall_px.empty() && m.circle_px.empty()) << render::DisplayModeName(mode);
        continue;
      }
      std::printf("| %s | %s | %.2f / %.2f (%zu) | %.2f / %.2f (%zu) |\n",
                  render::DisplayModeName(mode), EyeName(eye), P(m.wall_px, 0.5),
                  P(m.wall_px, 0.95), m.wall_px.size(), P(m.circle_px, 0.5), P(m.circle_px, 0.95),
                  m.circle_px.size());
      ASSERT_GT(m.wall_px.size(), 50u) << render::DisplayModeName(mode);
      ASSERT_GT(m.circle_px.size(), 50u) << render::DisplayModeName(mode);
      EXPECT_LE(P(m.wall_px, 0.95), 0.5) << render::DisplayModeName(mode) << ", " << EyeName(eye);
      EXPECT_LE(P(m.circle_px, 0.95), 0.5) << render::DisplayModeName(mode) << ", " << EyeName(eye);
    }
  }
  // Control: the squeezed left eye of sbs-half measured where mono-left would put it.
  const EyeErrors control =
      Measure(s, *world, Eye::kLeft, points, nullptr, render::DisplayMode::kSideBySideHalf,
              render::DisplayMode::kMonoLeft);
  std::printf("| control: sbs-half measured as mono-left | left | %.2f / %.2f (%zu) | |\n",
              P(control.wall_px, 0.5), P(control.wall_px, 0.95), control.wall_px.size());
  EXPECT_GT(P(control.wall_px, 0.5), 5.0);
}

// A picture to look at: the simulated corridor (k1 = -0.28) through the eye renderer with the
// true wall bases and circle points as red dots, written to registration_corridor.png in the
// test's working directory (the build tree under CTest).
TEST_F(RegistrationTest, WritesTheCorridorWithItsTrueBasesForInspection) {
  const Scenario s{"k1 -0.28", -0.28, 0.0, render::AlignmentModel::kSharedModel, 0.f};
  auto world = MakeWorld(s);
  ASSERT_NE(world, nullptr);
  const std::vector<TruthPoint> points = TruthPoints(*world);
  const sim::StereoImages images = world->StereoAt(kStart, false);
  std::string error;
  const double h = world->laser_params().height_m;
  const std::optional<render::EyeGeometry> geometry = render::MakeEyeGeometry(
      ClientCalibration(s, world->calibration(), Eye::kLeft, h), Eye::kLeft, {}, s.model, &error);
  ASSERT_TRUE(geometry.has_value()) << error;
  render::OverlayGeometry overlay;
  overlay.point_size_px = 3.f;
  for (const TruthPoint& p : points) {
    overlay.points.Add(static_cast<float>(p.laser.x()), static_cast<float>(p.laser.y()),
                       static_cast<float>(p.laser.z()), fusion::Rgba{1, 0, 0, 1});
  }
  eye_.Render(images.left, render::MakeEyeView(*geometry), overlay, {});
  cv::Mat rgba(eye_.height(), eye_.width(), CV_8UC4);
  glBindTexture(GL_TEXTURE_2D, eye_.texture());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTexImage(GL_TEXTURE_2D, 0, GL_BGRA, GL_UNSIGNED_BYTE, rgba.data);
  cv::Mat shown;
  cv::cvtColor(rgba, shown, cv::COLOR_BGRA2BGR);
  cv::flip(shown, shown, 0);
  cv::Mat both;
  cv::hconcat(images.left, shown, both);
  EXPECT_TRUE(cv::imwrite("registration_corridor.png", both));
}

// Thesis 9.1 with NESC's hint: the right camera mounted 5 px low, the edge processing run on each
// eye's image model; the suggested offset aligns the displayed images, and once applied NESC
// measures no residual. Needs no display.
TEST(StereoOffsetHintTest, SuggestionAlignsARightCameraMountedLow) {
  for (const render::AlignmentModel model :
       {render::AlignmentModel::kSharedModel, render::AlignmentModel::kPerEyeIntrinsics}) {
    sim::proto::Scene scene;
    std::string error;
    ASSERT_TRUE(LoadSimScene("corridor", &scene, &error)) << error;
    sim::proto::SimConfig config;
    config.mutable_camera()->set_k1(-0.28);
    config.mutable_camera()->set_right_vertical_offset_px(5.0);
    config.mutable_camera()->set_noise_sigma(0.0);
    auto world = sim::SimWorld::Create(scene, config, kStart, &error);
    ASSERT_NE(world, nullptr) << error;
    const double h = world->laser_params().height_m;
    const math::LaserCameraCalibration left_calibration =
        MathCalibrationFromSim(world->calibration(), Eye::kLeft, h);
    const math::LaserCameraCalibration right_calibration =
        model == render::AlignmentModel::kSharedModel
            ? left_calibration
            : MathCalibrationFromSim(world->calibration(), Eye::kRight, h);
    VisionPipeline pipeline{VisionOptions{}};
    int views = 0;
    // NESC's residual with the right eye's vertical offset `dy`, over a few views.
    const auto measure = [&](float dy, render::EyeGeometry* left, render::EyeGeometry* right) {
      render::EyeAlignment right_alignment;
      right_alignment.offset_y_px = dy;
      std::string why;
      const auto l = render::MakeEyeGeometry(left_calibration, Eye::kLeft, {}, model, &why);
      const auto r =
          render::MakeEyeGeometry(right_calibration, Eye::kRight, right_alignment, model, &why);
      EXPECT_TRUE(l && r) << why;
      *left = *l;
      *right = *r;
      VisionInput input;
      input.left_camera = std::make_shared<const math::CameraModel>(l->image);
      input.right_camera = std::make_shared<const math::CameraModel>(r->image);
      std::vector<double> residuals;
      world->SetVelocity(0.0, 0.4);
      for (int frame = 0; frame < 3; ++frame) {
        const Time t = kStart + FromSeconds(1.0 * views++);
        input.scan = world->ScanAt(t);
        const sim::StereoImages images = world->StereoAt(t, false);
        input.left = images.left;
        input.right = images.right;
        const VisionResult result = pipeline.Process(input);
        EXPECT_TRUE(result.ok) << result.error;
        if (result.nesc.offset.valid) residuals.push_back(result.nesc.offset.vertical_offset_px);
      }
      EXPECT_FALSE(residuals.empty());
      return Percentile(residuals, 0.5).value_or(0.0);
    };
    render::EyeGeometry left =
        *render::MakeEyeGeometry(left_calibration, Eye::kLeft, {}, model, &error);
    render::EyeGeometry right = left;
    const double residual = measure(0.f, &left, &right);
    const float suggested = render::SuggestedRightOffsetY(left, right, {}, residual);
    std::printf("%s model: residual %.2f px, suggested dy %.2f px\n",
                render::AlignmentModelName(model), residual, suggested);
    EXPECT_NEAR(suggested, -5.0, 0.75) << render::AlignmentModelName(model);
    const double after = measure(suggested, &left, &right);
    std::printf("%s model: after Apply, residual %.2f px\n", render::AlignmentModelName(model),
                after);
    if (model == render::AlignmentModel::kSharedModel) {
      EXPECT_NEAR(after, 0.0, 0.75);
    }
    EXPECT_NEAR(render::SuggestedRightOffsetY(left, right, {}, after), suggested, 0.75);
  }
}

}  // namespace
}  // namespace mostar::vision
