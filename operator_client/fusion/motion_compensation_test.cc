#include "operator_client/fusion/motion_compensation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "operator_client/fusion/ar_features.h"

namespace mostar::fusion {
namespace {

const Time kT0 = FromUnixNanos(1'700'000'000'000'000'000);
constexpr Duration kOdometryPeriod = std::chrono::milliseconds(20);

// The pose of a robot that left the origin at kT0 with constant (v, w): odom_from_base at t.
Pose2D ArcPose(double v_mps, double w_radps, Time t) {
  const double s = ToSeconds(t - kT0);
  const double th = w_radps * s;
  if (std::abs(w_radps) < 1e-12) return Pose2D{v_mps * s, 0.0, 0.0};
  const double r = v_mps / w_radps;
  return Pose2D{r * std::sin(th), r * (1.0 - std::cos(th)), th};
}

Odometry ArcOdometry(double v_mps, double w_radps, Time t) {
  Odometry o;
  o.stamp = t;
  o.pose = ArcPose(v_mps, w_radps, t);
  o.linear_mps = v_mps;
  o.angular_radps = w_radps;
  return o;
}

// Odometry at 50 Hz from `from` to `to` (inclusive) of the constant-twist robot.
OdometryHistory ArcHistory(double v_mps, double w_radps, Time from, Time to) {
  OdometryHistory history(256);
  for (Time t = from; t <= to; t += kOdometryPeriod) history.Add(ArcOdometry(v_mps, w_radps, t));
  return history;
}

// A scan with every beam at `range_m`, 181 beams over 180 deg, the LMS200's beam timing.
LaserScan UniformScan(Time stamp, float range_m) {
  LaserScan scan;
  scan.stamp = stamp;
  scan.angle_min_rad = static_cast<float>(-M_PI / 2);
  scan.angle_increment_rad = static_cast<float>(M_PI / 180);
  scan.time_increment_s = static_cast<float>(0.01332 / 360);
  scan.ranges_m.assign(181, range_m);
  return scan;
}

// Where a world point fixed in the odom frame lies in the base frame at `t`.
PlanarPoint InBaseAt(double v, double w, Time t, double odom_x, double odom_y) {
  const Pose2D base_from_odom = Inverse(ArcPose(v, w, t));
  const double c = std::cos(base_from_odom.theta_rad);
  const double s = std::sin(base_from_odom.theta_rad);
  return PlanarPoint{static_cast<float>(base_from_odom.x_m + c * odom_x - s * odom_y),
                     static_cast<float>(base_from_odom.y_m + s * odom_x + c * odom_y)};
}

// Checks every moved beam of `scan` against the truth: the beam measured at its own time
// (a point fixed in the odom frame) seen from the base at `image`.
void ExpectMovedToTruth(double v, double w, const LaserScan& scan, Time image, const MovedScan& m,
                        double tolerance_m) {
  ASSERT_TRUE(m.moved) << m.reason;
  ASSERT_EQ(m.points.size(), scan.ranges_m.size());
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const Time beam = scan.stamp + FromSeconds(scan.time_increment_s * static_cast<double>(i));
    const Pose2D odom_from_beam = ArcPose(v, w, beam);
    const double r = scan.ranges_m[i];
    const double a = scan.AngleOf(i);
    const Pose2D in_odom = Compose(odom_from_beam, Pose2D{r * std::cos(a), r * std::sin(a), 0});
    const PlanarPoint truth = InBaseAt(v, w, image, in_odom.x_m, in_odom.y_m);
    EXPECT_NEAR(m.points[i].x_m, truth.x_m, tolerance_m) << "beam " << i;
    EXPECT_NEAR(m.points[i].y_m, truth.y_m, tolerance_m) << "beam " << i;
  }
}

TEST(Se2Test, ComposeWithInverseIsIdentity) {
  const Pose2D p{1.5, -0.25, 2.5};
  const Pose2D e = Compose(p, Inverse(p));
  EXPECT_NEAR(e.x_m, 0, 1e-12);
  EXPECT_NEAR(e.y_m, 0, 1e-12);
  EXPECT_NEAR(WrapAngle(e.theta_rad), 0, 1e-12);
}

TEST(Se2Test, InterpolationFollowsTheConstantTwistArc) {
  for (const double w : {0.0, 0.5, -1.2, 3.0}) {
    const Time a = kT0 + std::chrono::milliseconds(100);
    const Time b = a + std::chrono::milliseconds(500);
    for (const double s : {0.0, 0.25, 0.5, 1.0, 1.2}) {
      const Pose2D p = InterpolatePose(ArcPose(0.5, w, a), ArcPose(0.5, w, b), s);
      const Pose2D truth = ArcPose(0.5, w, a + FromSeconds(0.5 * s));
      EXPECT_NEAR(p.x_m, truth.x_m, 1e-9) << "w " << w << " s " << s;
      EXPECT_NEAR(p.y_m, truth.y_m, 1e-9) << "w " << w << " s " << s;
      EXPECT_NEAR(WrapAngle(p.theta_rad - truth.theta_rad), 0, 1e-9) << "w " << w << " s " << s;
    }
  }
}

TEST(Se2Test, InterpolationTakesTheShortWayAcrossPi) {
  const Pose2D p = InterpolatePose(Pose2D{0, 0, M_PI - 0.1}, Pose2D{0, 0, -M_PI + 0.1}, 0.5);
  EXPECT_NEAR(std::abs(WrapAngle(p.theta_rad)), M_PI, 1e-9);
}

// Options with the arc interpolation alone (no smoothing).
MotionCompensationOptions Interpolating() {
  MotionCompensationOptions options;
  options.smoothing_window = Duration::zero();
  return options;
}

TEST(OdometryHistoryTest, InterpolatesBetweenSamplesAndRefusesGaps) {
  const MotionCompensationOptions options = Interpolating();
  OdometryHistory history(8);
  PoseCoverage coverage;
  history.PoseAt(kT0, options, &coverage);
  EXPECT_EQ(coverage, PoseCoverage::kNotCovered);  // empty

  history.Add(ArcOdometry(1.0, 0.0, kT0));
  history.Add(ArcOdometry(1.0, 0.0, kT0 + std::chrono::milliseconds(20)));
  history.Add(ArcOdometry(1.0, 0.0, kT0 + std::chrono::milliseconds(300)));  // 280 ms gap
  Pose2D p = history.PoseAt(kT0 + std::chrono::milliseconds(5), options, &coverage);
  EXPECT_EQ(coverage, PoseCoverage::kInterpolated);
  EXPECT_NEAR(p.x_m, 0.005, 1e-9);
  history.PoseAt(kT0 + std::chrono::milliseconds(100), options, &coverage);
  EXPECT_EQ(coverage, PoseCoverage::kNotCovered);
  p = history.PoseAt(kT0 + std::chrono::milliseconds(300), options, &coverage);
  EXPECT_EQ(coverage, PoseCoverage::kInterpolated);
  EXPECT_NEAR(p.x_m, 0.3, 1e-9);
}

TEST(OdometryHistoryTest, ExtrapolationIsBounded) {
  MotionCompensationOptions options = Interpolating();
  options.max_extrapolation = std::chrono::milliseconds(60);
  OdometryHistory history(8);
  history.Add(ArcOdometry(0.5, 0.5, kT0));
  history.Add(ArcOdometry(0.5, 0.5, kT0 + kOdometryPeriod));
  PoseCoverage coverage;
  const Time later = kT0 + kOdometryPeriod + std::chrono::milliseconds(50);
  const Pose2D p = history.PoseAt(later, options, &coverage);
  EXPECT_EQ(coverage, PoseCoverage::kExtrapolated);
  const Pose2D truth = ArcPose(0.5, 0.5, later);
  EXPECT_NEAR(p.x_m, truth.x_m, 1e-9);
  EXPECT_NEAR(p.theta_rad, truth.theta_rad, 1e-9);
  history.PoseAt(kT0 - std::chrono::milliseconds(50), options, &coverage);
  EXPECT_EQ(coverage, PoseCoverage::kExtrapolated);
  history.PoseAt(later + std::chrono::milliseconds(20), options, &coverage);
  EXPECT_EQ(coverage, PoseCoverage::kNotCovered);
  history.PoseAt(kT0 - std::chrono::milliseconds(61), options, &coverage);
  EXPECT_EQ(coverage, PoseCoverage::kNotCovered);
}

TEST(OdometryHistoryTest, OutOfOrderAndDuplicateSamplesKeepStampOrder) {
  const MotionCompensationOptions options = Interpolating();
  OdometryHistory history(8);
  history.Add(ArcOdometry(1.0, 0.0, kT0 + std::chrono::milliseconds(40)));
  history.Add(ArcOdometry(1.0, 0.0, kT0));
  history.Add(ArcOdometry(1.0, 0.0, kT0 + std::chrono::milliseconds(20)));
  Odometry duplicate = ArcOdometry(1.0, 0.0, kT0 + std::chrono::milliseconds(20));
  duplicate.pose.x_m = 0.03;  // a corrected sample with the same stamp replaces the first
  history.Add(duplicate);
  EXPECT_EQ(history.size(), 3u);
  EXPECT_EQ(history.oldest().stamp, kT0);
  EXPECT_EQ(history.newest().stamp, kT0 + std::chrono::milliseconds(40));
  PoseCoverage coverage;
  const Pose2D p = history.PoseAt(kT0 + std::chrono::milliseconds(10), options, &coverage);
  EXPECT_EQ(coverage, PoseCoverage::kInterpolated);
  EXPECT_NEAR(p.x_m, 0.015, 1e-9);  // halfway to the replacement
}

TEST(OdometryHistoryTest, SmoothingIsExactForConstantVelocityAndEvensOutTicks) {
  const MotionCompensationOptions plain = Interpolating();
  MotionCompensationOptions smooth;
  smooth.smoothing_window = std::chrono::milliseconds(60);
  const double w = 0.5;
  constexpr double kTickRad = 0.0022;  // heading in whole ticks, as encoders give it
  OdometryHistory exact(256);
  OdometryHistory ticks(256);
  for (Time t = kT0; t <= kT0 + std::chrono::seconds(2); t += kOdometryPeriod) {
    Odometry o = ArcOdometry(0.0, w, t);
    exact.Add(o);
    o.pose.theta_rad = std::round(o.pose.theta_rad / kTickRad) * kTickRad;
    ticks.Add(o);
  }
  double plain_sq = 0, smooth_sq = 0;
  PoseCoverage coverage;
  for (int k = 0; k < 200; ++k) {
    const Time a = kT0 + std::chrono::milliseconds(300) + k * std::chrono::milliseconds(7);
    const Time b = a + std::chrono::milliseconds(50);
    const double truth = w * 0.05;
    const double e =
        exact.PoseAt(b, smooth, &coverage).theta_rad - exact.PoseAt(a, smooth, &coverage).theta_rad;
    ASSERT_EQ(coverage, PoseCoverage::kInterpolated);
    EXPECT_NEAR(e, truth, 1e-9);
    const double p =
        ticks.PoseAt(b, plain, &coverage).theta_rad - ticks.PoseAt(a, plain, &coverage).theta_rad;
    const double s =
        ticks.PoseAt(b, smooth, &coverage).theta_rad - ticks.PoseAt(a, smooth, &coverage).theta_rad;
    plain_sq += (p - truth) * (p - truth);
    smooth_sq += (s - truth) * (s - truth);
  }
  const double plain_rms = std::sqrt(plain_sq / 200);
  const double smooth_rms = std::sqrt(smooth_sq / 200);
  EXPECT_GT(plain_rms, 0.25 * kTickRad);
  EXPECT_LT(smooth_rms, 0.7 * plain_rms);
}

TEST(OdometryHistoryTest, MemoryIsBounded) {
  OdometryHistory history(16);
  for (int i = 0; i < 1000; ++i) {
    history.Add(ArcOdometry(1.0, 0.0, kT0 + i * kOdometryPeriod));
    ASSERT_LE(history.size(), 16u);
  }
  EXPECT_EQ(history.oldest().stamp, kT0 + 984 * kOdometryPeriod);
  // Older than everything held, when full: dropped.
  history.Add(ArcOdometry(1.0, 0.0, kT0));
  EXPECT_EQ(history.size(), 16u);
  EXPECT_EQ(history.oldest().stamp, kT0 + 984 * kOdometryPeriod);
  // Out of order inside the window, when full: kept, the oldest goes.
  history.Add(ArcOdometry(1.0, 0.0, kT0 + 990 * kOdometryPeriod + std::chrono::milliseconds(1)));
  EXPECT_EQ(history.size(), 16u);
  EXPECT_EQ(history.oldest().stamp, kT0 + 985 * kOdometryPeriod);
  EXPECT_EQ(history.dropped(), 984u + 2u);
}

TEST(MoveScanTest, PureRotationTurnsThePointsBack) {
  const double w = 0.5;
  const Time scan_time = kT0 + std::chrono::milliseconds(200);
  const Time image = scan_time + std::chrono::milliseconds(50);
  const OdometryHistory history = ArcHistory(0.0, w, kT0, kT0 + std::chrono::seconds(1));
  LaserScan scan = UniformScan(scan_time, 2.0f);
  scan.time_increment_s = 0;  // all beams at the stamp: a rigid rotation
  MovedScan moved;
  MoveScanToImageTime(scan, image, history, {}, &moved);
  ASSERT_TRUE(moved.moved) << moved.reason;
  EXPECT_FALSE(moved.extrapolated);
  EXPECT_EQ(moved.image_minus_scan, std::chrono::milliseconds(50));
  // The robot turned 25 mrad left: every point appears 25 mrad further right, same distance.
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const double angle = std::atan2(moved.points[i].y_m, moved.points[i].x_m);
    EXPECT_NEAR(WrapAngle(angle - scan.AngleOf(i) + w * 0.05), 0, 1e-5) << i;
    EXPECT_NEAR(std::hypot(moved.points[i].x_m, moved.points[i].y_m), 2.0, 1e-5) << i;
  }
  ExpectMovedToTruth(0.0, w, scan, image, moved, 1e-5);
}

TEST(MoveScanTest, PureTranslationMovesThePointsTowardsTheRobot) {
  const double v = 0.5;
  const Time scan_time = kT0 + std::chrono::milliseconds(200);
  const Time image = scan_time + std::chrono::milliseconds(100);
  const OdometryHistory history = ArcHistory(v, 0.0, kT0, kT0 + std::chrono::seconds(1));
  LaserScan scan = UniformScan(scan_time, 2.0f);
  scan.time_increment_s = 0;
  MovedScan moved;
  MoveScanToImageTime(scan, image, history, {}, &moved);
  ASSERT_TRUE(moved.moved) << moved.reason;
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const float a = scan.AngleOf(i);
    EXPECT_NEAR(moved.points[i].x_m, 2.0 * std::cos(a) - 0.05, 1e-5) << i;
    EXPECT_NEAR(moved.points[i].y_m, 2.0 * std::sin(a), 1e-5) << i;
  }
}

TEST(MoveScanTest, EachBeamIsDeskewedByItsOwnTime) {
  const double v = 0.5;
  const double w = 0.5;
  const Time scan_time = kT0 + std::chrono::milliseconds(203);  // between odometry samples
  const OdometryHistory history = ArcHistory(v, w, kT0, kT0 + std::chrono::seconds(1));
  const LaserScan scan = UniformScan(scan_time, 3.0f);
  // At the scan's own stamp: the first beam does not move, the last has moved by the sweep.
  MovedScan moved;
  MoveScanToImageTime(scan, scan_time, history, {}, &moved);
  ExpectMovedToTruth(v, w, scan, scan_time, moved, 2e-5);
  EXPECT_NEAR(moved.points[0].y_m, -3.0, 1e-5);
  const double sweep_s = 180 * 0.01332 / 360;
  const double last_angle = std::atan2(moved.points[180].y_m, moved.points[180].x_m);
  // Since the first beam the robot turned left by w * sweep (the point lies further left seen
  // from the first beam's pose) and drove v * sweep ahead (the point 3 m left lies a little
  // behind that).
  EXPECT_NEAR(last_angle - M_PI / 2, w * sweep_s - v * sweep_s / 3.0, 1e-5);
  // Later images, and with the skew ignored the far beams miss by millimetres.
  const Time image = scan_time + std::chrono::milliseconds(37);
  MoveScanToImageTime(scan, image, history, {}, &moved);
  ExpectMovedToTruth(v, w, scan, image, moved, 2e-5);
  LaserScan unskewed = scan;
  unskewed.time_increment_s = 0;
  MovedScan rigid;
  MoveScanToImageTime(unskewed, image, history, {}, &rigid);
  const double miss = std::hypot(rigid.points[180].x_m - moved.points[180].x_m,
                                 rigid.points[180].y_m - moved.points[180].y_m);
  EXPECT_GT(miss, 0.5 * 3.0 * w * sweep_s);
}

TEST(MoveScanTest, GapNotCoveredLeavesTheScanAsMeasured) {
  const Time scan_time = kT0 + std::chrono::milliseconds(200);
  LaserScan scan = UniformScan(scan_time, 2.0f);
  MovedScan moved;
  // No odometry at all.
  MoveScanToImageTime(scan, scan_time + std::chrono::milliseconds(30), OdometryHistory(4), {},
                      &moved);
  EXPECT_FALSE(moved.moved);
  EXPECT_EQ(moved.reason, "no odometry");
  ASSERT_EQ(moved.points.size(), 181u);
  EXPECT_NEAR(moved.points[90].x_m, 2.0, 1e-6);
  // Odometry stopped 300 ms before the image.
  const OdometryHistory old = ArcHistory(0.5, 0.5, kT0, scan_time);
  MoveScanToImageTime(scan, scan_time + std::chrono::milliseconds(300), old, {}, &moved);
  EXPECT_FALSE(moved.moved);
  EXPECT_NEAR(moved.points[90].x_m, 2.0, 1e-6);
  EXPECT_NEAR(moved.points[90].y_m, 0.0, 1e-6);
  // Odometry starts after the scan (the client just started).
  const OdometryHistory recent = ArcHistory(0.5, 0.5, scan_time + std::chrono::milliseconds(200),
                                            kT0 + std::chrono::seconds(1));
  MoveScanToImageTime(scan, scan_time + std::chrono::milliseconds(250), recent, {}, &moved);
  EXPECT_FALSE(moved.moved);
  EXPECT_EQ(moved.reason, "no odometry at the scan time");
  // A scan older than max_scan_age.
  const OdometryHistory full = ArcHistory(0.5, 0.5, kT0, kT0 + std::chrono::seconds(4));
  MoveScanToImageTime(scan, scan_time + std::chrono::milliseconds(600), full, {}, &moved);
  EXPECT_FALSE(moved.moved);
  // The image just after the newest sample: extrapolated within the bound.
  MoveScanToImageTime(scan, scan_time + std::chrono::milliseconds(10), old, {}, &moved);
  EXPECT_TRUE(moved.moved) << moved.reason;
  EXPECT_TRUE(moved.extrapolated);
}

TEST(MoveScanTest, InvalidBeamsStayAtTheOrigin) {
  const Time scan_time = kT0 + std::chrono::milliseconds(200);
  const OdometryHistory history = ArcHistory(0.5, 0.5, kT0, kT0 + std::chrono::seconds(1));
  LaserScan scan = UniformScan(scan_time, 2.0f);
  scan.ranges_m[3] = NAN;
  scan.ranges_m[4] = INFINITY;
  MovedScan moved;
  MoveScanToImageTime(scan, scan_time + std::chrono::milliseconds(40), history, {}, &moved);
  ASSERT_TRUE(moved.moved);
  EXPECT_EQ(moved.points[3].x_m, 0.f);
  EXPECT_EQ(moved.points[4].y_m, 0.f);
}

TEST(ArFeaturesMovedTest, WallsAndLabelsFollowTheMovedPoints) {
  const ArFeatureBuilder builder{ArFeatureOptions{}};
  const LaserScan scan = UniformScan(kT0, 2.0f);
  std::vector<PlanarPoint> shifted(scan.ranges_m.size());
  for (size_t i = 0; i < shifted.size(); ++i) {
    const float a = scan.AngleOf(i);
    shifted[i] = PlanarPoint{2.0f * std::cos(a) - 0.25f, 2.0f * std::sin(a)};
  }
  ArFeatures plain;
  ArFeatures moved;
  builder.Build(scan, &plain);
  builder.Build(scan, shifted, &moved);
  ASSERT_EQ(plain.walls.positions.size(), moved.walls.positions.size());
  ASSERT_FALSE(moved.walls.empty());
  for (size_t v = 0; v < moved.walls.vertex_count(); ++v) {
    EXPECT_NEAR(moved.walls.positions[3 * v], plain.walls.positions[3 * v] - 0.25f, 1e-5);
    EXPECT_FLOAT_EQ(moved.walls.colors[4 * v + 3], plain.walls.colors[4 * v + 3]);
  }
  ASSERT_FALSE(moved.labels.empty());
  EXPECT_NEAR(moved.labels[0].anchor_x_m, plain.labels[0].anchor_x_m - 0.25f, 1e-5);
  EXPECT_EQ(moved.labels[0].text, plain.labels[0].text);  // the measured distance
}

}  // namespace
}  // namespace mostar::fusion
