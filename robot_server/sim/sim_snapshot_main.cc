// sim_snapshot: renders a scene from the robot's start pose to PNG files.
//
//   sim_snapshot --scene deploy/scenes/corridor.pbtxt
//                --config deploy/config/sim_morduc.pbtxt --out /tmp/corridor
// writes <out>_left.png, <out>_right.png, <out>_map.png (bird's-eye view: obstacles, robot
// footprint, camera field of view, laser points) and <out>_truth.png (left image with the
// true obstacle base line in green and the laser points projected with the true calibration).
#include <CLI/CLI.hpp>
#include <cmath>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "robot_server/sim/scene.h"
#include "robot_server/sim/sim_world.h"

namespace mostar::sim {
namespace {

cv::Mat DrawMap(const SimWorld& sim, const LaserScan& scan, const Pose2D& pose) {
  const auto& f = sim.world().scene().floor();
  const double px_per_m = std::min(900.0 / (f.max_x_m() - f.min_x_m()), 160.0);
  const int margin = 20;
  const int w = static_cast<int>((f.max_x_m() - f.min_x_m()) * px_per_m) + 2 * margin;
  const int h = static_cast<int>((f.max_y_m() - f.min_y_m()) * px_per_m) + 2 * margin;
  cv::Mat map(h, w, CV_8UC3, cv::Scalar(40, 40, 40));
  // World x to the right, world y up.
  auto to_px = [&](double x, double y) {
    return cv::Point(static_cast<int>(margin + (x - f.min_x_m()) * px_per_m),
                     static_cast<int>(margin + (f.max_y_m() - y) * px_per_m));
  };
  cv::rectangle(map, to_px(f.min_x_m(), f.max_y_m()), to_px(f.max_x_m(), f.min_y_m()),
                cv::Scalar(225, 225, 225), cv::FILLED);
  for (const auto& o : sim.world().obstacles()) {
    const Rgb& c = o.surface.colour;
    const cv::Scalar colour(c.b, c.g, c.r);
    if (o.kind == ShapeKind::kWall) {
      cv::line(map, to_px(o.x0_m, o.y0_m), to_px(o.x1_m, o.y1_m), cv::Scalar(60, 60, 60), 3);
    } else if (o.kind == ShapeKind::kBox) {
      std::vector<cv::Point> pts;
      const double cy = std::cos(o.yaw_rad), sy = std::sin(o.yaw_rad);
      for (const auto& [sx, sy2] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
        const double lx = sx * o.half_x_m, ly = sy2 * o.half_y_m;
        pts.push_back(to_px(o.x0_m + cy * lx - sy * ly, o.y0_m + sy * lx + cy * ly));
      }
      cv::fillConvexPoly(map, pts, colour);
      cv::polylines(map, pts, true, cv::Scalar(0, 0, 0), 1);
    } else {
      cv::circle(map, to_px(o.x0_m, o.y0_m), std::max(2, static_cast<int>(o.radius_m * px_per_m)),
                 colour, cv::FILLED);
    }
  }
  // Robot footprint and heading.
  const auto& d = sim.drive_params();
  const double c = std::cos(pose.theta_rad), s = std::sin(pose.theta_rad);
  cv::circle(map,
             to_px(pose.x_m + c * d.footprint_center_x_m, pose.y_m + s * d.footprint_center_x_m),
             static_cast<int>(d.footprint_radius_m * px_per_m), cv::Scalar(200, 120, 40), 2);
  cv::arrowedLine(map, to_px(pose.x_m, pose.y_m), to_px(pose.x_m + 0.5 * c, pose.y_m + 0.5 * s),
                  cv::Scalar(200, 120, 40), 2);
  // Camera field of view (horizontal half angle at the image centre row).
  const auto& k = sim.calibration();
  const double half_fov = std::atan(k.width_px / (2.0 * k.focal_px));
  for (double a : {-half_fov, half_fov}) {
    cv::line(map, to_px(pose.x_m, pose.y_m),
             to_px(pose.x_m + 3 * std::cos(pose.theta_rad + a),
                   pose.y_m + 3 * std::sin(pose.theta_rad + a)),
             cv::Scalar(40, 160, 40), 1);
  }
  // Laser points: red; error-coded (unknown) beams as short grey rays.
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const double a = pose.theta_rad + scan.AngleOf(i);
    const float r = scan.ranges_m[i];
    if (std::isnan(r)) {
      cv::line(map, to_px(pose.x_m, pose.y_m),
               to_px(pose.x_m + 0.6 * std::cos(a), pose.y_m + 0.6 * std::sin(a)),
               cv::Scalar(150, 150, 150), 1);
    } else if (std::isfinite(r)) {
      cv::circle(map, to_px(pose.x_m + r * std::cos(a), pose.y_m + r * std::sin(a)), 2,
                 cv::Scalar(0, 0, 230), cv::FILLED);
    }
  }
  return map;
}

cv::Mat DrawTruth(const SimWorld& sim, const StereoImages& images, const LaserScan& scan) {
  cv::Mat out = images.left.clone();
  const auto& truth = images.left_truth;
  for (int u = 0; u < out.cols; ++u) {
    if (truth.base_row_px[u] >= 0) {
      cv::circle(out, cv::Point(u, truth.base_row_px[u]), 1, cv::Scalar(0, 220, 0), cv::FILLED);
    }
  }
  const double laser_z = 0.0;  // laser points lie in the laser frame's xy plane
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const float r = scan.ranges_m[i];
    if (!std::isfinite(r)) continue;
    double u, v;
    const double a = scan.AngleOf(i);
    if (ProjectLaserPoint(sim.calibration(), Eye::kLeft, r * std::cos(a), r * std::sin(a), laser_z,
                          &u, &v)) {
      cv::circle(out, cv::Point(static_cast<int>(u), static_cast<int>(v)), 2, cv::Scalar(0, 0, 255),
                 cv::FILLED);
    }
  }
  return out;
}

int Run(int argc, char** argv) {
  CLI::App app{"Renders a simulated scene from the robot's start pose to PNG files."};
  std::string scene_path, config_path = "deploy/config/sim_morduc.pbtxt", out = "sim";
  app.add_option("--scene", scene_path, "Scene file (protobuf text)")->required();
  app.add_option("--config", config_path, "Simulator config file (protobuf text)");
  app.add_option("--out", out, "Output prefix: <out>_left.png, _right.png, _map.png, _truth.png");
  CLI11_PARSE(app, argc, argv);

  proto::Scene scene;
  proto::SimConfig config;
  std::string error;
  if (!LoadScene(scene_path, &scene, &error) || !LoadSimConfig(config_path, &config, &error)) {
    std::cerr << error << "\n";
    return 1;
  }
  auto sim = SimWorld::Create(scene, config, Time(), &error);
  if (!sim) {
    std::cerr << error << "\n";
    return 1;
  }
  Pose2D pose;
  const StereoImages images = sim->StereoAt(Time(), /*with_truth=*/true, &pose);
  const LaserScan scan = sim->ScanAt(Time());
  const bool ok = cv::imwrite(out + "_left.png", images.left) &&
                  cv::imwrite(out + "_right.png", images.right) &&
                  cv::imwrite(out + "_map.png", DrawMap(*sim, scan, pose)) &&
                  cv::imwrite(out + "_truth.png", DrawTruth(*sim, images, scan));
  if (!ok) {
    std::cerr << out << ": cannot write the PNG files\n";
    return 1;
  }
  std::cout << "wrote " << out << "_{left,right,map,truth}.png\n";
  return 0;
}

}  // namespace
}  // namespace mostar::sim

int main(int argc, char** argv) { return mostar::sim::Run(argc, argv); }
