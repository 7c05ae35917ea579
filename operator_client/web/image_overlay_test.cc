#include "operator_client/web/image_overlay.h"

#include <gtest/gtest.h>

namespace mostar::web {
namespace {

const fusion::Rgba kRed{1.f, 0.f, 0.f, 0.5f};

math::CameraModel Model() {
  math::LaserCameraCalibration calibration;
  calibration.distortion.k1 = -0.2;  // the page's image is not undistorted: vertices must be
  calibration.distortion.k2 = 0.05;  // placed with the lens model
  return math::CameraModel(calibration, Eye::kLeft);
}

void Add(fusion::VertexArray* array, const Eigen::Vector3d& p, const fusion::Rgba& c = kRed) {
  array->Add(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()), c);
}

void ExpectAt(const PixelVertex& v, const Eigen::Vector2d& px) {
  EXPECT_NEAR(v.u_px, px.x(), 1e-3);
  EXPECT_NEAR(v.v_px, px.y(), 1e-3);
}

TEST(ProjectOverlayTest, VerticesInFrontLandWhereTheCameraModelPutsThem) {
  const math::CameraModel model = Model();
  render::OverlayGeometry overlay;
  const std::vector<Eigen::Vector3d> wall = {{2.0, 0.5, -0.4}, {2.0, -0.5, -0.4}, {2.0, 0.5, 0.2}};
  for (const auto& p : wall) Add(&overlay.triangles, p);
  Add(&overlay.lines, {1.0, 0.0, -0.4});
  Add(&overlay.lines, {3.0, 0.3, -0.4});
  Add(&overlay.points, {2.5, -0.2, 0.0});
  const ImageOverlay out = ProjectOverlay(overlay, {}, model);
  ASSERT_EQ(out.triangles.size(), 3u);
  for (int i = 0; i < 3; ++i) ExpectAt(out.triangles[i], *model.Project(wall[i]));
  ASSERT_EQ(out.lines.size(), 2u);
  ExpectAt(out.lines[0], *model.Project({1.0, 0.0, -0.4}));
  ExpectAt(out.lines[1], *model.Project({3.0, 0.3, -0.4}));
  ASSERT_EQ(out.points.size(), 1u);
  ExpectAt(out.points[0], *model.Project({2.5, -0.2, 0.0}));
  EXPECT_EQ(out.triangles[0].rgba[0], 255);
  EXPECT_EQ(out.triangles[0].rgba[1], 0);
  EXPECT_EQ(out.triangles[0].rgba[3], 128);
  EXPECT_EQ(out.unprojectable, 0u);
}

TEST(ProjectOverlayTest, PrimitivesBehindTheCameraVanish) {
  render::OverlayGeometry overlay;
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(-1, 0.5, -0.4), Eigen::Vector3d(-1, -0.5, -0.4),
                                   Eigen::Vector3d(-2, 0, -0.4)}) {
    Add(&overlay.triangles, p);
  }
  Add(&overlay.lines, {-1, 0, -0.4});
  Add(&overlay.lines, {-2, 0, -0.4});
  Add(&overlay.points, {-1, 0, 0});
  const ImageOverlay out = ProjectOverlay(overlay, {}, Model());
  EXPECT_TRUE(out.triangles.empty());
  EXPECT_TRUE(out.lines.empty());
  EXPECT_TRUE(out.points.empty());
}

TEST(ProjectOverlayTest, ATriangleThroughTheNearPlaneIsClippedNotDropped) {
  const math::CameraModel model = Model();
  render::OverlayGeometry overlay;
  // One vertex behind the camera, two in front: the visible part is a quadrilateral (two
  // triangles) whose vertices lie at or in front of the near plane.
  Add(&overlay.triangles, {-1.0, 0.0, -0.4});
  Add(&overlay.triangles, {2.0, 0.3, -0.4});
  Add(&overlay.triangles, {2.0, -0.3, -0.4});
  const ImageOverlay out = ProjectOverlay(overlay, {}, model);
  ASSERT_EQ(out.triangles.size(), 6u);
  // The two vertices in front keep their exact place.
  int exact = 0;
  for (const PixelVertex& v : out.triangles) {
    for (const Eigen::Vector3d& p :
         {Eigen::Vector3d(2.0, 0.3, -0.4), Eigen::Vector3d(2.0, -0.3, -0.4)}) {
      const Eigen::Vector2d px = *model.Project(p);
      if (std::abs(v.u_px - px.x()) < 1e-3 && std::abs(v.v_px - px.y()) < 1e-3) ++exact;
    }
  }
  EXPECT_GE(exact, 2);
}

TEST(ProjectOverlayTest, ALineThroughTheNearPlaneKeepsItsVisibleEnd) {
  const math::CameraModel model = Model();
  render::OverlayGeometry overlay;
  Add(&overlay.lines, {-0.5, 0.0, -0.4});
  Add(&overlay.lines, {2.0, 0.0, -0.4});
  const ImageOverlay out = ProjectOverlay(overlay, {}, model);
  ASSERT_EQ(out.lines.size(), 2u);
  ExpectAt(out.lines[1], *model.Project({2.0, 0.0, -0.4}));
  // The clipped end is on the near plane: far below the image (the floor under the camera).
  EXPECT_GT(out.lines[0].v_px, out.lines[1].v_px);
}

TEST(ProjectOverlayTest, PrimitivesBeyondOneSideOfTheImageAreLeftOut) {
  const math::CameraModel model = Model();
  render::OverlayGeometry overlay;
  // Far to the left of the field of view (laser +y), in front of the camera.
  Add(&overlay.lines, {1.0, 3.0, -0.4});
  Add(&overlay.lines, {1.5, 3.5, -0.4});
  Add(&overlay.points, {1.0, 3.0, 0.0});
  const ImageOverlay out = ProjectOverlay(overlay, {}, model);
  EXPECT_TRUE(out.lines.empty());
  EXPECT_TRUE(out.points.empty());
  EXPECT_EQ(out.unprojectable, 0u);
}

TEST(ProjectOverlayTest, LabelsInTheImageKeepTextAndColour) {
  const math::CameraModel model = Model();
  fusion::DistanceLabel in;
  in.anchor_x_m = 2.f;
  in.anchor_z_m = 0.3f;
  in.text = "2.00 m";
  in.color = {0.f, 1.f, 0.f, 1.f};
  fusion::DistanceLabel behind = in;
  behind.anchor_x_m = -2.f;
  const ImageOverlay out = ProjectOverlay({}, {in, behind}, model);
  ASSERT_EQ(out.labels.size(), 1u);
  EXPECT_EQ(out.labels[0].text, "2.00 m");
  EXPECT_EQ(out.labels[0].rgba[1], 255);
  const Eigen::Vector2d px = *model.Project({2.0, 0.0, 0.3});
  EXPECT_NEAR(out.labels[0].u_px, px.x(), 1e-3);
  EXPECT_NEAR(out.labels[0].v_px, px.y(), 1e-3);
}

TEST(ToRgba8Test, ClampsAndRounds) {
  uint8_t out[4];
  ToRgba8({-1.f, 2.f, 0.5f, std::nanf("")}, out);
  EXPECT_EQ(out[0], 0);
  EXPECT_EQ(out[1], 255);
  EXPECT_EQ(out[2], 128);
  EXPECT_EQ(out[3], 0);
}

}  // namespace
}  // namespace mostar::web
