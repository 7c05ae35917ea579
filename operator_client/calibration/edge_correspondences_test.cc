#include "operator_client/calibration/edge_correspondences.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mostar::calibration {
namespace {

constexpr double kHeight = 0.35;

// 181 beams over 180 degrees; a straight wall 3 m ahead for |angle| < 40 degrees, no echo
// elsewhere.
LaserScan WallScan() {
  LaserScan scan;
  scan.angle_min_rad = static_cast<float>(-M_PI / 2);
  scan.angle_increment_rad = static_cast<float>(M_PI / 180);
  scan.range_min_m = 0.1f;
  scan.range_max_m = 8.0f;
  for (int i = 0; i < 181; ++i) {
    const double a = scan.angle_min_rad + i * scan.angle_increment_rad;
    scan.ranges_m.push_back(std::abs(a) < 40 * M_PI / 180 ? static_cast<float>(3.0 / std::cos(a))
                                                          : NAN);
  }
  return scan;
}

// Every beam with a range agrees; the left eye's NEPs at the laser range, none in the right.
vision::VisionResult AgreeingResult(const LaserScan& scan) {
  vision::VisionResult result;
  result.ok = true;
  result.stamp = FromUnixNanos(1'000'000'000);
  const size_t n = scan.ranges_m.size();
  result.classification.beams.resize(n);
  result.left_ned.neps.resize(n);
  result.right_ned.neps.resize(n);
  for (size_t i = 0; i < n; ++i) {
    if (!LaserScan::IsValidRange(scan.ranges_m[i])) continue;
    result.classification.beams[i].relation = vision::NepRelation::kAgrees;
    vision::Nep& nep = result.left_ned.neps[i];
    nep.found = true;
    nep.distance_m = scan.ranges_m[i];
    nep.metres_per_px = 0.01;
    nep.pixel = Eigen::Vector2d(static_cast<double>(i), 200.0);
  }
  return result;
}

TEST(EdgeCorrespondencesTest, AgreeingNepsOnAStraightBaseLineBecomeCorrespondences) {
  const LaserScan scan = WallScan();
  vision::VisionResult result = AgreeingResult(scan);
  // Beam 90 (straight ahead): its left NEP is 0.5 m nearer than the laser: no correspondence.
  result.left_ned.neps[90].distance_m -= 0.5;
  const std::vector<EdgeCorrespondence> out =
      ExtractCorrespondences(result, scan, vision::NepClassifierOptions{}, kHeight, {});
  // Beams whose three neighbours on each side have ranges, but beam 90; none of them sees the
  // wall within 20 deg of end-on.
  size_t expected = 0;
  for (size_t i = 3; i + 3 < scan.ranges_m.size(); ++i) {
    bool line = i != 90;
    for (size_t j = i - 3; j <= i + 3; ++j) line &= LaserScan::IsValidRange(scan.ranges_m[j]);
    expected += line ? 1 : 0;
  }
  EXPECT_GT(expected, 60u);
  EXPECT_EQ(out.size(), expected);
  for (const EdgeCorrespondence& c : out) {
    EXPECT_EQ(c.eye, Eye::kLeft);
    EXPECT_NEAR(c.base_laser.x(), 3.0, 1e-5);
    EXPECT_NEAR(c.base_laser.z(), -kHeight, 1e-12);
    EXPECT_NEAR(std::abs(c.direction_laser.y()), 1.0, 1e-6);
    EXPECT_EQ(c.stamp, result.stamp);
    EXPECT_NE(c.pixel.x(), 90.0);
  }
}

TEST(EdgeCorrespondencesTest, CornersAndBadInputGiveNone) {
  LaserScan scan = WallScan();
  // Step the wall at beam 90: beams 87..92 have neighbours on both sides of the step.
  for (int i = 90; i < 181; ++i) {
    if (LaserScan::IsValidRange(scan.ranges_m[i])) scan.ranges_m[i] *= 0.8f;
  }
  vision::VisionResult result = AgreeingResult(scan);
  for (size_t i = 0; i < scan.ranges_m.size(); ++i)
    result.left_ned.neps[i].distance_m = scan.ranges_m[i];
  const std::vector<EdgeCorrespondence> out =
      ExtractCorrespondences(result, scan, vision::NepClassifierOptions{}, kHeight, {});
  EXPECT_GT(out.size(), 50u);
  for (const EdgeCorrespondence& c : out) {
    EXPECT_TRUE(c.pixel.x() < 87.0 || c.pixel.x() > 92.0) << c.pixel.x();
  }
  result.ok = false;
  EXPECT_TRUE(
      ExtractCorrespondences(result, scan, vision::NepClassifierOptions{}, kHeight, {}).empty());
  result.ok = true;
  result.classification.beams.pop_back();
  EXPECT_TRUE(
      ExtractCorrespondences(result, scan, vision::NepClassifierOptions{}, kHeight, {}).empty());
  CorrespondenceOptions bad;
  bad.line_half_beams = 0;
  EXPECT_FALSE(bad.IsValid(nullptr));
}

TEST(CorrespondenceWindowTest, KeepsTheNewestWithinCapacityAndAge) {
  CorrespondenceWindow window(5, std::chrono::seconds(10));
  const Time t0 = FromUnixNanos(1'000'000'000'000);
  std::vector<EdgeCorrespondence> batch(3);
  for (auto& c : batch) c.stamp = t0;
  window.Add(batch);
  EXPECT_EQ(window.size(), 3u);
  for (auto& c : batch) c.stamp = t0 + std::chrono::seconds(5);
  window.Add(batch);
  EXPECT_EQ(window.size(), 5u);  // capacity
  EXPECT_EQ(window.Snapshot().front().stamp, t0);
  for (auto& c : batch) c.stamp = t0 + std::chrono::seconds(12);
  window.Add(batch);  // t0 is now 12 s old
  for (const EdgeCorrespondence& c : window.Snapshot()) EXPECT_GT(c.stamp, t0);
  window.Clear();
  EXPECT_EQ(window.size(), 0u);
}

}  // namespace
}  // namespace mostar::calibration
