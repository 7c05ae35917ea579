#include "robot_server/sim/laser_raycast.h"

#include <gtest/gtest.h>

#include <cmath>

#include "robot_server/sim/sim_test_helpers.h"

namespace mostar::sim {
namespace {

using testing::OpenFloor;

LaserParams Exact() {
  LaserParams p;
  p.noise_sigma_m = 0;
  return p;
}

// Index of the beam closest to `angle_rad`.
size_t BeamAt(const LaserParams& p, double angle_rad) {
  return static_cast<size_t>(std::lround((angle_rad - p.AngleMin()) / p.increment_rad));
}

constexpr char kWallAt3m[] = "wall { x0_m: 3 y0_m: -20 x1_m: 3 y1_m: 20 height_m: 2 }\n";

TEST(LaserRaycastTest, BeamLayoutFollowsTheLms200Modes) {
  LaserParams p = LaserParams::FromProto(proto::LaserConfig());
  EXPECT_EQ(p.BeamCount(), 361u);
  EXPECT_NEAR(p.AngleMin(), -M_PI / 2, 1e-12);
  EXPECT_NEAR(p.range_max_m, 8.183, 1e-12);
  proto::LaserConfig narrow;
  narrow.set_fov(proto::LaserConfig::FOV_100);
  narrow.set_resolution(proto::LaserConfig::RES_0_25_DEG);
  narrow.set_range_mode(proto::LaserConfig::CM);
  p = LaserParams::FromProto(narrow);
  EXPECT_EQ(p.BeamCount(), 401u);
  EXPECT_NEAR(p.range_max_m, 81.83, 1e-12);
}

TEST(LaserRaycastTest, WallAtKnownDistanceGivesTheRangeOfEachBeam) {
  const World world(OpenFloor(kWallAt3m));
  const LaserParams p = Exact();
  LaserRaycaster laser(world, p, 1);
  std::vector<float> truth;
  const LaserScan scan = laser.Scan(Pose2D{}, Time(), &truth);
  ASSERT_EQ(scan.ranges_m.size(), 361u);
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const double a = scan.AngleOf(i);
    const double expected = 3.0 / std::cos(a);
    if (expected > 0 && expected < p.range_max_m) {
      EXPECT_NEAR(scan.ranges_m[i], expected, 1e-4) << "beam " << i;
      EXPECT_NEAR(truth[i], expected, 1e-4);
    } else {
      EXPECT_TRUE(std::isinf(scan.ranges_m[i])) << "beam " << i;
    }
  }
}

TEST(LaserRaycastTest, ScanIsInTheLaserFrameOfAMovedRobot) {
  const World world(OpenFloor(kWallAt3m));
  const LaserParams p = Exact();
  LaserRaycaster laser(world, p, 1);
  // At (1, 0.5) facing +y, the wall (x = 3) is 2 m to the robot's right (-90 deg).
  const LaserScan scan = laser.Scan(Pose2D{1.0, 0.5, M_PI / 2}, Time(), nullptr);
  EXPECT_NEAR(scan.ranges_m[BeamAt(p, -M_PI / 2)], 2.0, 1e-4);
  EXPECT_TRUE(std::isinf(scan.ranges_m[BeamAt(p, M_PI / 2)]));
}

TEST(LaserRaycastTest, NothingInRangeIsInfinite) {
  const World world(OpenFloor(""));
  LaserRaycaster laser(world, Exact(), 1);
  for (float r : laser.Scan(Pose2D{}, Time(), nullptr).ranges_m) EXPECT_TRUE(std::isinf(r));
}

TEST(LaserRaycastTest, ObjectBelowTheScanPlaneIsNotSeen) {
  const World world(OpenFloor(std::string(kWallAt3m) +
                              "box { x_m: 1.5 y_m: 0 size_x_m: 0.4 size_y_m: 1 height_m: 0.2 }\n"
                              "box { x_m: 1.5 y_m: 2 size_x_m: 0.4 size_y_m: 1 height_m: 0.5 }"));
  const LaserParams p = Exact();  // plane at 0.35 m
  LaserRaycaster laser(world, p, 1);
  const LaserScan scan = laser.Scan(Pose2D{}, Time(), nullptr);
  EXPECT_NEAR(scan.ranges_m[BeamAt(p, 0)], 3.0, 1e-4);  // through the 0.2 m box
  EXPECT_NEAR(scan.ranges_m[BeamAt(p, std::atan2(2, 1.3))], std::hypot(1.3, 2.0), 0.02);
}

TEST(LaserRaycastTest, RaisedObjectAboveThePlaneIsNotSeen) {
  const World world(OpenFloor(std::string(kWallAt3m) +
                              "box { x_m: 1.5 y_m: 0 size_x_m: 1 size_y_m: 1 height_m: 0.05 "
                              "elevation_m: 0.72 }"));
  const LaserParams p = Exact();
  LaserRaycaster laser(world, p, 1);
  EXPECT_NEAR(laser.Scan(Pose2D{}, Time(), nullptr).ranges_m[BeamAt(p, 0)], 3.0, 1e-4);
}

TEST(LaserRaycastTest, NoEchoSurfaceGivesInfinityLikeNothingInRange) {
  const World world(OpenFloor(std::string(kWallAt3m) +
                              "cylinder { x_m: 1.5 y_m: 0 radius_m: 0.2 height_m: 1 "
                              "material { laser: NO_ECHO } }"));
  const LaserParams p = Exact();
  LaserRaycaster laser(world, p, 1);
  std::vector<float> truth;
  const LaserScan scan = laser.Scan(Pose2D{}, Time(), &truth);
  EXPECT_TRUE(LaserScan::IsFreeRange(scan.ranges_m[BeamAt(p, 0)]));
  EXPECT_NEAR(truth[BeamAt(p, 0)], 1.3, 1e-4);  // the truth knows the bin is there
  EXPECT_NEAR(scan.ranges_m[BeamAt(p, 0.5)], 3.0 / std::cos(scan.AngleOf(BeamAt(p, 0.5))), 1e-4);
}

TEST(LaserRaycastTest, DazzlingSurfaceGivesNaN) {
  const World world(OpenFloor(std::string(kWallAt3m) +
                              "box { x_m: 1.5 y_m: 0 size_x_m: 0.1 size_y_m: 0.4 height_m: 1 "
                              "material { laser: DAZZLE } }"));
  const LaserParams p = Exact();
  LaserRaycaster laser(world, p, 1);
  std::vector<float> truth;
  const LaserScan scan = laser.Scan(Pose2D{}, Time(), &truth);
  EXPECT_TRUE(std::isnan(scan.ranges_m[BeamAt(p, 0)]));
  EXPECT_NEAR(truth[BeamAt(p, 0)], 1.45, 1e-4);
  EXPECT_NEAR(scan.ranges_m[BeamAt(p, 0.5)], 3.0 / std::cos(scan.AngleOf(BeamAt(p, 0.5))), 1e-4);
}

TEST(LaserRaycastTest, TransparentSurfaceIsSeenThrough) {
  const World world(OpenFloor(std::string(kWallAt3m) +
                              "box { x_m: 1.5 y_m: 0 size_x_m: 0.02 size_y_m: 2 height_m: 2 "
                              "material { laser: TRANSPARENT } }"));
  const LaserParams p = Exact();
  LaserRaycaster laser(world, p, 1);
  EXPECT_NEAR(laser.Scan(Pose2D{}, Time(), nullptr).ranges_m[BeamAt(p, 0)], 3.0, 1e-4);
}

TEST(LaserRaycastTest, SpuriousSurfaceGivesShorterWrongRanges) {
  const World world(
      OpenFloor("wall { x0_m: 3 y0_m: -20 x1_m: 3 y1_m: 20 "
                "material { laser: SPURIOUS spurious_probability: 0.5 } }"));
  const LaserParams p = Exact();
  LaserRaycaster laser(world, p, 7);
  int wrong = 0, right = 0;
  for (int s = 0; s < 5; ++s) {
    const LaserScan scan = laser.Scan(Pose2D{}, Time(), nullptr);
    for (size_t i = BeamAt(p, -0.5); i <= BeamAt(p, 0.5); ++i) {
      const double expected = 3.0 / std::cos(scan.AngleOf(i));
      if (std::abs(scan.ranges_m[i] - expected) < 1e-4) {
        ++right;
      } else {
        EXPECT_LT(scan.ranges_m[i], expected);
        ++wrong;
      }
    }
  }
  EXPECT_GT(wrong, 100);
  EXPECT_GT(right, 100);
}

TEST(LaserRaycastTest, DarkCheckerCellsAbsorbTheBeam) {
  const World world(
      OpenFloor("wall { x0_m: 2 y0_m: -2 x1_m: 2 y1_m: 2 material { "
                "texture: CHECKERBOARD square_m: 0.2 colour2 { r: 0 g: 0 b: 0 } "
                "laser: ABSORB_DARK } }"));
  const LaserParams p = Exact();
  LaserRaycaster laser(world, p, 1);
  const LaserScan scan = laser.Scan(Pose2D{}, Time(), nullptr);
  int absorbed = 0, valid = 0;
  for (size_t i = BeamAt(p, -0.7); i <= BeamAt(p, 0.7); ++i) {
    EXPECT_FALSE(std::isnan(scan.ranges_m[i])) << "beam " << i;  // no echo is not an error
    LaserScan::IsFreeRange(scan.ranges_m[i]) ? ++absorbed : ++valid;
  }
  EXPECT_GT(absorbed, 20);
  EXPECT_GT(valid, 20);
}

TEST(LaserRaycastTest, PitchedPlaneMeetsTheFloorAndBlackSquaresAbsorb) {
  const World world(
      OpenFloor("floor { pattern: CHECKERBOARD square_m: 0.5 "
                "colour2 { r: 0 g: 0 b: 0 } black_squares_absorb: true }"));
  LaserParams p = Exact();
  p.pitch_rad = 0.1;
  LaserRaycaster laser(world, p, 1);
  std::vector<float> truth;
  const LaserScan scan = laser.Scan(Pose2D{}, Time(), &truth);
  int absorbed = 0, valid = 0;
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const float r = scan.ranges_m[i];
    EXPECT_FALSE(std::isnan(r)) << "beam " << i;
    if (LaserScan::IsFreeRange(r) && std::isfinite(truth[i])) {
      ++absorbed;  // the floor is there, but black
    } else if (std::isfinite(r)) {
      ++valid;
      const double expected = p.height_m / (std::cos(scan.AngleOf(i)) * std::sin(p.pitch_rad));
      EXPECT_NEAR(r, expected, 1e-3) << "beam " << i;
    }
  }
  EXPECT_GT(absorbed, 30);
  EXPECT_GT(valid, 30);
}

TEST(LaserRaycastTest, NoiseIsSeededAndMillimetric) {
  const World world(OpenFloor(kWallAt3m));
  LaserParams p;
  p.noise_sigma_m = 0.005;
  LaserRaycaster a(world, p, 42), b(world, p, 42);
  const LaserScan sa = a.Scan(Pose2D{}, Time(), nullptr);
  const LaserScan sb = b.Scan(Pose2D{}, Time(), nullptr);
  EXPECT_EQ(sa.ranges_m, sb.ranges_m);
  double sum2 = 0;
  int n = 0;
  for (size_t i = BeamAt(p, -0.8); i <= BeamAt(p, 0.8); ++i, ++n) {
    const double e = sa.ranges_m[i] - 3.0 / std::cos(sa.AngleOf(i));
    sum2 += e * e;
  }
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.005, 0.002);
}

TEST(LaserRaycastTest, TrueRangesMatchTheNoiselessScan) {
  const World world(
      OpenFloor(std::string(kWallAt3m) + "cylinder { x_m: 1 y_m: 1 radius_m: 0.1 height_m: 1 }"));
  const LaserParams p = Exact();
  LaserRaycaster laser(world, p, 1);
  EXPECT_EQ(laser.Scan(Pose2D{0.2, 0.1, 0.3}, Time(), nullptr).ranges_m,
            TrueRangesAt(world, p, Pose2D{0.2, 0.1, 0.3}));
}

}  // namespace
}  // namespace mostar::sim
