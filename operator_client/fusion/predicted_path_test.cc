#include "operator_client/fusion/predicted_path.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mostar::fusion {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Xy {
  float x, y;
};

// Vertices of polyline `line` (0 centre, 1 left, 2 right) as points: first vertex of each
// segment plus the last vertex.
std::vector<Xy> Polyline(const VertexArray& array, int line, int segments) {
  std::vector<Xy> points;
  const size_t first = static_cast<size_t>(line * segments * 2);
  for (int s = 0; s < segments; ++s) {
    const size_t v = first + 2 * static_cast<size_t>(s);
    points.push_back({array.positions[3 * v], array.positions[3 * v + 1]});
  }
  const size_t last = first + 2 * static_cast<size_t>(segments) - 1;
  points.push_back({array.positions[3 * last], array.positions[3 * last + 1]});
  return points;
}

TEST(PoseAfterTest, StraightAndArc) {
  const PlanarPose straight = PoseAfter(0.5, 0.0, 2.0);
  EXPECT_DOUBLE_EQ(straight.x_m, 1.0);
  EXPECT_DOUBLE_EQ(straight.y_m, 0.0);
  const PlanarPose quarter = PoseAfter(1.0, 0.5, kPi);  // quarter turn on a 2 m radius, left
  EXPECT_NEAR(quarter.x_m, 2.0, 1e-12);
  EXPECT_NEAR(quarter.y_m, 2.0, 1e-12);
  EXPECT_NEAR(quarter.theta_rad, kPi / 2, 1e-12);
  const PlanarPose spin = PoseAfter(0.0, 1.0, 1.0);
  EXPECT_DOUBLE_EQ(spin.x_m, 0.0);
  EXPECT_DOUBLE_EQ(spin.y_m, 0.0);
}

TEST(PredictedPathTest, StraightCommandGivesParallelLinesOnTheFloor) {
  PredictedPathOptions options;
  options.horizon_s = 2.0f;
  options.step_s = 0.5f;
  options.half_width_m = 0.3f;
  options.rotation_center_x_m = -0.2f;
  VertexArray path;
  BuildPredictedPath(1.0, 0.0, options, &path);
  ASSERT_EQ(path.vertex_count(), 3u * 4u * 2u);
  const std::vector<Xy> centre = Polyline(path, 0, 4);
  EXPECT_NEAR(centre.front().x, -0.2f, 1e-6f);
  EXPECT_NEAR(centre.back().x, 1.8f, 1e-6f);
  EXPECT_NEAR(Polyline(path, 1, 4).back().y, 0.3f, 1e-6f);   // left edge
  EXPECT_NEAR(Polyline(path, 2, 4).back().y, -0.3f, 1e-6f);  // right edge
  for (size_t v = 0; v < path.vertex_count(); ++v) {
    EXPECT_EQ(path.positions[3 * v + 2], -options.laser_height_m);
  }
}

TEST(PredictedPathTest, TurningCommandFollowsAnArc) {
  PredictedPathOptions options;
  options.horizon_s = 3.0f;
  options.step_s = 0.1f;
  options.half_width_m = 0.25f;
  VertexArray path;
  BuildPredictedPath(0.5, -0.25, options, &path);  // turning right on a 2 m radius
  const int segments = 30;
  ASSERT_EQ(path.vertex_count(), 3u * segments * 2u);
  const double radii[3] = {2.0, 2.25, 1.75};  // centre, left edge (outside), right edge
  for (int line = 0; line < 3; ++line) {
    for (const Xy& p : Polyline(path, line, segments)) {
      EXPECT_NEAR(std::hypot(p.x, p.y + 2.0), radii[line], 1e-5) << line;
      EXPECT_LE(p.y, 0.25f + 1e-6f);
    }
  }
  EXPECT_LT(Polyline(path, 0, segments).back().y, -0.5f);  // ends to the right
}

TEST(PredictedPathTest, NoWidthGivesOnlyTheCentreLineAndBadCommandsNothing) {
  PredictedPathOptions options;
  options.half_width_m = 0.f;
  VertexArray path;
  BuildPredictedPath(0.3, 0.1, options, &path);
  EXPECT_EQ(path.vertex_count(), 30u * 2u);
  BuildPredictedPath(NAN, 0.1, options, &path);
  EXPECT_TRUE(path.empty());
}

TEST(PredictedPathOptionsTest, IsValidNamesTheViolatedConstraint) {
  PredictedPathOptions options;
  std::string error;
  EXPECT_TRUE(options.IsValid(&error)) << error;
  options.step_s = 5.f;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("step_s"), std::string::npos);
  options = PredictedPathOptions{};
  options.half_width_m = -1.f;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("half_width_m"), std::string::npos);
  options = PredictedPathOptions{};
  options.horizon_s = 0.f;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("horizon_s"), std::string::npos);
}

}  // namespace
}  // namespace mostar::fusion
