#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include "operator_client/vision/sim_calibration.h"
#include "operator_client/vision/vision_pipeline.h"
#include "robot_server/sim/sim_world.h"
using namespace mostar;
using namespace mostar::vision;
int main(int argc, char** argv) {
  sim::proto::Scene scene; std::string error;
  LoadSimScene(argv[1], &scene, &error);
  sim::proto::SimConfig config;
  auto world = sim::SimWorld::Create(scene, config, FromUnixNanos(0), &error);
  const double h = world->laser_params().height_m;
  VisionInput input;
  input.left_camera = SimCameraModel(world->calibration(), Eye::kLeft, h);
  input.right_camera = SimCameraModel(world->calibration(), Eye::kRight, h);
  VisionOptions o;
  if (argc > 5) { o.edges.low_threshold = atoi(argv[2]); o.edges.high_threshold = atoi(argv[3]); o.edges.canny_threshold1 = atof(argv[4]); o.edges.canny_threshold2 = atof(argv[5]); }
  VisionPipeline p(o);
  input.scan = world->ScanAt(FromUnixNanos(0));
  auto im = world->StereoAt(FromUnixNanos(0), true);
  input.left = im.left; input.right = im.right;
  auto r = p.Process(input);
  cv::Mat vis = im.right.clone();
  for (auto& n : r.right_ned.neps) if (n.found) cv::circle(vis, cv::Point(n.pixel.x(), n.pixel.y()), 2, cv::Scalar(0,0,255), -1);
  for (auto pt : sim::BaseLinePixels(im.right_truth.labels)) vis.at<cv::Vec3b>(pt) = cv::Vec3b(0,255,0);
  cv::imwrite("/tmp/vision_dbg_right.png", vis);
  cv::imwrite("/tmp/vision_dbg_edges.png", r.right_edges.edges);
  cv::imwrite("/tmp/vision_dbg_stretch.png", r.right_edges.stretched_grey);
  cv::Mat grey; cv::cvtColor(im.right, grey, cv::COLOR_BGR2GRAY);
  double mn, mx; cv::minMaxLoc(grey.rowRange(300,480), &mn, &mx);
  printf("floor rows grey min %f max %f found %d\n", mn, mx, r.right_ned.found);
}
