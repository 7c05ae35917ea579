// Self-refining calibration against the simulator's ground truth (issue 17, "Calibration that
// refines itself"; docs/calibration.md, "Self-calibration").
//
// The robot drives through a scene while the edge processing runs with a calibration perturbed
// from the simulator's true one by the amounts (f 10 %, tilt 2 deg, camera y 3 cm, pan
// 1 deg, every sign flipped together). Each processed pair's agreeing NEPs feed the rolling
// window; once per second of driving the window is fitted from the calibration in force, and
// the simulated operator applies every trustworthy proposal (the edge processing uses it from
// the next pair on; more NEPs then agree). Every scenario drives the whole 30 s and states what
// must happen, so that every scenario can fail:
//  - kReaches: the proposal becomes trustworthy and within 1 % / 0.2 deg / 5 mm / 0.2 deg of the
//    truth with a reprojection p95 <= 1 px over the correct points it fits (injected wrong
//    points left out), and every trustworthy proposal after that stays within kSettledBound
//    times those tolerances (the tilt then drifts to about -0.21 deg: a systematic bias, the
//    open goal "tilt within 0.1 deg" of issue 36; docs/calibration.md);
//  - kStaysNear (wrong NEPs injected): some trustworthy proposal has the parameters within
//    tolerance, and every one from then on stays within kSettledBound times it;
//  - kRefuses: no fit is ever trustworthy, and the last says why (`refusal`, part of its reason);
//  - kHalfway: nothing is applied; the last fit from the perturbed start is at least halfway.
// Every scenario: no trustworthy proposal makes a parameter worse than its start.
// With `wrong_fraction` > 0 that share of the correspondences is moved 3 to 20 px off the edge
// in a random direction (wrong NEPs that still agree with the laser).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "common/stats/percentile.h"
#include "operator_client/calibration/calibration_fit.h"
#include "operator_client/calibration/edge_correspondences.h"
#include "operator_client/vision/vision_pipeline.h"
#include "robot_server/sim/sim_world.h"
#include "tests/vision/sim_calibration.h"

namespace mostar::vision {
namespace {

using calibration::FitResult;

const Time kStart = FromUnixNanos(1'700'000'000'000'000'000);
constexpr double kDeg = M_PI / 180.0;
constexpr double kPairPeriodS = 0.2;  // edge processing at 5 pairs per second
constexpr int kPairsPerFit = 5;       // one fit per second of driving
constexpr int kMaxPairs = 150;        // 30 s of driving

enum class Expect { kReaches, kStaysNear, kRefuses, kHalfway };

// How far, in tolerances, a trustworthy proposal may be from the truth once one was within
// tolerance, and how much worse than its start any trustworthy proposal may make a parameter.
constexpr double kSettledBound = 1.5;

struct Scenario {
  const char* scene;
  double sign;            // +1: f +10 %, tilt +2 deg, y +3 cm, pan +1 deg; -1: all negative
  double wrong_fraction;  // share of correspondences moved off their edge
  bool all_free;          // false: x, z and roll held (the issue perturbs f, tilt, y, pan)
  bool clean_images;      // no image noise, no contact shadows (the simulator's defaults have)
  // The operator applies every trustworthy proposal (the edge processing then uses it); false:
  // nothing is ever applied and every fit starts from the perturbed calibration.
  bool applies;
  Expect expect;
  const char* refusal = "";  // kRefuses: part of the last fit's reason
};

std::string Name(const ::testing::TestParamInfo<Scenario>& info) {
  return std::string(info.param.scene) + (info.param.sign > 0 ? "_plus" : "_minus") + "_wrong" +
         std::to_string(static_cast<int>(std::lround(100 * info.param.wrong_fraction))) +
         (info.param.all_free ? "_all_free" : "") + (info.param.clean_images ? "_clean" : "") +
         (info.param.applies ? "" : "_never_applied");
}

// The robot's path: forward at 0.25 m/s, weaving (heading +-20 deg, period 8 s); it stops at
// obstacles (the simulator's collision test), turning on.
double AngularAt(double t_s) { return 0.3 * std::sin(2.0 * M_PI * t_s / 8.0); }

// Each perturbed parameter's error, in units of its tolerance (1 % / 0.2 deg / 5 mm / 0.2 deg).
std::array<double, 4> ScaledErrors(const math::LaserCameraCalibration& truth,
                                   const math::LaserCameraCalibration& c) {
  return {std::abs(c.focal_px / truth.focal_px - 1.0) / 0.01,
          std::abs(c.tilt_rad - truth.tilt_rad) / (0.2 * kDeg),
          std::abs(c.camera_y_m - truth.camera_y_m) / 0.005,
          std::abs(c.pan_rad - truth.pan_rad) / (0.2 * kDeg)};
}

// A trustworthy proposal must not make any perturbed parameter worse than the calibration it
// started from, beyond kSettledBound tolerances: applying it is safe.
bool MadeWorse(const math::LaserCameraCalibration& truth, const FitResult& fit) {
  const std::array<double, 4> before = ScaledErrors(truth, fit.start);
  const std::array<double, 4> after = ScaledErrors(truth, fit.proposal);
  for (size_t i = 0; i < before.size(); ++i) {
    if (after[i] > std::max(before[i], kSettledBound)) return true;
  }
  return false;
}

// Distance from a correspondence's pixel to the image of its base line under `model`, pixels
// (the fit's residual); +Inf when the line does not project.
double Residual(const math::CameraModel& model, const calibration::EdgeCorrespondence& c) {
  const std::optional<Eigen::Vector2d> a = model.Project(c.base_laser);
  const std::optional<Eigen::Vector2d> b = model.Project(c.base_laser + 0.1 * c.direction_laser);
  if (!a || !b || (*b - *a).norm() < 1e-9) return std::numeric_limits<double>::infinity();
  const Eigen::Vector2d d = (*b - *a).normalized();
  const Eigen::Vector2d v = c.pixel - *a;
  return std::abs(v.x() * d.y() - v.y() * d.x());
}

// The proposal's reprojection p95 over the correct points (not injected) it fits (residual
// within the fit's inlier_px): the fit's own p95 would count injected points that happen to
// fall near their line.
double CorrectPointsP95(const FitResult& fit, const calibration::FitInput& input,
                        const std::vector<bool>& injected, double inlier_px) {
  const math::CameraModel left(fit.proposal, Eye::kLeft);
  std::optional<math::CameraModel> right;
  if (input.right) {
    right.emplace(calibration::MoveParameters(*input.right, calibration::ParametersOf(fit.start),
                                              calibration::ParametersOf(fit.proposal)),
                  Eye::kRight);
  }
  std::vector<double> residuals;
  for (size_t i = 0; i < input.points.size(); ++i) {
    if (injected[i]) continue;
    const calibration::EdgeCorrespondence& c = input.points[i];
    if (c.eye == Eye::kRight && !right) continue;
    const double r = Residual(c.eye == Eye::kLeft ? left : *right, c);
    if (r <= inlier_px) residuals.push_back(r);
  }
  return Percentile(residuals, 0.95).value_or(std::numeric_limits<double>::infinity());
}

// The largest of the four parameters' errors, in tolerances (ScaledErrors).
double WorstScaledError(const math::LaserCameraCalibration& truth, const FitResult& fit) {
  const std::array<double, 4> e = ScaledErrors(truth, fit.proposal);
  return *std::max_element(e.begin(), e.end());
}

bool WithinTolerance(const math::LaserCameraCalibration& truth, const FitResult& fit,
                     double correct_p95_px) {
  return fit.trustworthy && correct_p95_px <= 1.0 &&
         std::abs(fit.proposal.focal_px / truth.focal_px - 1.0) <= 0.01 &&
         std::abs(fit.proposal.tilt_rad - truth.tilt_rad) <= 0.2 * kDeg &&
         std::abs(fit.proposal.camera_y_m - truth.camera_y_m) <= 0.005 &&
         std::abs(fit.proposal.pan_rad - truth.pan_rad) <= 0.2 * kDeg;
}

class SelfCalibrationTest : public ::testing::TestWithParam<Scenario> {};

TEST_P(SelfCalibrationTest, ProposalReachesTheTruthWhileDriving) {
  const Scenario& scenario = GetParam();
  sim::proto::Scene scene;
  std::string error;
  ASSERT_TRUE(LoadSimScene(scenario.scene, &scene, &error)) << error;
  sim::proto::SimConfig config;
  if (scenario.clean_images) {
    config.mutable_camera()->set_noise_sigma(0.0);
    config.mutable_camera()->set_contact_shadows(false);
  }
  auto world = sim::SimWorld::Create(scene, config, kStart, &error);
  ASSERT_NE(world, nullptr) << error;
  const double height_m = world->laser_params().height_m;
  const math::LaserCameraCalibration truth[2] = {
      MathCalibrationFromSim(world->calibration(), Eye::kLeft, height_m),
      MathCalibrationFromSim(world->calibration(), Eye::kRight, height_m)};
  calibration::ParameterVector delta = calibration::ParametersOf(truth[0]);
  delta[calibration::kFocal] *= 1.0 + 0.10 * scenario.sign;
  delta[calibration::kTilt] += 2.0 * kDeg * scenario.sign;
  delta[calibration::kCameraY] += 0.03 * scenario.sign;
  delta[calibration::kPan] += 1.0 * kDeg * scenario.sign;
  calibration::FitInput fit_input;
  fit_input.left =
      calibration::MoveParameters(truth[0], calibration::ParametersOf(truth[0]), delta);
  fit_input.right =
      calibration::MoveParameters(truth[1], calibration::ParametersOf(truth[0]), delta);

  VisionInput input;
  input.left_camera = std::make_shared<const math::CameraModel>(fit_input.left, Eye::kLeft);
  input.right_camera = std::make_shared<const math::CameraModel>(*fit_input.right, Eye::kRight);
  const VisionOptions options;
  VisionPipeline pipeline{options};
  calibration::CorrespondenceWindow window(3000, std::chrono::seconds(60));
  std::deque<bool> injected;  // per window point, in the window's order (its capacity, 3000)
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);

  double reached_s = -1.0;
  FitResult last;
  size_t pairs = 0;
  size_t correspondences = 0;
  int applied = 0;
  int made_worse = 0;        // trustworthy proposals worse than their start (MadeWorse)
  int trustworthy = 0;       // trustworthy fits
  int left_bound = 0;        // trustworthy fits beyond kSettledBound after one was within tolerance
  double settled_worst = 0;  // largest WorstScaledError from then on
  double parameters_within_s = -1.0;  // the first trustworthy fit with the parameters within
  double reached_p95_px = 0;          // CorrectPointsP95 of the first fit within tolerance
  for (int k = 0; k <= kMaxPairs; ++k) {
    const double t_s = k * kPairPeriodS;
    const Time t = kStart + FromSeconds(t_s);
    world->SetVelocity(0.25, AngularAt(t_s));
    input.stamp = t;
    input.scan = world->ScanAt(t);
    const sim::StereoImages images = world->StereoAt(t, /*with_truth=*/false);
    input.left = images.left;
    input.right = images.right;
    const VisionResult result = pipeline.Process(input);
    ASSERT_TRUE(result.ok) << result.error;
    ++pairs;
    std::vector<calibration::EdgeCorrespondence> found = calibration::ExtractCorrespondences(
        result, input.scan, options.classifier, height_m, calibration::CorrespondenceOptions{});
    for (calibration::EdgeCorrespondence& c : found) {
      const bool wrong = unit(rng) < scenario.wrong_fraction;
      injected.push_back(wrong);
      if (!wrong) continue;
      const double angle = 2.0 * M_PI * unit(rng);
      c.pixel += (3.0 + 17.0 * unit(rng)) * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    }
    correspondences += found.size();
    window.Add(found);
    while (injected.size() > window.size()) injected.pop_front();  // as the window drops
    if (k == 0 || k % kPairsPerFit != 0) continue;
    fit_input.points = window.Snapshot();
    ASSERT_EQ(injected.size(), fit_input.points.size());
    calibration::FitOptions fit_options;  // x, z and roll held by default
    if (scenario.all_free) fit_options.free.fill(true);
    last = calibration::FitCalibration(fit_input, fit_options);
    if (!last.trustworthy) continue;
    ++trustworthy;
    if (MadeWorse(truth[0], last)) ++made_worse;
    const double p95_px =
        CorrectPointsP95(last, fit_input, std::vector<bool>(injected.begin(), injected.end()),
                         fit_options.inlier_px);
    const double worst = WorstScaledError(truth[0], last);
    if (parameters_within_s < 0 && worst <= 1.0) parameters_within_s = t_s;
    if (reached_s < 0 && WithinTolerance(truth[0], last, p95_px)) {
      reached_s = t_s;
      reached_p95_px = p95_px;
    }
    const bool settled =
        scenario.expect == Expect::kStaysNear ? parameters_within_s >= 0 : reached_s >= 0;
    if (settled) {
      settled_worst = std::max(settled_worst, worst);
      if (worst > kSettledBound) ++left_bound;
    }
    if (scenario.applies && last.trustworthy) {  // the operator's click
      const calibration::ParameterVector from = calibration::ParametersOf(fit_input.left);
      const calibration::ParameterVector to = calibration::ParametersOf(last.proposal);
      fit_input.left = last.proposal;
      fit_input.right = calibration::MoveParameters(*fit_input.right, from, to);
      input.left_camera = std::make_shared<const math::CameraModel>(fit_input.left, Eye::kLeft);
      input.right_camera = std::make_shared<const math::CameraModel>(*fit_input.right, Eye::kRight);
      ++applied;
    }
  }
  const math::LaserCameraCalibration& p = last.proposal;
  std::printf(
      "| %s | %+.0f | %.0f %% | %s | %.2f %% | %.3f deg | %.1f mm | %.3f deg | %.2f / %.2f | "
      "%.2f / %.2f | %zu (%zu inliers) | %s |\n",
      (std::string(scenario.scene) + (scenario.all_free ? ", all 7 free" : "") +
       (scenario.clean_images ? ", clean images" : "") +
       (scenario.applies ? "" : ", never applied"))
          .c_str(),
      scenario.sign, 100 * scenario.wrong_fraction,
      reached_s >= 0 ? (std::to_string(static_cast<int>(std::lround(reached_s))) + " s").c_str()
                     : "not reached",
      100 * (p.focal_px / truth[0].focal_px - 1.0), (p.tilt_rad - truth[0].tilt_rad) / kDeg,
      1000 * (p.camera_y_m - truth[0].camera_y_m), (p.pan_rad - truth[0].pan_rad) / kDeg,
      last.before.p50_px, last.before.p95_px, last.after.p50_px, last.after.p95_px, last.points,
      last.inliers, last.trustworthy ? "trustworthy" : last.reason.c_str());
  std::printf(
      "parameters within tolerance from %.0f s; "
      "applied %d proposals, %d trustworthy fits; correct points' p95 when reached %.2f px; "
      "worst parameter error from then on %.2f tolerances (%d beyond %.1f); pairs %zu, "
      "correspondences %zu, other parameters: x %.1f mm, z %.1f mm, roll %.3f deg\n",
      parameters_within_s, applied, trustworthy, reached_p95_px, settled_worst, left_bound,
      kSettledBound, pairs, correspondences, 1000 * (p.camera_x_m - truth[0].camera_x_m),
      1000 * (p.camera_z_m - truth[0].camera_z_m), (p.roll_rad - truth[0].roll_rad) / kDeg);
  EXPECT_EQ(made_worse, 0) << "trustworthy proposals that made a parameter worse";
  if (scenario.expect == Expect::kReaches) {
    EXPECT_GE(reached_s, 0.0) << "not within tolerance after " << kMaxPairs * kPairPeriodS
                              << " s: " << last.reason;
    EXPECT_EQ(left_bound, 0) << "trustworthy proposals drifted away after reaching tolerance";
  } else if (scenario.expect == Expect::kStaysNear) {
    EXPECT_GE(parameters_within_s, 0.0) << "never within tolerance: " << last.reason;
    EXPECT_EQ(left_bound, 0) << "trustworthy proposals drifted away";
  } else if (scenario.expect == Expect::kRefuses) {
    EXPECT_EQ(trustworthy, 0) << "expected a refusal (" << scenario.refusal << ")";
    EXPECT_NE(last.reason.find(scenario.refusal), std::string::npos) << last.reason;
  } else {
    // Fitted from the perturbed start alone (near, agreeing NEPs only): at least halfway there.
    EXPECT_TRUE(last.ok) << last.reason;
    EXPECT_LT(std::abs(p.focal_px / truth[0].focal_px - 1.0), 0.05);
    EXPECT_LT(std::abs(p.tilt_rad - truth[0].tilt_rad), 1.0 * kDeg);
    EXPECT_LT(std::abs(p.camera_y_m - truth[0].camera_y_m), 0.015);
    EXPECT_LT(std::abs(p.pan_rad - truth[0].pan_rad), 0.5 * kDeg);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, SelfCalibrationTest,
    ::testing::Values(
        Scenario{"corridor", +1, 0.0, false, false, true, Expect::kReaches},
        Scenario{"corridor", -1, 0.0, false, false, true, Expect::kReaches},
        // The floor's own edges hide the wall bases (docs/calibration.md): too few agree.
        Scenario{"checkerboard_room", +1, 0.0, false, false, true, Expect::kRefuses, "cover"},
        Scenario{"checkerboard_room", -1, 0.0, false, false, true, Expect::kRefuses, "too few"},
        Scenario{"corridor", +1, 0.3, false, false, true, Expect::kStaysNear},
        Scenario{"checkerboard_room", -1, 0.3, false, false, true, Expect::kRefuses, "too few"},
        // Tile joints and tape near the robot hide the wall bases: the agreeing points gather in
        // a narrow band of columns (the fits there would be 5 deg and 9 cm off).
        Scenario{"tiled_room", +1, 0.0, false, false, true, Expect::kRefuses, "cover"},
        Scenario{"tiled_room", -1, 0.0, false, false, true, Expect::kRefuses, "cover"},
        Scenario{"corridor", +1, 0.0, false, false, false, Expect::kHalfway},
        // x trades off against pan and z against f on a corridor's floor edges.
        Scenario{"corridor", +1, 0.0, true, false, true, Expect::kRefuses, "uncertain"}),
    Name);

}  // namespace
}  // namespace mostar::vision
