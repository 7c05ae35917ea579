#include "operator_client/vision/nep_classifier.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace mostar::vision {
namespace {

constexpr double kLaserHeightM = 0.40;

LaserScan ScanOf(std::vector<float> ranges_m) {
  LaserScan scan;
  scan.angle_min_rad = -0.1f;
  scan.angle_increment_rad = 0.1f;
  scan.ranges_m = std::move(ranges_m);
  return scan;
}

Nep NepAt(const LaserScan& scan, size_t beam, double distance_m, bool reliable = true) {
  Nep nep;
  nep.found = true;
  nep.distance_m = distance_m;
  nep.floor_point_laser = FloorPointLaser(scan.AngleOf(beam), distance_m, kLaserHeightM);
  nep.reliable = reliable;
  return nep;
}

// The thesis' rules alone: every nearer NEP is a dot, only its own laser point counts.
NepClassifierOptions ThesisRules() {
  NepClassifierOptions options;
  options.neighbour_beams = 0;
  options.min_obstacle_beams = 1;
  return options;
}

NepClassification Classify(const LaserScan& scan, const std::vector<Nep>& neps,
                           const std::vector<bool>& outliers = {},
                           const NepClassifierOptions& options = ThesisRules()) {
  NepClassification out;
  std::string error;
  EXPECT_TRUE(ClassifyNeps(scan, neps, outliers, options, kLaserHeightM, &out, &error)) << error;
  return out;
}

TEST(NepClassifierTest, AgreeingNepMovesTheLaserPointOntoIt) {
  const LaserScan scan = ScanOf({2.0f, 2.0f, 2.0f});
  const NepClassification out = Classify(scan, {Nep{}, NepAt(scan, 1, 2.07), Nep{}});
  EXPECT_EQ(out.beams[1].relation, NepRelation::kAgrees);
  EXPECT_FLOAT_EQ(out.corrected_scan.ranges_m[1], 2.07f);
  EXPECT_FLOAT_EQ(out.corrected_scan.ranges_m[0], 2.0f);  // no NEP: untouched
  EXPECT_EQ(out.corrected, 1);
  EXPECT_TRUE(out.possible_obstacles.empty());
}

TEST(NepClassifierTest, MuchNearerNepIsAPossibleObstacleTheLaserMissed) {
  const LaserScan scan = ScanOf({3.0f, 3.0f, 3.0f});
  const NepClassification out = Classify(scan, {Nep{}, NepAt(scan, 1, 1.5), Nep{}});
  EXPECT_EQ(out.beams[1].relation, NepRelation::kNearer);
  ASSERT_EQ(out.possible_obstacles.size(), 1u);
  EXPECT_EQ(out.possible_obstacles[0].beam, 1);
  EXPECT_DOUBLE_EQ(out.possible_obstacles[0].distance_m, 1.5);
  EXPECT_NEAR(out.possible_obstacles[0].floor_point_laser.norm(), std::hypot(1.5, kLaserHeightM),
              1e-9);
  EXPECT_FLOAT_EQ(out.corrected_scan.ranges_m[1], 3.0f);  // the laser is not moved
}

TEST(NepClassifierTest, MuchFurtherNepIsIgnored) {
  const LaserScan scan = ScanOf({1.0f});
  const NepClassification out = Classify(scan, {NepAt(scan, 0, 2.5)});
  EXPECT_EQ(out.beams[0].relation, NepRelation::kFurther);
  EXPECT_EQ(out.further, 1);
  EXPECT_TRUE(out.possible_obstacles.empty());
  EXPECT_FLOAT_EQ(out.corrected_scan.ranges_m[0], 1.0f);
}

TEST(NepClassifierTest, ThresholdIsInclusive) {
  EXPECT_EQ(RelateNepToLaser(2.0999, 2.0f, 0.1), NepRelation::kAgrees);
  EXPECT_EQ(RelateNepToLaser(1.85, 2.0f, 0.1), NepRelation::kNearer);
  EXPECT_EQ(RelateNepToLaser(2.15, 2.0f, 0.1), NepRelation::kFurther);
}

TEST(NepClassifierTest, BeamWithoutAValidRangeMakesTheNepAPossibleObstacle) {
  const LaserScan scan =
      ScanOf({std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()});
  const NepClassification out = Classify(scan, {NepAt(scan, 0, 1.0), NepAt(scan, 1, 4.0)});
  EXPECT_EQ(out.beams[0].relation, NepRelation::kNearer);
  EXPECT_EQ(out.beams[1].relation, NepRelation::kNearer);
}

TEST(NepClassifierTest, DisagreeingNepConfirmsAPotentialOutlier) {
  // Beam 1: a spurious short range between two walls at 3 m; the edge is at the wall.
  const LaserScan scan = ScanOf({3.0f, 1.2f, 3.0f, 3.0f});
  const NepClassification out = Classify(
      scan, {Nep{}, NepAt(scan, 1, 3.0), Nep{}, NepAt(scan, 3, 1.0)}, {false, true, false, true});
  EXPECT_TRUE(out.beams[1].confirmed_outlier);              // further NEP disagrees
  EXPECT_TRUE(std::isnan(out.corrected_scan.ranges_m[1]));  // not drawn
  EXPECT_TRUE(out.beams[3].confirmed_outlier);              // nearer NEP disagrees too
  EXPECT_EQ(out.confirmed_outliers, 2);
  EXPECT_FALSE(out.beams[0].confirmed_outlier);
}

TEST(NepClassifierTest, PotentialOutlierWithAnAgreeingOrNoNepIsKept) {
  const LaserScan scan = ScanOf({1.2f, 1.2f});
  const NepClassification out = Classify(scan, {NepAt(scan, 0, 1.25), Nep{}}, {true, true});
  EXPECT_FALSE(out.beams[0].confirmed_outlier);
  EXPECT_FALSE(out.beams[1].confirmed_outlier);
  EXPECT_FLOAT_EQ(out.corrected_scan.ranges_m[0], 1.25f);
  EXPECT_FLOAT_EQ(out.corrected_scan.ranges_m[1], 1.2f);
  EXPECT_EQ(out.potential_outliers_kept, 2);
}

TEST(NepClassifierTest, UnreliableNepCountsOnlyWhenItAgrees) {
  const LaserScan scan = ScanOf({3.0f, 3.0f, 3.0f});
  const NepClassification out = Classify(
      scan, {NepAt(scan, 0, 1.0, false), NepAt(scan, 1, 3.05, false), NepAt(scan, 2, 1.0, false)},
      {false, false, true});
  EXPECT_EQ(out.beams[0].relation, NepRelation::kNone);
  EXPECT_EQ(out.beams[1].relation, NepRelation::kAgrees);
  EXPECT_FALSE(out.beams[2].confirmed_outlier);  // an unreliable NEP confirms nothing
  EXPECT_TRUE(out.possible_obstacles.empty());
  EXPECT_EQ(out.unreliable_ignored, 2);
}

// A silhouette (an edge along its ray) is no base on its beam: it still agrees with the laser
// or lies beyond it, but never makes a dot nor confirms a potential outlier.
TEST(NepClassifierTest, NepAlongItsRayMakesNoDot) {
  const LaserScan scan = ScanOf({3.0f, 3.0f, 3.0f, 3.0f});
  std::vector<Nep> neps = {NepAt(scan, 0, 1.0), NepAt(scan, 1, 3.05), NepAt(scan, 2, 1.0),
                           NepAt(scan, 3, 4.0)};
  for (Nep& nep : neps) nep.along_ray = true;
  const NepClassification out = Classify(scan, neps, {false, false, true, false});
  EXPECT_EQ(out.beams[0].relation, NepRelation::kNone);
  EXPECT_EQ(out.beams[1].relation, NepRelation::kAgrees);
  EXPECT_FLOAT_EQ(out.corrected_scan.ranges_m[1], 3.05f);
  EXPECT_FALSE(out.beams[2].confirmed_outlier);
  EXPECT_EQ(out.beams[3].relation, NepRelation::kFurther);
  EXPECT_TRUE(out.possible_obstacles.empty());
  EXPECT_EQ(out.along_ray_ignored, 2);
  // The same NEPs across their rays: two dots.
  for (Nep& nep : neps) nep.along_ray = false;
  EXPECT_EQ(Classify(scan, neps, {false, false, true, false}).possible_obstacles.size(), 2u);
}

LaserScan FineScan(std::vector<float> ranges_m) {
  LaserScan scan = ScanOf(std::move(ranges_m));
  scan.angle_min_rad = -0.05f;
  scan.angle_increment_rad = 0.01f;  // about half a degree, as the LMS200
  return scan;
}

TEST(NepClassifierTest, NepNextToALaserPointOfANeighbouringBeamIsNoDot) {
  // A thin leg at 3 m seen by the laser on beam 2 only; beams 1 and 3 pass beside it and their
  // rays cross the leg's image (or its contact shadow) near 3 m.
  const LaserScan scan = FineScan({6.0f, 6.0f, 3.0f, 6.0f, 6.0f});
  const std::vector<Nep> neps = {Nep{}, NepAt(scan, 1, 2.97), NepAt(scan, 2, 3.0),
                                 NepAt(scan, 3, 3.02), Nep{}};
  const NepClassification thesis = Classify(scan, neps);
  EXPECT_EQ(thesis.possible_obstacles.size(), 2u);
  NepClassifierOptions options = ThesisRules();
  options.neighbour_beams = 2;
  const NepClassification out = Classify(scan, neps, {}, options);
  EXPECT_TRUE(out.possible_obstacles.empty());
  EXPECT_EQ(out.beams[1].relation, NepRelation::kNeighbour);
  EXPECT_EQ(out.beams[3].relation, NepRelation::kNeighbour);
  EXPECT_EQ(out.beams[2].relation, NepRelation::kAgrees);
  EXPECT_EQ(out.neighbour, 2);
  EXPECT_FLOAT_EQ(out.corrected_scan.ranges_m[1], 6.0f);  // not moved
  // Three beams away is not a neighbour with neighbour_beams = 2 (though 9 cm away).
  const LaserScan far_scan = FineScan({6.0f, 6.0f, 6.0f, 6.0f, 3.0f});
  const NepClassification far_out =
      Classify(far_scan, {Nep{}, NepAt(far_scan, 1, 3.0), Nep{}, Nep{}, Nep{}}, {}, options);
  EXPECT_EQ(far_out.beams[1].relation, NepRelation::kNearer);
}

TEST(NepClassifierTest, IsolatedDotsAreDroppedAndLinesOfDotsKept) {
  // Beams 0-3: the base of a low box at 1.5 m (a line of NEPs); beam 7: one stray edge.
  const LaserScan scan = FineScan({4, 4, 4, 4, 4, 4, 4, 4, 4});
  std::vector<Nep> neps(9);
  for (size_t i = 0; i < 4; ++i) neps[i] = NepAt(scan, i, 1.5 + 0.01 * static_cast<double>(i));
  neps[7] = NepAt(scan, 7, 2.2);
  NepClassifierOptions options = ThesisRules();
  options.min_obstacle_beams = 2;
  const NepClassification out = Classify(scan, neps, {}, options);
  ASSERT_EQ(out.possible_obstacles.size(), 4u);
  EXPECT_EQ(out.possible_obstacles.back().beam, 3);
  EXPECT_EQ(out.beams[7].relation, NepRelation::kIsolated);
  EXPECT_EQ(out.isolated, 1);
  // A one-beam gap keeps the line; NEPs far apart on neighbouring beams do not link.
  neps.assign(9, Nep{});
  neps[2] = NepAt(scan, 2, 1.5);
  neps[4] = NepAt(scan, 4, 1.52);
  neps[6] = NepAt(scan, 6, 3.0);
  neps[7] = NepAt(scan, 7, 1.0);
  const NepClassification gaps = Classify(scan, neps, {}, options);
  EXPECT_EQ(gaps.beams[2].relation, NepRelation::kNearer);
  EXPECT_EQ(gaps.beams[4].relation, NepRelation::kNearer);
  EXPECT_EQ(gaps.beams[6].relation, NepRelation::kIsolated);
  EXPECT_EQ(gaps.beams[7].relation, NepRelation::kIsolated);
}

TEST(NepClassifierTest, IsolatedNepConfirmsNoOutlier) {
  const LaserScan scan = FineScan({3.0f, 1.2f, 3.0f});
  NepClassifierOptions options = ThesisRules();
  options.min_obstacle_beams = 2;
  const NepClassification out =
      Classify(scan, {Nep{}, NepAt(scan, 1, 0.6), Nep{}}, {false, true, false}, options);
  EXPECT_EQ(out.beams[1].relation, NepRelation::kIsolated);
  EXPECT_FALSE(out.beams[1].confirmed_outlier);
  EXPECT_FLOAT_EQ(out.corrected_scan.ranges_m[1], 1.2f);
}

TEST(NepClassifierTest, RejectsSizeMismatchesWithAMessage) {
  const LaserScan scan = ScanOf({1.0f, 1.0f});
  NepClassification out;
  std::string error;
  EXPECT_FALSE(
      ClassifyNeps(scan, {Nep{}}, {}, NepClassifierOptions{}, kLaserHeightM, &out, &error));
  EXPECT_NE(error.find("1 NEPs for 2 beams"), std::string::npos) << error;
  EXPECT_FALSE(ClassifyNeps(scan, {Nep{}, Nep{}}, {true}, NepClassifierOptions{}, kLaserHeightM,
                            &out, &error));
  EXPECT_NE(error.find("outlier labels"), std::string::npos) << error;
  NepClassifierOptions bad;
  bad.edge_threshold_m = 0;
  EXPECT_FALSE(ClassifyNeps(scan, {Nep{}, Nep{}}, {}, bad, kLaserHeightM, &out, &error));
  EXPECT_NE(error.find("edge_threshold_m"), std::string::npos) << error;
  bad = NepClassifierOptions{};
  bad.min_obstacle_beams = 0;
  EXPECT_FALSE(ClassifyNeps(scan, {Nep{}, Nep{}}, {}, bad, kLaserHeightM, &out, &error));
  EXPECT_NE(error.find("min_obstacle_beams"), std::string::npos) << error;
}

}  // namespace
}  // namespace mostar::vision
