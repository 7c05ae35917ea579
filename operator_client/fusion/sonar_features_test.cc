#include "operator_client/fusion/sonar_features.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "operator_client/fusion/color_scale.h"

namespace mostar::fusion {
namespace {

constexpr double kPi = 3.14159265358979323846;

SonarRange Sonar(double x, double y, double yaw, float range_m) {
  SonarRange r;
  r.mount.frame_id = "sonar";
  r.mount.x_m = x;
  r.mount.y_m = y;
  r.mount.yaw_rad = yaw;
  r.range_m = range_m;
  r.min_range_m = 0.03f;
  r.max_range_m = 6.0f;
  r.field_of_view_rad = 0.5f;
  return r;
}

ScanPointLabel LaserPoint(float x, float y) {
  ScanPointLabel p;
  p.x_m = x;
  p.y_m = y;
  p.range_m = std::hypot(x, y);
  p.valid = true;
  return p;
}

// The LMS200's 180 degrees ahead.
constexpr LaserFieldOfView kAhead{static_cast<float>(-kPi / 2), static_cast<float>(kPi / 2)};

SonarFeatures Build(const std::vector<SonarRange>& ranges, const std::vector<ScanPointLabel>& laser,
                    const SonarFeatureOptions& options = {}, const LaserFieldOfView& fov = kAhead) {
  SonarRanges ring;
  ring.ranges = ranges;
  SonarFeatures out;
  BuildSonarFeatures(ring, laser, fov, ArFeatureOptions{}, options, &out);
  return out;
}

TEST(SonarFeaturesTest, AnEchoTheLaserDoesNotSeeIsAHighlightedSectorOnTheFloor) {
  const SonarFeatureOptions options;
  const SonarFeatures f = Build({Sonar(0.2, 0.0, 0.0, 1.0f)}, {}, options);
  ASSERT_EQ(f.sectors.size(), 1u);
  EXPECT_TRUE(f.sectors[0].has_echo);
  EXPECT_TRUE(f.sectors[0].unseen_by_laser);
  EXPECT_EQ(f.echoes, 1u);
  EXPECT_EQ(f.unseen, 1u);
  EXPECT_EQ(f.fans.vertex_count(), 3u * options.arc_segments);
  EXPECT_EQ(f.outlines.vertex_count(), 2u * (2 + options.arc_segments));
  const ArFeatureOptions colors;
  for (size_t v = 0; v < f.fans.vertex_count(); ++v) {
    const float x = f.fans.positions[3 * v];
    const float y = f.fans.positions[3 * v + 1];
    EXPECT_FLOAT_EQ(f.fans.positions[3 * v + 2], -colors.laser_height_m);
    const double from_mount = std::hypot(x - 0.2, y);
    EXPECT_LE(from_mount, 1.0 + 1e-5);
    if (from_mount > 1e-6) {
      EXPECT_NEAR(from_mount, 1.0, 1e-5);
      EXPECT_LE(std::abs(std::atan2(y, x - 0.2)), 0.25 + 1e-5);
    }
    EXPECT_FLOAT_EQ(f.fans.colors[4 * v + 3], options.unseen_alpha);
  }
  const Rgba expected = DistanceColor(1.0f, colors.min_distance_m, colors.max_distance_m);
  EXPECT_FLOAT_EQ(f.sectors[0].color.r, expected.r);
  EXPECT_FLOAT_EQ(f.sectors[0].color.g, expected.g);
  EXPECT_FLOAT_EQ(f.fans.colors[0], expected.r);
  EXPECT_FLOAT_EQ(f.outlines.colors[0], options.unseen_outline.r);
  EXPECT_FLOAT_EQ(f.outlines.colors[2], options.unseen_outline.b);
}

TEST(SonarFeaturesTest, AnEchoTheLaserAgreesWithIsAPlainSector) {
  const SonarFeatureOptions options;
  // The wall 1.1 m ahead of the sonar: the laser point lies in the cone, within the margin.
  const SonarFeatures f = Build({Sonar(0.2, 0.0, 0.0, 1.0f)}, {LaserPoint(1.3f, 0.05f)}, options);
  ASSERT_EQ(f.sectors.size(), 1u);
  EXPECT_FALSE(f.sectors[0].unseen_by_laser);
  EXPECT_EQ(f.unseen, 0u);
  EXPECT_TRUE(f.outlines.empty());
  EXPECT_FLOAT_EQ(f.fans.colors[3], options.sector_alpha);
}

TEST(SonarFeaturesTest, TheLaserSeeingThroughGlassOrBesideTheConeDoesNotAgree) {
  // Through the glass: the laser's point lies 3 m behind the sonar's echo at 1 m.
  EXPECT_TRUE(
      Build({Sonar(0.2, 0.0, 0.0, 1.0f)}, {LaserPoint(4.2f, 0.0f)}).sectors[0].unseen_by_laser);
  // Beside the cone: near enough but 45 degrees off the sonar's axis (half cone 14 degrees).
  EXPECT_TRUE(
      Build({Sonar(0.2, 0.0, 0.0, 1.0f)}, {LaserPoint(0.9f, 0.7f)}).sectors[0].unseen_by_laser);
  // Invalid laser points never agree.
  ScanPointLabel invalid = LaserPoint(1.2f, 0.0f);
  invalid.valid = false;
  EXPECT_TRUE(Build({Sonar(0.2, 0.0, 0.0, 1.0f)}, {invalid}).sectors[0].unseen_by_laser);
}

TEST(SonarFeaturesTest, ConeTestWrapsAroundBehindTheRobot) {
  // A 360-degree laser, a rear sonar (yaw pi) and a laser point just across the +-pi cut.
  const LaserFieldOfView all_around{static_cast<float>(-kPi), static_cast<float>(kPi)};
  EXPECT_FALSE(Build({Sonar(-0.2, 0.0, kPi, 1.0f)}, {LaserPoint(-1.25f, -0.05f)}, {}, all_around)
                   .sectors[0]
                   .unseen_by_laser);
  EXPECT_FALSE(Build({Sonar(-0.2, 0.0, kPi, 1.0f)}, {LaserPoint(-1.25f, 0.05f)}, {}, all_around)
                   .sectors[0]
                   .unseen_by_laser);
  EXPECT_TRUE(Build({Sonar(-0.2, 0.0, kPi, 1.0f)}, {}, {}, all_around).sectors[0].unseen_by_laser);
}

TEST(SonarFeaturesTest, SonarsLookingWhereTheLaserCannotAreNotCompared) {
  // A rear sonar and the LMS200's 180 degrees ahead: a plain sector, never highlighted.
  const SonarFeatures rear = Build({Sonar(-0.2, 0.0, kPi, 1.0f)}, {});
  EXPECT_TRUE(rear.sectors[0].has_echo);
  EXPECT_FALSE(rear.sectors[0].compared);
  EXPECT_FALSE(rear.sectors[0].unseen_by_laser);
  EXPECT_TRUE(rear.outlines.empty());
  EXPECT_FALSE(rear.fans.empty());
  // No scan known: nothing is compared either.
  const SonarFeatures no_scan = Build({Sonar(0.2, 0.0, 0.0, 1.0f)}, {}, {}, LaserFieldOfView{});
  EXPECT_FALSE(no_scan.sectors[0].compared);
  EXPECT_EQ(no_scan.unseen, 0u);
}

TEST(SonarFeaturesTest, OnlyTheMainLobeAgrees) {
  // A glass door ahead and the partition beside it at the same distance, in the cone's outer
  // part (half cone 14 degrees, main lobe 7): the laser's partition points do not explain the
  // echo; with the whole cone they would.
  const std::vector<ScanPointLabel> partition = {LaserPoint(1.2f, 0.2f), LaserPoint(1.2f, -0.2f)};
  EXPECT_TRUE(Build({Sonar(0.2, 0.0, 0.0, 1.0f)}, partition).sectors[0].unseen_by_laser);
  SonarFeatureOptions whole_cone;
  whole_cone.agreement_cone_fraction = 1.f;
  EXPECT_FALSE(
      Build({Sonar(0.2, 0.0, 0.0, 1.0f)}, partition, whole_cone).sectors[0].unseen_by_laser);
}

TEST(SonarFeaturesTest, NoEchoFailedOrOutOfWindowReadingsDrawNothing) {
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const SonarFeatures f = Build({Sonar(0, 0, 0, inf), Sonar(0, 0, 0, nan), Sonar(0, 0, 0, 0.01f),
                                 Sonar(0, 0, 0, 7.0f), Sonar(0, 0, 0, 2.0f)},
                                {});
  ASSERT_EQ(f.sectors.size(), 5u);
  for (int i = 0; i < 4; ++i) EXPECT_FALSE(f.sectors[i].has_echo) << i;
  EXPECT_TRUE(f.sectors[4].has_echo);
  EXPECT_EQ(f.echoes, 1u);
  EXPECT_EQ(f.fans.vertex_count(), 3u * SonarFeatureOptions{}.arc_segments);
}

TEST(SonarFeaturesTest, DisabledDrawsNothingAndReusedOutputIsCleared) {
  SonarFeatures f = Build({Sonar(0.2, 0.0, 0.0, 1.0f)}, {});
  ASSERT_FALSE(f.fans.empty());
  SonarRanges ring;
  ring.ranges = {Sonar(0.2, 0.0, 0.0, 1.0f)};
  SonarFeatureOptions off;
  off.enabled = false;
  BuildSonarFeatures(ring, {}, kAhead, ArFeatureOptions{}, off, &f);
  EXPECT_TRUE(f.fans.empty());
  EXPECT_TRUE(f.outlines.empty());
  EXPECT_TRUE(f.sectors.empty());
  EXPECT_EQ(f.echoes, 0u);
}

TEST(SonarFeaturesTest, OptionsAreChecked) {
  std::string error;
  SonarFeatureOptions o;
  EXPECT_TRUE(o.IsValid(&error));
  o.arc_segments = 0;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("arc_segments"), std::string::npos);
  o = {};
  o.unseen_alpha = 1.5f;
  EXPECT_FALSE(o.IsValid(&error));
  o = {};
  o.laser_agreement_margin_m = 0;
  EXPECT_FALSE(o.IsValid(&error));
  o = {};
  o.agreement_cone_fraction = 0;
  EXPECT_FALSE(o.IsValid(&error));
  o = {};
  o.max_age_s = 0;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("max_age_s"), std::string::npos);
}

TEST(SonarFeaturesTest, AgeAtAnImageIsOnTheRobotsClockAndIgnoresWhenItArrived) {
  using std::chrono::milliseconds;
  const Time t0 = FromUnixNanos(1'700'000'000'000'000'000);
  SonarRanges ring;
  ring.ranges = {Sonar(0.2, 0.0, 0.0, 1.0f), Sonar(-0.2, 0.0, kPi, 1.0f)};
  ring.ranges[0].stamp = t0;
  ring.ranges[1].stamp = t0 + milliseconds(30);       // the cycle ends with its last ranging
  const Duration long_ago = std::chrono::seconds(9);  // received long ago (a paused replay)
  EXPECT_EQ(SonarAgeAtImage(ring, t0 + milliseconds(130), long_ago), milliseconds(100));
  // A cycle that ended after the image is as far from it.
  EXPECT_EQ(SonarAgeAtImage(ring, t0 - milliseconds(70), long_ago), milliseconds(100));
  // No image: the time since it was received.
  EXPECT_EQ(SonarAgeAtImage(ring, std::nullopt, long_ago), long_ago);
  EXPECT_EQ(SonarAgeAtImage(std::nullopt, t0, long_ago), Duration::zero());
  EXPECT_EQ(SonarAgeAtImage(SonarRanges{}, t0, long_ago), Duration::zero());
}

TEST(SonarFeaturesTest, OnlyAFreshCycleIsDrawnAndOnlyTheScansFieldOfViewIsCompared) {
  SonarRanges ring;
  ring.ranges = {Sonar(0.2, 0.0, 0.0, 1.0f), Sonar(-0.2, 0.0, kPi, 1.0f)};  // ahead, behind
  const SonarFeatureOptions options;                                        // max_age_s 1
  const ArFeatureOptions colors;
  SonarFeatures out;
  out.echoes = 99;  // untouched when nothing is drawn
  EXPECT_FALSE(BuildFreshSonarFeatures(std::nullopt, {}, nullptr, {}, colors, options, &out));
  EXPECT_FALSE(BuildFreshSonarFeatures(ring, std::chrono::milliseconds(1500), nullptr, {}, colors,
                                       options, &out));
  EXPECT_EQ(out.echoes, 99u);
  // Without a scan nothing is compared: two echoes, none unseen.
  ASSERT_TRUE(BuildFreshSonarFeatures(ring, std::chrono::milliseconds(200), nullptr, {}, colors,
                                      options, &out));
  EXPECT_EQ(out.echoes, 2u);
  EXPECT_EQ(out.unseen, 0u);
  // With a scan ahead that sees nothing there, the front sonar is unseen, the rear one is not
  // compared.
  LaserScan scan;
  scan.angle_min_rad = static_cast<float>(-kPi / 2);
  scan.angle_increment_rad = static_cast<float>(kPi / 180);
  scan.ranges_m.assign(181, 8.0f);
  ASSERT_TRUE(BuildFreshSonarFeatures(ring, std::chrono::milliseconds(200), &scan, {}, colors,
                                      options, &out));
  EXPECT_EQ(out.unseen, 1u);
  EXPECT_TRUE(out.sectors[0].compared);
  EXPECT_FALSE(out.sectors[1].compared);
}

}  // namespace
}  // namespace mostar::fusion
