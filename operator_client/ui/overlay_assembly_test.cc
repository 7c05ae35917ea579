#include "operator_client/ui/overlay_assembly.h"

#include <gtest/gtest.h>

#include "operator_client/fusion/predicted_path.h"

namespace mostar::ui {
namespace {

fusion::VertexArray Vertices(int count, float tag) {
  fusion::VertexArray v;
  for (int i = 0; i < count; ++i) v.Add(tag, static_cast<float>(i), 0.f, {tag, 0.f, 0.f, 1.f});
  return v;
}

TEST(AssembleOverlayTest, ThePredictedPathIsAddedToRaysCirclesAndLinesNotInTheirPlace) {
  fusion::ArFeatures features;
  features.walls = Vertices(6, 1);
  features.rays = Vertices(4, 2);
  features.circles = Vertices(8, 3);
  features.vertical_lines = Vertices(2, 4);
  features.laser_points = Vertices(5, 5);
  fusion::VertexArray path;
  fusion::BuildPredictedPath(0.3, 0.2, fusion::PredictedPathOptions{}, &path);
  ASSERT_FALSE(path.empty());
  render::OverlayGeometry overlay;
  AssembleOverlay(nullptr, &features, {}, path, &overlay);
  EXPECT_EQ(overlay.triangles.vertex_count(), 6u);
  EXPECT_EQ(overlay.lines.vertex_count(), 4u + 8u + 2u + path.vertex_count());
  EXPECT_EQ(overlay.lines.positions[0], 2.f) << "rays first";
  EXPECT_EQ(overlay.points.vertex_count(), 5u);
}

TEST(AssembleOverlayTest, PossibleObstaclesAreMagentaDotsOnTheFloor) {
  vision::PossibleObstacle obstacle;
  obstacle.floor_point_laser = Eigen::Vector3d(1.5, -0.25, -0.4);
  render::OverlayGeometry overlay;
  AssembleOverlay(nullptr, nullptr, {obstacle}, {}, &overlay);
  ASSERT_EQ(overlay.points.vertex_count(), 1u);
  EXPECT_FLOAT_EQ(overlay.points.positions[0], 1.5f);
  EXPECT_FLOAT_EQ(overlay.points.positions[1], -0.25f);
  EXPECT_FLOAT_EQ(overlay.points.positions[2], -0.4f);
  EXPECT_EQ(overlay.points.colors, (std::vector<float>{1.f, 0.f, 1.f, 1.f}));
  EXPECT_TRUE(overlay.lines.empty());
  EXPECT_TRUE(overlay.triangles.empty());
}

TEST(AssembleOverlayTest, SonarFansLieUnderTheWallsAndTheirOutlinesAmongTheLines) {
  fusion::SonarFeatures sonar;
  sonar.fans = Vertices(3, 7);
  sonar.outlines = Vertices(2, 8);
  fusion::ArFeatures features;
  features.walls = Vertices(6, 1);
  features.rays = Vertices(4, 2);
  render::OverlayGeometry overlay;
  AssembleOverlay(&sonar, &features, {}, {}, &overlay);
  ASSERT_EQ(overlay.triangles.vertex_count(), 9u);
  EXPECT_EQ(overlay.triangles.positions[0], 7.f) << "sonar fans drawn first";
  EXPECT_EQ(overlay.triangles.positions[9], 1.f) << "then the walls";
  EXPECT_EQ(overlay.lines.vertex_count(), 6u);
  EXPECT_EQ(overlay.lines.positions[0], 8.f);
}

}  // namespace
}  // namespace mostar::ui
