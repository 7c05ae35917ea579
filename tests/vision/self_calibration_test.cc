// Self-refining calibration against the simulator's ground truth (issue 17, "Calibration that
// refines itself"; docs/calibration.md, "Self-calibration").
//
// The robot drives through a scene while the edge processing runs with a calibration perturbed
// from the simulator's true one by the amounts (f 10 %, tilt 2 deg, camera y 3 cm, pan
// 1 deg, every sign flipped together). Each processed pair's agreeing NEPs feed the rolling
// window; once per second of driving the window is fitted from the calibration in force, and
// the simulated operator applies every trustworthy proposal (the edge processing uses it from
// the next pair on; more NEPs then agree). The test reports how many seconds of driving it takes
// until the proposal is trustworthy and within 1 % / 0.2 deg / 5 mm / 0.2 deg of the truth with
// a reprojection p95 <= 1 px, and fails when that does not happen within 30 s. One scenario
// never applies anything: every fit starts from the perturbed calibration.
// With `wrong_fraction` > 0 that share of the correspondences is moved 3 to 20 px off the edge
// in a random direction (wrong NEPs that still agree with the laser).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

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

struct Scenario {
  const char* scene;
  double sign;            // +1: f +10 %, tilt +2 deg, y +3 cm, pan +1 deg; -1: all negative
  double wrong_fraction;  // share of correspondences moved off their edge
  bool all_free;          // false: x, z and roll held (the issue perturbs f, tilt, y, pan)
  bool clean_images;      // no image noise, no contact shadows (the simulator's defaults have)
  // The operator applies every trustworthy proposal (the edge processing then uses it); false:
  // nothing is ever applied and every fit starts from the perturbed calibration.
  bool applies;
  // The drive should bring the proposal within tolerance (false: the scene hides the wall
  // bases, see docs/calibration.md; only the safety check below applies).
  bool expect_reached;
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
// started from, beyond the tolerance: applying it is safe.
bool MadeWorse(const math::LaserCameraCalibration& truth, const FitResult& fit) {
  const std::array<double, 4> before = ScaledErrors(truth, fit.start);
  const std::array<double, 4> after = ScaledErrors(truth, fit.proposal);
  for (size_t i = 0; i < before.size(); ++i) {
    if (after[i] > std::max(before[i], 1.0)) return true;
  }
  return false;
}

// With wrong NEPs the proposal's p95 counts the wrong points that fall within inlier_px of their
// line: the criterion is then the parameters alone.
bool WithinTolerance(const math::LaserCameraCalibration& truth, const FitResult& fit,
                     bool clean_points) {
  return fit.trustworthy && (!clean_points || fit.after.p95_px <= 1.0) &&
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
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);

  double reached_s = -1.0;
  FitResult last;
  size_t pairs = 0;
  size_t correspondences = 0;
  int applied = 0;
  int made_worse = 0;  // trustworthy proposals worse than their start (MadeWorse)
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
      if (unit(rng) >= scenario.wrong_fraction) continue;
      const double angle = 2.0 * M_PI * unit(rng);
      c.pixel += (3.0 + 17.0 * unit(rng)) * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    }
    correspondences += found.size();
    window.Add(found);
    if (k == 0 || k % kPairsPerFit != 0) continue;
    fit_input.points = window.Snapshot();
    calibration::FitOptions fit_options;  // x, z and roll held by default
    if (scenario.all_free) fit_options.free.fill(true);
    last = calibration::FitCalibration(fit_input, fit_options);
    if (last.trustworthy && MadeWorse(truth[0], last)) ++made_worse;
    if (WithinTolerance(truth[0], last, scenario.wrong_fraction == 0.0)) {
      reached_s = t_s;
      break;
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
      "applied %d proposals; pairs %zu, correspondences %zu, other parameters: x %.1f mm, z %.1f "
      "mm, roll %.3f deg\n",
      applied, pairs, correspondences, 1000 * (p.camera_x_m - truth[0].camera_x_m),
      1000 * (p.camera_z_m - truth[0].camera_z_m), (p.roll_rad - truth[0].roll_rad) / kDeg);
  EXPECT_EQ(made_worse, 0) << "trustworthy proposals that made a parameter worse";
  if (scenario.applies && scenario.expect_reached) {
    EXPECT_GE(reached_s, 0.0) << "not within tolerance after " << kMaxPairs * kPairPeriodS
                              << " s: " << last.reason;
  } else if (!scenario.applies) {
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
    ::testing::Values(Scenario{"corridor", +1, 0.0, false, false, true, true},
                      Scenario{"corridor", -1, 0.0, false, false, true, true},
                      Scenario{"checkerboard_room", +1, 0.0, false, false, true, false},
                      Scenario{"checkerboard_room", -1, 0.0, false, false, true, false},
                      Scenario{"corridor", +1, 0.3, false, false, true, true},
                      Scenario{"checkerboard_room", -1, 0.3, false, false, true, false},
                      Scenario{"corridor", +1, 0.0, false, false, false, false},
                      Scenario{"corridor", +1, 0.0, true, false, true, false}),
    Name);

}  // namespace
}  // namespace mostar::vision
