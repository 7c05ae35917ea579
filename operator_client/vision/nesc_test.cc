#include "operator_client/vision/nesc.h"

#include <gtest/gtest.h>

#include "operator_client/vision/nep_classifier.h"

namespace mostar::vision {
namespace {

constexpr double kLaserHeightM = 0.40;

struct Rig {
  math::CameraModel left{math::LaserCameraCalibration{}, math::Eye::kLeft};
  math::CameraModel right{math::LaserCameraCalibration{}, math::Eye::kRight};
};

LaserScan ScanOf(std::vector<float> ranges_m) {
  LaserScan scan;
  scan.angle_min_rad = -0.01f;
  scan.angle_increment_rad = 0.01f;
  scan.ranges_m = std::move(ranges_m);
  return scan;
}

// A NEP as NED would report it in `camera`'s image.
Nep NepAt(const LaserScan& scan, size_t beam, double distance_m, const math::CameraModel& camera,
          double row_shift_px = 0.0) {
  Nep nep;
  nep.found = true;
  nep.distance_m = distance_m;
  nep.floor_point_laser = FloorPointLaser(scan.AngleOf(beam), distance_m, kLaserHeightM);
  nep.pixel = *camera.Project(nep.floor_point_laser) + Eigen::Vector2d(0, row_shift_px);
  return nep;
}

NedResult Ned(std::vector<Nep> neps) {
  NedResult result;
  result.neps = std::move(neps);
  return result;
}

NescResult RunNescOn(const NedResult& left, const NedResult& right, const LaserScan& scan,
                     const Rig& rig, NescOptions options = NescOptions{}) {
  NescResult out;
  std::string error;
  EXPECT_TRUE(RunNesc(left, right, scan, rig.right, options, NepClassifierOptions{}, &out, &error))
      << error;
  return out;
}

// Thesis 9.2 with the thesis' classification (every nearer NEP is a dot).
NepClassification Classify(const LaserScan& scan, const NescResult& nesc) {
  NepClassifierOptions options;
  options.neighbour_beams = 0;
  options.min_obstacle_beams = 1;
  NepClassification out;
  std::string error;
  EXPECT_TRUE(ClassifyNeps(scan, nesc.selected, {}, options, kLaserHeightM, &out, &error)) << error;
  return out;
}

TEST(NescTest, OneEyeArtifactIsUnreliableAndRemoved) {
  const Rig rig;
  const LaserScan scan = ScanOf({3.0f, 3.0f, 3.0f});
  // The right eye sees a dark blob at 1.5 m on beam 1; the left eye sees nothing there.
  const NescResult nesc = RunNescOn(Ned({Nep{}, Nep{}, Nep{}}),
                                    Ned({Nep{}, NepAt(scan, 1, 1.5, rig.right), Nep{}}), scan, rig);
  EXPECT_EQ(nesc.kinds[1], StereoNepKind::kRightOnly);
  EXPECT_FALSE(nesc.selected[1].reliable);
  EXPECT_EQ(nesc.one_eye, 1);
  const NepClassification out = Classify(scan, nesc);
  EXPECT_TRUE(out.possible_obstacles.empty());
  EXPECT_EQ(out.beams[1].relation, NepRelation::kNone);
}

TEST(NescTest, RealEdgeInBothEyesBecomesOneReliableNepAtTheMidpoint) {
  const Rig rig;
  const LaserScan scan = ScanOf({3.0f, 3.0f, 3.0f});
  const NescResult nesc =
      RunNescOn(Ned({Nep{}, NepAt(scan, 1, 1.48, rig.left), Nep{}}),
                Ned({Nep{}, NepAt(scan, 1, 1.52, rig.right), Nep{}}), scan, rig);
  EXPECT_EQ(nesc.kinds[1], StereoNepKind::kMatched);
  EXPECT_TRUE(nesc.selected[1].reliable);
  EXPECT_NEAR(nesc.selected[1].distance_m, 1.50, 1e-12);
  EXPECT_NEAR(nesc.selected[1].floor_point_laser.x(),
              FloorPointLaser(scan.AngleOf(1), 1.5, kLaserHeightM).x(), 1e-12);
  const NepClassification out = Classify(scan, nesc);
  ASSERT_EQ(out.possible_obstacles.size(), 1u);  // the low obstacle the laser missed
  EXPECT_NEAR(out.possible_obstacles[0].distance_m, 1.5, 1e-12);
}

// One eye's NEP runs along its ray (a silhouette), the other's crosses it: the fused NEP is a
// silhouette and makes no dot.
TEST(NescTest, FusedNepIsAlongTheRayWhenEitherEyesIs) {
  const Rig rig;
  const LaserScan scan = ScanOf({3.0f, 3.0f, 3.0f});
  Nep left = NepAt(scan, 1, 1.48, rig.left);
  left.along_ray = true;
  const NescResult nesc = RunNescOn(
      Ned({Nep{}, left, Nep{}}), Ned({Nep{}, NepAt(scan, 1, 1.52, rig.right), Nep{}}), scan, rig);
  EXPECT_EQ(nesc.kinds[1], StereoNepKind::kMatched);
  EXPECT_TRUE(nesc.selected[1].reliable);
  EXPECT_TRUE(nesc.selected[1].along_ray);
  EXPECT_TRUE(Classify(scan, nesc).possible_obstacles.empty());
}

TEST(NescTest, ReliableNepCorrectsTheOverlay) {
  const Rig rig;
  const LaserScan scan = ScanOf({2.0f});
  const NescResult nesc = RunNescOn(Ned({NepAt(scan, 0, 2.05, rig.left)}),
                                    Ned({NepAt(scan, 0, 2.07, rig.right)}), scan, rig);
  const NepClassification out = Classify(scan, nesc);
  EXPECT_EQ(out.beams[0].relation, NepRelation::kAgrees);
  EXPECT_NEAR(out.corrected_scan.ranges_m[0], 2.06f, 1e-6);
}

TEST(NescTest, BothUnreliableAndBothAgreeingTheNearerWins) {
  const Rig rig;
  const LaserScan scan = ScanOf({2.0f});
  NescOptions options;
  options.stereo_threshold_m = 0.05;  // 0.12 apart: both unreliable, both within edgeTh
  const NescResult nesc = RunNescOn(Ned({NepAt(scan, 0, 2.07, rig.left)}),
                                    Ned({NepAt(scan, 0, 1.95, rig.right)}), scan, rig, options);
  EXPECT_EQ(nesc.kinds[0], StereoNepKind::kDisagree);
  EXPECT_EQ(nesc.disagree_resolved, 1);
  EXPECT_FALSE(nesc.selected[0].reliable);
  EXPECT_NEAR(nesc.selected[0].distance_m, 1.95, 1e-12);
  const NepClassification out = Classify(scan, nesc);
  EXPECT_EQ(out.beams[0].relation, NepRelation::kAgrees);
  EXPECT_NEAR(out.corrected_scan.ranges_m[0], 1.95f, 1e-6);
}

TEST(NescTest, BothUnreliableOnlyTheAgreeingOneCounts) {
  const Rig rig;
  const LaserScan scan = ScanOf({2.0f});
  const NescResult nesc = RunNescOn(Ned({NepAt(scan, 0, 1.2, rig.left)}),
                                    Ned({NepAt(scan, 0, 2.04, rig.right)}), scan, rig);
  EXPECT_NEAR(nesc.selected[0].distance_m, 2.04, 1e-12);
  const NepClassification out = Classify(scan, nesc);
  EXPECT_EQ(out.beams[0].relation, NepRelation::kAgrees);
  EXPECT_TRUE(out.possible_obstacles.empty());  // the left eye's stray edge is dropped
}

TEST(NescTest, BothUnreliableAndNeitherAgreesNothingIsUsed) {
  const Rig rig;
  const LaserScan scan = ScanOf({3.0f});
  const NescResult nesc = RunNescOn(Ned({NepAt(scan, 0, 1.0, rig.left)}),
                                    Ned({NepAt(scan, 0, 1.6, rig.right)}), scan, rig);
  EXPECT_EQ(nesc.disagree_resolved, 0);
  const NepClassification out = Classify(scan, nesc);
  EXPECT_EQ(out.beams[0].relation, NepRelation::kNone);
  EXPECT_TRUE(out.possible_obstacles.empty());
}

TEST(NescTest, EstimatesTheVerticalOffsetOfTheRightImage) {
  const Rig rig;
  std::vector<float> ranges(40, 3.0f);
  const LaserScan scan = ScanOf(ranges);
  std::vector<Nep> left, right;
  for (size_t i = 0; i < ranges.size(); ++i) {
    left.push_back(NepAt(scan, i, 2.0, rig.left));
    right.push_back(NepAt(scan, i, 2.0, rig.right, /*row_shift_px=*/3.0 + 0.1 * (i % 3)));
  }
  right[5].pixel.y() += 40;  // a gross mismatch is left out
  const NescResult nesc = RunNescOn(Ned(left), Ned(right), scan, rig);
  ASSERT_TRUE(nesc.offset.valid);
  EXPECT_EQ(nesc.offset.samples, 39);
  EXPECT_NEAR(nesc.offset.vertical_offset_px, 3.1, 0.11);
  EXPECT_LT(nesc.offset.spread_px, 0.2);
}

TEST(NescTest, NoOffsetHintFromTooFewSamples) {
  const Rig rig;
  const LaserScan scan = ScanOf({3.0f});
  const NescResult nesc = RunNescOn(Ned({NepAt(scan, 0, 2.0, rig.left)}),
                                    Ned({NepAt(scan, 0, 2.0, rig.right)}), scan, rig);
  EXPECT_FALSE(nesc.offset.valid);
  EXPECT_EQ(nesc.offset.samples, 1);
}

TEST(NescTest, RejectsMismatchedSizes) {
  const Rig rig;
  const LaserScan scan = ScanOf({3.0f, 3.0f});
  NescResult out;
  std::string error;
  EXPECT_FALSE(RunNesc(Ned({Nep{}}), Ned({Nep{}, Nep{}}), scan, rig.right, NescOptions{},
                       NepClassifierOptions{}, &out, &error));
  EXPECT_NE(error.find("one NEP per beam"), std::string::npos) << error;
}

}  // namespace
}  // namespace mostar::vision
