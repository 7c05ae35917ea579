#include "operator_client/calibration/calibration_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace mostar::calibration {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A rig like the simulator's: 640x480, f 440 px, mild barrel distortion.
math::LaserCameraCalibration TrueCalibration() {
  math::LaserCameraCalibration c;
  c.focal_px = 440.0;
  c.distortion.k1 = -0.05;
  c.camera_y_m = 0.55;
  c.camera_z_m = -0.10;
  c.tilt_rad = 12.0 * kDeg;
  c.laser_height_m = 0.35;
  return c;
}

// The issue's perturbed start: f +10 %, tilt +2 deg, y -3 cm, pan +1 deg.
math::LaserCameraCalibration Perturbed(const math::LaserCameraCalibration& truth) {
  math::LaserCameraCalibration c = truth;
  c.focal_px *= 1.10;
  c.tilt_rad += 2.0 * kDeg;
  c.camera_y_m -= 0.03;
  c.pan_rad += 1.0 * kDeg;
  return c;
}

struct Wall {
  Eigen::Vector2d a;  // floor segment, laser frame
  Eigen::Vector2d b;
};

// Base points of walls around the robot as both eyes see them with `truth`: the NEP pixel is
// the true image of a base point slid up to 5 cm along the wall (NEPs lie anywhere on the
// edge), plus `noise_px` of pixel noise. `wrong_fraction` of them are moved 3 to 20 px in a
// random direction (NEPs on other edges that still agree with the laser), or straight down when
// `wrong_down` (edges on the floor in front of the base: shadows, tile joints).
std::vector<EdgeCorrespondence> Synthesize(const math::LaserCameraCalibration& truth,
                                           const std::vector<Wall>& walls, int per_wall,
                                           double noise_px, double wrong_fraction, uint32_t seed,
                                           bool wrong_down = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  const math::CameraModel eyes[2] = {math::CameraModel(truth, Eye::kLeft),
                                     math::CameraModel(truth, Eye::kRight)};
  std::vector<EdgeCorrespondence> out;
  for (const Wall& w : walls) {
    const Eigen::Vector2d d = (w.b - w.a).normalized();
    for (int k = 0; k < per_wall; ++k) {
      const Eigen::Vector2d p = w.a + (w.b - w.a) * unit(rng);
      for (int e = 0; e < 2; ++e) {
        EdgeCorrespondence c;
        c.eye = e == 0 ? Eye::kLeft : Eye::kRight;
        c.base_laser = Eigen::Vector3d(p.x(), p.y(), -truth.laser_height_m);
        c.direction_laser = Eigen::Vector3d(d.x(), d.y(), 0.0);
        const double slide = 0.05 * (2.0 * unit(rng) - 1.0);
        const std::optional<Eigen::Vector2d> px =
            eyes[e].Project(c.base_laser + slide * c.direction_laser);
        if (!px || !eyes[e].IsInImage(*px)) continue;
        c.pixel = *px + Eigen::Vector2d(noise(rng), noise(rng));
        if (unit(rng) < wrong_fraction) {
          const double angle = wrong_down ? M_PI / 2 : 2.0 * M_PI * unit(rng);
          const double shift = 3.0 + 17.0 * unit(rng);
          c.pixel += shift * Eigen::Vector2d(std::cos(angle), std::sin(angle));
        }
        out.push_back(c);
      }
    }
  }
  return out;
}

// A room: a wall ahead, two side walls, a diagonal box face.
std::vector<Wall> Room() {
  return {{{3.5, 2.0}, {3.5, -2.0}},
          {{0.8, 1.1}, {5.0, 1.1}},
          {{0.8, -1.1}, {5.0, -1.1}},
          {{1.6, 0.2}, {2.0, -0.5}}};
}

// Both eyes from the perturbed start, points of `walls` seen with the truth.
FitInput PerturbedInput(const std::vector<Wall>& walls, int per_wall, double wrong_fraction,
                        uint32_t seed) {
  FitInput input;
  input.left = Perturbed(TrueCalibration());
  input.right = input.left;
  input.points = Synthesize(TrueCalibration(), walls, per_wall, 0.3, wrong_fraction, seed);
  return input;
}

// Fits `input` with the default options and checks the proposal is trustworthy and within the
// issue's tolerances of the truth.
FitResult FitWithinIssueTolerances(const FitInput& input) {
  const math::LaserCameraCalibration truth = TrueCalibration();
  const FitResult result = FitCalibration(input, FitOptions{});
  EXPECT_TRUE(result.ok && result.trustworthy) << result.reason;
  EXPECT_NEAR(result.proposal.focal_px / truth.focal_px, 1.0, 0.01);
  EXPECT_NEAR(result.proposal.tilt_rad, truth.tilt_rad, 0.2 * kDeg);
  EXPECT_NEAR(result.proposal.camera_y_m, truth.camera_y_m, 0.005);
  EXPECT_NEAR(result.proposal.pan_rad, truth.pan_rad, 0.2 * kDeg);
  return result;
}

TEST(CalibrationFitTest, RecoversAKnownPerturbation) {
  const FitInput input = PerturbedInput(Room(), 150, 0.0, 1);
  const FitResult result = FitWithinIssueTolerances(input);
  EXPECT_GT(result.before.p50_px, 2.0);
  EXPECT_LT(result.after.p95_px, 1.0);
  EXPECT_EQ(result.points, input.points.size());
  EXPECT_GT(result.inliers, 0.9 * input.points.size());
  EXPECT_GT(result.sigma[kTilt], 0.0);
  EXPECT_LT(result.sigma[kTilt], 0.1 * kDeg);
}

TEST(CalibrationFitTest, ThirtyPercentWrongCorrespondencesStayWithinTolerance) {
  const FitInput input = PerturbedInput(Room(), 150, 0.3, 2);
  const FitResult result = FitWithinIssueTolerances(input);
  // Wrong points that happen to lie within inlier_px of the line count as inliers: the p95
  // includes them; the median does not.
  EXPECT_LT(result.after.p50_px, 0.6);
  EXPECT_LT(result.inliers, 0.85 * input.points.size());  // most wrong ones do not fit
}

TEST(CalibrationFitTest, WrongCorrespondencesOnOneSideNeedTheRobustLoss) {
  // 30 % of the NEPs 3 to 20 px below their base (edges on the floor in front of it): the robust
  // fit stays within tolerance, least squares (a loss scale of 10^4 px) is pulled away.
  FitInput input = PerturbedInput(Room(), 150, 0.0, 2);
  input.points = Synthesize(TrueCalibration(), Room(), 150, 0.3, 0.3, 2, /*wrong_down=*/true);
  FitWithinIssueTolerances(input);
  FitOptions least_squares;
  least_squares.coarse_loss_px = 1e4;
  least_squares.loss_px = 1e4;
  const FitResult result = FitCalibration(input, least_squares);
  ASSERT_TRUE(result.ok) << result.reason;
  const math::LaserCameraCalibration truth = TrueCalibration();
  const double focal_error = std::abs(result.proposal.focal_px / truth.focal_px - 1.0);
  const double tilt_error = std::abs(result.proposal.tilt_rad - truth.tilt_rad);
  EXPECT_TRUE(focal_error > 0.01 || tilt_error > 0.2 * kDeg)
      << focal_error << " " << tilt_error / kDeg;
}

TEST(CalibrationFitTest, RefusesTooFewPoints) {
  const math::LaserCameraCalibration truth = TrueCalibration();
  FitInput input;
  input.left = Perturbed(truth);
  input.points = Synthesize(truth, Room(), 5, 0.3, 0.0, 3);
  const FitResult result = FitCalibration(input, FitOptions{});
  EXPECT_FALSE(result.ok);
  EXPECT_FALSE(result.trustworthy);
  EXPECT_NE(result.reason.find("too few correspondences"), std::string::npos) << result.reason;
}

TEST(CalibrationFitTest, OneWallAheadDoesNotDetermineEveryParameter) {
  // Points of a single straight wall: a line fixes two parameters, not seven.
  const FitInput input = PerturbedInput({{{3.0, 1.5}, {3.0, -1.5}}}, 300, 0.0, 4);
  const FitResult result = FitCalibration(input, FitOptions{});
  EXPECT_FALSE(result.trustworthy);
  EXPECT_FALSE(result.reason.empty());
}

TEST(CalibrationFitTest, RecoversAKnownPerturbationWithEveryParameterFree) {
  const math::LaserCameraCalibration truth = TrueCalibration();
  FitInput input = PerturbedInput(Room(), 150, 0.0, 1);
  input.left.camera_z_m += 0.02;
  input.left.roll_rad += 0.5 * kDeg;
  input.right = input.left;
  FitOptions options;
  options.free.fill(true);
  const FitResult result = FitCalibration(input, options);
  ASSERT_TRUE(result.ok) << result.reason;
  EXPECT_NEAR(result.proposal.focal_px / truth.focal_px, 1.0, 0.01);
  EXPECT_NEAR(result.proposal.tilt_rad, truth.tilt_rad, 0.2 * kDeg);
  EXPECT_NEAR(result.proposal.camera_z_m, truth.camera_z_m, 0.01);
  EXPECT_NEAR(result.proposal.roll_rad, truth.roll_rad, 0.1 * kDeg);
}

TEST(CalibrationFitTest, FixedParametersKeepTheirValues) {
  const math::LaserCameraCalibration truth = TrueCalibration();
  FitInput input;
  input.left = Perturbed(truth);
  input.left.camera_x_m = 0.01;  // wrong, but held
  input.right = input.left;
  input.points = Synthesize(truth, Room(), 150, 0.3, 0.0, 5);
  FitOptions options;
  options.free[kCameraX] = false;
  options.free[kRoll] = false;
  const FitResult result = FitCalibration(input, options);
  ASSERT_TRUE(result.ok) << result.reason;
  EXPECT_EQ(result.proposal.camera_x_m, 0.01);
  EXPECT_EQ(result.proposal.roll_rad, input.left.roll_rad);
  EXPECT_EQ(result.sigma[kCameraX], 0.0);
}

TEST(CalibrationFitTest, InvalidInputIsRefusedWithAReason) {
  FitInput input;
  input.left.focal_px = -1.0;
  const FitResult result = FitCalibration(input, FitOptions{});
  EXPECT_FALSE(result.ok);
  EXPECT_NE(result.reason.find("focal_px"), std::string::npos) << result.reason;
  FitOptions options;
  options.loss_px = 0.0;
  EXPECT_FALSE(options.IsValid(nullptr));
  FitOptions none_free;
  none_free.free.fill(false);
  std::string why;
  EXPECT_FALSE(none_free.IsValid(&why));
  EXPECT_EQ(why, "no parameter is free");
  none_free.free[kRoll] = true;
  EXPECT_TRUE(none_free.IsValid(&why)) << why;
}

TEST(CalibrationFitTest, MoveParametersScalesFocalAndOffsetsTheRest) {
  math::LaserCameraCalibration base;
  base.focal_px = 1000.0;
  base.focal_y_px = 1010.0;
  base.tilt_rad = 0.1;
  ParameterVector from = ParametersOf(TrueCalibration());
  ParameterVector to = from;
  to[kFocal] *= 1.02;
  to[kTilt] += 0.01;
  to[kCameraY] -= 0.02;
  const math::LaserCameraCalibration moved = MoveParameters(base, from, to);
  EXPECT_NEAR(moved.focal_px, 1020.0, 1e-9);
  EXPECT_NEAR(*moved.focal_y_px, 1030.2, 1e-9);
  EXPECT_NEAR(moved.tilt_rad, 0.11, 1e-12);
  EXPECT_NEAR(moved.camera_y_m, base.camera_y_m - 0.02, 1e-12);
  EXPECT_EQ(moved.pan_rad, base.pan_rad);
}

}  // namespace
}  // namespace mostar::calibration
