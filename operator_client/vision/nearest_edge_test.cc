#include "operator_client/vision/nearest_edge.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <opencv2/imgproc.hpp>

namespace mostar::vision {
namespace {

constexpr double kPi = 3.14159265358979323846;

math::LaserCameraCalibration Calibration() {
  math::LaserCameraCalibration c;  // MORDUC-like defaults: 640x480, tilted 12 degrees down
  return c;
}

LaserScan ScanWithBeams(int beams, float range_m) {
  LaserScan scan;
  scan.angle_min_rad = static_cast<float>(-kPi / 2);
  scan.angle_increment_rad = static_cast<float>(kPi / (beams - 1));
  scan.ranges_m.assign(beams, range_m);
  return scan;
}

// Floor distance covered by one image row at `pixel` (metres per pixel, vertical).
double MetresPerPixel(const math::CameraModel& camera, const Eigen::Vector3d& floor_point) {
  const Eigen::Vector2d p = *camera.Project(floor_point);
  const auto a = camera.UnprojectToFloor(p + Eigen::Vector2d(0, -0.5));
  const auto b = camera.UnprojectToFloor(p + Eigen::Vector2d(0, 0.5));
  return (*a - *b).norm();
}

TEST(NearestEdgeOptionsTest, RejectsBadValuesByName) {
  std::string error;
  NearestEdgeOptions options;
  EXPECT_TRUE(options.IsValid(&error)) << error;
  options.step_px = 2.0;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("step_px"), std::string::npos);
  options = NearestEdgeOptions{};
  options.max_range_m = -1;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("max_range_m"), std::string::npos);
  options = NearestEdgeOptions{};
  options.min_crossing_angle_deg = 90.0;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("min_crossing_angle_deg"), std::string::npos);
}

TEST(NearestEdgeTest, FindsAHorizontalLineDrawnAtAKnownFloorDistance) {
  const math::CameraModel camera(Calibration(), math::kMonoCamera);
  for (const double distance_m : {1.2, 2.0, 3.5, 6.0}) {
    const Eigen::Vector3d floor_point = FloorPointLaser(0.0, distance_m, 0.40);
    const Eigen::Vector2d pixel = *camera.Project(floor_point);
    cv::Mat edges(480, 640, CV_8UC1, cv::Scalar(0));
    const int row = static_cast<int>(std::lround(pixel.y()));
    edges.row(row).setTo(255);

    const Nep nep = FindNearestEdgeOnRay(edges, camera, 0.0, NearestEdgeOptions{});
    ASSERT_TRUE(nep.found) << distance_m;
    EXPECT_EQ(nep.pixel.y(), row);
    // Within one pixel-equivalent of the true distance (the row is rounded).
    EXPECT_NEAR(nep.distance_m, distance_m, MetresPerPixel(camera, floor_point)) << distance_m;
    EXPECT_NEAR(nep.floor_point_laser.z(), -0.40, 1e-12);
    EXPECT_NEAR(nep.floor_point_laser.y(), 0.0, 1e-12);
  }
}

TEST(NearestEdgeTest, EveryVisibleBeamStopsAtTheFirstLineFromTheRobot) {
  const math::CameraModel camera(Calibration(), math::kMonoCamera);
  cv::Mat edges(480, 640, CV_8UC1, cv::Scalar(0));
  edges.row(300).setTo(255);  // nearer line
  edges.row(200).setTo(255);  // farther line
  const LaserScan scan = ScanWithBeams(181, 5.0f);
  NedResult result;
  std::string error;
  ASSERT_TRUE(FindNearestEdges(edges, camera, scan, NearestEdgeOptions{}, &result, &error))
      << error;
  ASSERT_EQ(result.neps.size(), 181u);
  EXPECT_GT(result.visible_rays, 40);
  EXPECT_GT(result.found, 40);
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const Nep& nep = result.neps[i];
    if (!nep.found) continue;
    EXPECT_EQ(nep.pixel.y(), 300) << "beam " << i;
    // The NEP lies on its beam's floor ray and re-projects onto the line.
    const double azimuth = scan.AngleOf(i);
    EXPECT_NEAR(std::atan2(nep.floor_point_laser.y(), nep.floor_point_laser.x()), azimuth, 1e-5);
    EXPECT_NEAR(camera.Project(nep.floor_point_laser)->y(), 300.0, 0.75) << "beam " << i;
  }
  // Beams pointing sideways/backwards never enter the image.
  EXPECT_FALSE(result.neps.front().found);
  EXPECT_FALSE(result.neps.back().found);
}

TEST(NearestEdgeTest, FollowsTheCurvedImageOfTheRayUnderDistortion) {
  math::LaserCameraCalibration calibration = Calibration();
  calibration.distortion.k1 = -0.25;
  calibration.distortion.k2 = 0.05;
  const math::CameraModel camera(calibration, math::kMonoCamera);
  // The image of the floor line x = 2.5 m (a curve under distortion), drawn 8-connected.
  constexpr double kLineX = 2.5;
  cv::Mat edges(480, 640, CV_8UC1, cv::Scalar(0));
  std::vector<cv::Point> curve;
  for (double y = -4.0; y <= 4.0; y += 0.002) {
    const auto p = camera.Project(Eigen::Vector3d(kLineX, y, -0.40));
    if (p && camera.IsInImage(*p)) {
      curve.emplace_back(static_cast<int>(std::lround(p->x())),
                         static_cast<int>(std::lround(p->y())));
    }
  }
  ASSERT_GT(curve.size(), 100u);
  cv::polylines(edges, curve, false, cv::Scalar(255), 1, cv::LINE_8);

  int checked = 0;
  for (double azimuth = -0.6; azimuth <= 0.6; azimuth += 0.05) {
    bool visible = false;
    const Nep nep = FindNearestEdgeOnRay(edges, camera, azimuth, NearestEdgeOptions{}, &visible);
    if (!visible) continue;
    ASSERT_TRUE(nep.found) << azimuth;
    const double expected_m = kLineX / std::cos(azimuth);
    EXPECT_NEAR(nep.distance_m, expected_m,
                1.5 * MetresPerPixel(camera, FloorPointLaser(azimuth, expected_m, 0.40)))
        << azimuth;
    ++checked;
  }
  EXPECT_GT(checked, 15);
}

TEST(NearestEdgeTest, IgnoresTheRobotsBottomMargin) {
  const math::CameraModel camera(Calibration(), math::kMonoCamera);
  cv::Mat edges(480, 640, CV_8UC1, cv::Scalar(0));
  edges.row(470).setTo(255);  // the robot's own bumper
  edges.row(350).setTo(255);
  NearestEdgeOptions options;
  EXPECT_EQ(FindNearestEdgeOnRay(edges, camera, 0.0, options).pixel.y(), 470);
  options.bottom_margin_px = 20;
  const Nep nep = FindNearestEdgeOnRay(edges, camera, 0.0, options);
  ASSERT_TRUE(nep.found);
  EXPECT_EQ(nep.pixel.y(), 350);
}

TEST(NearestEdgeTest, DoesNotCrossADiagonalEdgeUnseen) {
  const math::CameraModel camera(Calibration(), math::kMonoCamera);
  // A thin 8-connected diagonal line v = offset + slope * u; rays fanning left and right cross
  // it in both diagonal directions, where a pixel-by-pixel walk could slip between two pixels.
  for (const double slope : {1.0, -1.0}) {
    const double offset = slope > 0 ? 60.0 : 700.0;
    cv::Mat edges(480, 640, CV_8UC1, cv::Scalar(0));
    cv::line(edges, cv::Point(0, static_cast<int>(offset)),
             cv::Point(639, static_cast<int>(offset + slope * 639)), cv::Scalar(255), 1,
             cv::LINE_8);
    const auto side = [&](const Eigen::Vector2d& p) { return p.y() - (offset + slope * p.x()); };
    int crossing = 0;
    for (double azimuth = -0.6; azimuth <= 0.6; azimuth += 0.005) {
      const auto segment = camera.ProjectRayToImage(
          Eigen::Vector3d(0, 0, -0.40), Eigen::Vector3d(std::cos(azimuth), std::sin(azimuth), 0),
          NearestEdgeOptions{}.max_range_m);
      if (!segment || side(segment->start_px) * side(segment->end_px) > -4.0) continue;
      ++crossing;
      const Nep nep = FindNearestEdgeOnRay(edges, camera, azimuth, NearestEdgeOptions{});
      ASSERT_TRUE(nep.found) << "azimuth " << azimuth << " slope " << slope;
      EXPECT_NEAR(side(nep.pixel), 0.0, 1.0);
    }
    EXPECT_GT(crossing, 50);
  }
}

TEST(NearestEdgeTest, LateralToleranceCatchesAnEdgeBesideTheRay) {
  const math::CameraModel camera(Calibration(), math::kMonoCamera);
  const Eigen::Vector2d pixel = *camera.Project(FloorPointLaser(0.0, 3.0, 0.40));
  cv::Mat edges(480, 640, CV_8UC1, cv::Scalar(0));
  const int col = static_cast<int>(std::lround(pixel.x())) + 2;
  edges.at<uint8_t>(static_cast<int>(std::lround(pixel.y())), col) = 255;
  NearestEdgeOptions options;
  EXPECT_FALSE(FindNearestEdgeOnRay(edges, camera, 0.0, options).found);
  options.lateral_tolerance_px = 2;
  const Nep nep = FindNearestEdgeOnRay(edges, camera, 0.0, options);
  ASSERT_TRUE(nep.found);
  EXPECT_EQ(nep.pixel.x(), col);
  EXPECT_NEAR(nep.distance_m, 3.0, 2 * MetresPerPixel(camera, FloorPointLaser(0.0, 3.0, 0.4)));
}

TEST(NearestEdgeTest, RejectsAMismatchedEdgeImageWithAMessage) {
  const math::CameraModel camera(Calibration(), math::kMonoCamera);
  const LaserScan scan = ScanWithBeams(11, 2.0f);
  NedResult result;
  std::string error;
  EXPECT_FALSE(FindNearestEdges(cv::Mat(240, 320, CV_8UC1, cv::Scalar(0)), camera, scan,
                                NearestEdgeOptions{}, &result, &error));
  EXPECT_NE(error.find("640x480"), std::string::npos) << error;
  ASSERT_EQ(result.neps.size(), 11u);
  for (const Nep& nep : result.neps) EXPECT_FALSE(nep.found);
}

TEST(NearestEdgeTest, AnEmptyEdgeImageGivesNoNeps) {
  const math::CameraModel camera(Calibration(), math::kMonoCamera);
  NedResult result;
  std::string error;
  ASSERT_TRUE(FindNearestEdges(cv::Mat(480, 640, CV_8UC1, cv::Scalar(0)), camera,
                               ScanWithBeams(181, 3.0f), NearestEdgeOptions{}, &result, &error));
  EXPECT_EQ(result.found, 0);
  EXPECT_GT(result.visible_rays, 0);
}

TEST(NearestEdgeTest, BaseRefinementMovesFromAShadowRimToTheStrongerBaseEdge) {
  // Straight ahead: a faint rim (floor 150 -> shadow 120) two rows nearer than the base
  // (shadow 120 -> dark obstacle 20), both marked as edges.
  const math::CameraModel camera(Calibration(), math::kMonoCamera);
  const int base_row =
      static_cast<int>(std::lround(camera.Project(FloorPointLaser(0, 2.0, 0.40))->y()));
  cv::Mat grey(480, 640, CV_8UC1, cv::Scalar(150));
  grey.rowRange(base_row - 1, base_row + 3).setTo(120);  // the shadow band below the base
  grey.rowRange(0, base_row - 1).setTo(20);              // the obstacle
  cv::Mat edges(480, 640, CV_8UC1, cv::Scalar(0));
  edges.row(base_row + 2).setTo(255);  // rim
  edges.row(base_row - 1).setTo(255);  // base
  NearestEdgeOptions options;
  options.base_search_m = 0.0;  // the thesis' first edge
  const Nep first =
      FindNearestEdgeOnPixels(edges, TraceRayPixels(camera, 0.0, options), options, 0.40, grey);
  ASSERT_TRUE(first.found);
  EXPECT_EQ(first.pixel.y(), base_row + 2);
  options.base_search_m = 0.10;
  const Nep refined =
      FindNearestEdgeOnPixels(edges, TraceRayPixels(camera, 0.0, options), options, 0.40, grey);
  ASSERT_TRUE(refined.found);
  EXPECT_EQ(refined.pixel.y(), base_row - 1);
  EXPECT_GT(refined.distance_m, first.distance_m);
  // Without the grey image there is nothing to compare: the first edge stays.
  EXPECT_EQ(
      FindNearestEdgeOnPixels(edges, TraceRayPixels(camera, 0.0, options), options, 0.40).pixel.y(),
      base_row + 2);
  // An edge farther than base_search_m beyond the first one is another object.
  options.base_search_m = 0.01;
  EXPECT_EQ(
      FindNearestEdgeOnPixels(edges, TraceRayPixels(camera, 0.0, options), options, 0.40, grey)
          .pixel.y(),
      base_row + 2);
}

TEST(NearestEdgeTest, StepTestSkipsThinFloorLinesButNotObstacleBases) {
  const math::CameraModel camera(Calibration(), math::kMonoCamera);
  const int joint_row =
      static_cast<int>(std::lround(camera.Project(FloorPointLaser(0, 1.5, 0.40))->y()));
  const int base_row =
      static_cast<int>(std::lround(camera.Project(FloorPointLaser(0, 3.0, 0.40))->y()));
  cv::Mat grey(480, 640, CV_8UC1, cv::Scalar(200));
  grey.row(joint_row).setTo(120);            // a tile joint: floor on both sides
  grey.rowRange(0, base_row + 1).setTo(60);  // an obstacle standing at 3 m
  cv::Mat edges(480, 640, CV_8UC1, cv::Scalar(0));
  edges.row(joint_row).setTo(255);
  edges.row(base_row).setTo(255);
  NearestEdgeOptions options;
  options.base_search_m = 0.0;
  const RayPixels ray = TraceRayPixels(camera, 0.0, options);
  EXPECT_EQ(FindNearestEdgeOnPixels(edges, ray, options, 0.40, grey).pixel.y(), joint_row);
  options.min_step_grey = 45;
  const Nep nep = FindNearestEdgeOnPixels(edges, ray, options, 0.40, grey);
  ASSERT_TRUE(nep.found);
  EXPECT_EQ(nep.pixel.y(), base_row);
  EXPECT_NEAR(nep.distance_m, 3.0, 0.1);
}

// An edge at the ray's start (the image border) has no floor before it to compare with: the
// step test cannot tell it from a line on the floor and skips it.
TEST(NearestEdgeTest, StepTestSkipsEdgesWithNoFloorBeforeThem) {
  const math::CameraModel camera(Calibration(), math::kMonoCamera);
  NearestEdgeOptions options;
  options.base_search_m = 0.0;
  const RayPixels ray = TraceRayPixels(camera, 0.0, options);
  ASSERT_GT(ray.pixels.size(), 20u);
  const int border_row = ray.pixels[1].row;
  const int base_row =
      static_cast<int>(std::lround(camera.Project(FloorPointLaser(0, 3.0, 0.40))->y()));
  cv::Mat grey(480, 640, CV_8UC1, cv::Scalar(200));
  grey.rowRange(border_row, 480).setTo(120);  // something dark at the border, floor beyond
  grey.rowRange(0, base_row + 1).setTo(60);   // an obstacle standing at 3 m
  cv::Mat edges(480, 640, CV_8UC1, cv::Scalar(0));
  edges.row(border_row).setTo(255);
  edges.row(base_row).setTo(255);
  EXPECT_EQ(FindNearestEdgeOnPixels(edges, ray, options, 0.40, grey).pixel.y(), border_row);
  options.min_step_grey = 45;
  const Nep nep = FindNearestEdgeOnPixels(edges, ray, options, 0.40, grey);
  ASSERT_TRUE(nep.found);
  EXPECT_EQ(nep.pixel.y(), base_row);
}

TEST(EdgeCrossesRayTest, MeasuresTheAngleBetweenTheEdgeAndTheRay) {
  // A straight grey step through (320, 240) with the edge at `edge_deg` from the image's u axis.
  const auto step_image = [](double edge_deg) {
    cv::Mat grey(480, 640, CV_8UC1);
    const double a = edge_deg * kPi / 180.0;
    for (int r = 0; r < grey.rows; ++r) {
      for (int c = 0; c < grey.cols; ++c) {
        const double side = -(c - 320) * std::sin(a) + (r - 240) * std::cos(a);
        grey.at<uint8_t>(r, c) = side > 0.25 ? 200 : 60;  // no pixel centre on the line
      }
    }
    return grey;
  };
  const Eigen::Vector2d up(0.0, -1.0);  // a ray walking up the image
  for (const double edge_deg : {0.0, 20.0, 45.0, 70.0, 90.0}) {
    const cv::Mat grey = step_image(edge_deg);
    const double crossing_deg = 90.0 - edge_deg;  // the edge against the vertical ray
    EXPECT_EQ(EdgeCrossesRay(grey, 320, 240, up, crossing_deg - 8.0), true) << edge_deg;
    if (crossing_deg + 8.0 <= 85.0) {
      EXPECT_EQ(EdgeCrossesRay(grey, 320, 240, up, crossing_deg + 8.0), false) << edge_deg;
    }
    EXPECT_TRUE(EdgeCrossesRay(grey, 320, 240, up, 0.0)) << "the test off";
  }
  // No gradient: nothing to judge, the edge crosses.
  EXPECT_TRUE(EdgeCrossesRay(cv::Mat(480, 640, CV_8UC1, cv::Scalar(90)), 320, 240, up, 60.0));
}

// A ray walking up the image meets the silhouette of an obstacle standing beside it (a vertical
// grey step, along the ray) before a base further on (across the ray). NED stops at the
// silhouette as the thesis does; the direction test marks that NEP as along the ray.
TEST(NearestEdgeTest, DirectionTestMarksASilhouetteAlongTheRay) {
  const math::CameraModel camera(Calibration(), math::kMonoCamera);
  NearestEdgeOptions options;
  options.base_search_m = 0.0;
  const RayPixels ray = TraceRayPixels(camera, 0.0, options);
  ASSERT_GT(ray.pixels.size(), 40u);
  // The silhouette: a vertical grey step along the ray's pixel column from the ray's 20th pixel
  // up to the base, dark on its right (the obstacle's side face beside the ray).
  const RayPixels::Pixel& silhouette = ray.pixels[20];
  ASSERT_LT(std::abs(silhouette.direction_u), 0.05f);
  ASSERT_LT(silhouette.direction_v, -0.99f);
  const int base_row =
      static_cast<int>(std::lround(camera.Project(FloorPointLaser(0, 3.0, 0.40))->y()));
  ASSERT_LT(base_row + 5, silhouette.row);
  cv::Mat grey(480, 640, CV_8UC1, cv::Scalar(200));
  grey.rowRange(0, base_row + 1).setTo(60);  // an obstacle across the ray at 3 m
  const cv::Rect side(silhouette.col, 0, 640 - silhouette.col, 480);
  grey(side).setTo(60);
  cv::Mat edges(480, 640, CV_8UC1, cv::Scalar(0));
  const cv::Rect side_edge(silhouette.col, base_row + 1, 1, silhouette.row - base_row);
  edges(side_edge).setTo(255);
  edges.row(base_row).setTo(255);

  options.min_crossing_angle_deg = 0.0;
  const Nep thesis = FindNearestEdgeOnPixels(edges, ray, options, 0.40, grey);
  ASSERT_TRUE(thesis.found);
  EXPECT_EQ(thesis.pixel.y(), silhouette.row);
  EXPECT_FALSE(thesis.along_ray);
  options.min_crossing_angle_deg = 30.0;
  const Nep marked = FindNearestEdgeOnPixels(edges, ray, options, 0.40, grey);
  ASSERT_TRUE(marked.found);
  EXPECT_EQ(marked.pixel.y(), silhouette.row);
  EXPECT_TRUE(marked.along_ray);
  EXPECT_FALSE(FindNearestEdgeOnPixels(edges, ray, options, 0.40, cv::Mat()).along_ray)
      << "no grey image, no direction test";
  // Without the silhouette the base across the ray is found with the test on.
  edges(side_edge).setTo(0);
  grey(side).setTo(200);
  grey.rowRange(0, base_row + 1).setTo(60);
  const Nep base = FindNearestEdgeOnPixels(edges, ray, options, 0.40, grey);
  ASSERT_TRUE(base.found);
  EXPECT_FALSE(base.along_ray);
  EXPECT_EQ(base.pixel.y(), base_row);
  EXPECT_NEAR(base.distance_m, 3.0, 0.1);
}

// The rays entering the image at its bottom start on the floor (grey 200), but those starting on
// a dark box there (grey 60, its base below the image) have their NEP on the line above marked:
// with the finder and with the free function, and not at all when the test is off.
TEST(NearestEdgeTest, StartTestMarksRaysStartingOnAnObjectAtTheImageBottom) {
  const auto camera = std::make_shared<const math::CameraModel>(Calibration(), math::kMonoCamera);
  const LaserScan scan = ScanWithBeams(181, 5.0f);
  cv::Mat edges(480, 640, CV_8UC1, cv::Scalar(0));
  edges.row(300).setTo(255);
  cv::Mat grey(480, 640, CV_8UC1, cv::Scalar(200));
  grey(cv::Rect(280, 400, 80, 80)).setTo(60);
  NearestEdgeOptions options;
  options.min_crossing_angle_deg = 0.0;
  options.start_grey_deviation = 80;
  NearestEdgeFinder finder(options);
  NedResult cached, direct, off;
  std::string error;
  ASSERT_TRUE(finder.Find(edges, camera, scan, &cached, &error, grey)) << error;
  ASSERT_TRUE(FindNearestEdges(edges, *camera, scan, options, &direct, &error, grey)) << error;
  NearestEdgeOptions disabled = options;
  disabled.start_grey_deviation = 0;
  ASSERT_TRUE(FindNearestEdges(edges, *camera, scan, disabled, &off, &error, grey)) << error;
  int marked = 0, unmarked = 0;
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    if (!cached.neps[i].found) continue;
    const RayPixels ray = TraceRayPixels(*camera, scan.AngleOf(i), options);
    ASSERT_FALSE(ray.pixels.empty());
    const RayPixels::Pixel& first = ray.pixels.front();
    const bool on_box = first.row >= 477 && first.col >= 281 && first.col <= 358;
    EXPECT_EQ(cached.neps[i].starts_on_object, on_box) << "beam " << i;
    EXPECT_EQ(direct.neps[i].starts_on_object, cached.neps[i].starts_on_object) << "beam " << i;
    EXPECT_FALSE(off.neps[i].starts_on_object) << "beam " << i;
    (cached.neps[i].starts_on_object ? marked : unmarked) += 1;
  }
  EXPECT_GE(marked, 3);
  EXPECT_GT(unmarked, 20);
  // The rows that show the robot are not its start: with the box only there, nothing is marked.
  cv::Mat robot_rows(480, 640, CV_8UC1, cv::Scalar(200));
  robot_rows(cv::Rect(280, 470, 80, 10)).setTo(60);
  NearestEdgeOptions with_margin = options;
  with_margin.bottom_margin_px = 12;
  NedResult margin;
  ASSERT_TRUE(FindNearestEdges(edges, *camera, scan, with_margin, &margin, &error, robot_rows))
      << error;
  for (const Nep& nep : margin.neps) EXPECT_FALSE(nep.starts_on_object);
  EXPECT_GT(margin.found, 20);
}

TEST(NearestEdgeTest, FinderReportsTheHighestRowItsRaysRead) {
  const auto camera = std::make_shared<const math::CameraModel>(Calibration(), math::kMonoCamera);
  const LaserScan scan = ScanWithBeams(181, 3.0f);
  NearestEdgeOptions options;
  NearestEdgeFinder finder(options);
  std::string error;
  ASSERT_TRUE(finder.Prepare(camera, scan, &error)) << error;
  // The floor at max_range_m straight ahead is above every other ray pixel.
  const int far_row = static_cast<int>(
      std::floor(camera->Project(FloorPointLaser(0.0, options.max_range_m, 0.40))->y()));
  EXPECT_LE(finder.top_row(), far_row);
  EXPECT_GE(finder.top_row(), far_row - 6);
  // Edges above top_row() change nothing.
  cv::Mat edges(480, 640, CV_8UC1, cv::Scalar(0));
  edges.row(400).setTo(255);
  NedResult with_top, without_top;
  ASSERT_TRUE(finder.Find(edges, camera, scan, &without_top, &error)) << error;
  edges.rowRange(0, finder.top_row()).setTo(255);
  ASSERT_TRUE(finder.Find(edges, camera, scan, &with_top, &error)) << error;
  ASSERT_EQ(with_top.found, without_top.found);
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    ASSERT_EQ(with_top.neps[i].found, without_top.neps[i].found) << i;
    if (with_top.neps[i].found) {
      EXPECT_EQ(with_top.neps[i].distance_m, without_top.neps[i].distance_m) << i;
    }
  }
  EXPECT_FALSE(finder.Find(edges, camera, scan, &with_top, &error, cv::Mat(10, 10, CV_8UC1)));
  EXPECT_NE(error.find("grey image"), std::string::npos) << error;
}

}  // namespace
}  // namespace mostar::vision
