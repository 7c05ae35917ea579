// Scores the edge processing against the simulator's ground truth and prints a table (the one in
// docs/vision.md). Per scene: precision and recall of "obstacle below the laser" dots (mono =
// right image alone, thesis 8; stereo = NESC, thesis 9.2; both with the client's defaults, so
// with the neighbour and isolated-dot rules), the share of stray NEPs NESC removes,
// and the overlay misalignment in pixels before and after NEP correction under a deliberately
// perturbed calibration. Images carry sensor noise and a one-eye artefact (right eye, every
// other frame on average). Run from the repository root (or set MOSTAR_SOURCE_DIR).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "common/config/config_loader.h"
#include "common/stats/percentile.h"
#include "operator_client/client_config.pb.h"
#include "operator_client/vision/vision_pipeline.h"
#include "robot_server/sim/sim_world.h"
#include "tests/vision/sim_calibration.h"

namespace mostar::vision {
namespace {

struct SceneCase {
  std::string name;
  std::string floor;
  int low_threshold;  // the profile an operator would tune in the edge-calibration view
  int high_threshold;
  int min_step_grey;  // step test against thin floor lines (0 = off)
};

struct Counts {
  int frames = 0;
  int positives = 0;
  int mono_dots = 0, mono_true = 0, mono_found = 0;
  int stereo_dots = 0, stereo_true = 0, stereo_found = 0;
  int stray = 0, stray_survived = 0;
  int real = 0, real_survived = 0;
  std::vector<double> before_px, after_px;
  int aligned_beams = 0, corrected_beams = 0;
  int offset_valid = 0;
  double offset_sum_px = 0;
};

double Percentile(const std::vector<double>& v, double q) {
  return mostar::Percentile(v, q).value_or(std::nan(""));
}

cv::Mat DistanceToBaseLines(const cv::Mat& labels) {
  cv::Mat not_base(labels.size(), CV_8U, cv::Scalar(255));
  for (const cv::Point& p : sim::BaseLinePixels(labels)) {
    not_base.at<uint8_t>(p) = 0;
    not_base.at<uint8_t>(p + cv::Point(0, 1)) = 0;
  }
  cv::Mat distance;
  cv::distanceTransform(not_base, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  return distance;
}

std::shared_ptr<const math::CameraModel> Perturbed(const math::CameraModel& camera, double tilt_rad,
                                                   double height_m) {
  math::LaserCameraCalibration c = camera.calibration();
  c.tilt_rad += tilt_rad;
  c.camera_y_m += height_m;
  return std::make_shared<const math::CameraModel>(c, camera.eye());
}

void DrawDot(cv::Mat* image, const math::CameraModel& camera, const Eigen::Vector3d& point,
             const cv::Scalar& colour, int radius) {
  const auto p = camera.Project(point);
  if (p && camera.IsInImage(*p)) {
    cv::circle(
        *image,
        cv::Point(static_cast<int>(std::lround(p->x())), static_cast<int>(std::lround(p->y()))),
        radius, colour, cv::FILLED);
  }
}

int Run(int argc, char** argv) {
  CLI::App app{"Edge processing against the simulator's ground truth"};
  int frames = 12;
  double noise_sigma = 3.0;
  double artifact_probability = 0.5;
  double tilt_error_rad = 0.012;
  double height_error_m = 0.02;
  double right_vertical_offset_px = 0.0;
  std::string images_out;
  bool below_laser_only = false;
  app.add_option("--frames", frames, "frames per scene")->check(CLI::Range(1, 1000));
  app.add_option("--noise", noise_sigma, "image noise sigma, grey levels");
  app.add_option("--artifact_probability", artifact_probability, "one-eye artefact per frame");
  app.add_option("--tilt_error_rad", tilt_error_rad, "calibration perturbation: tilt");
  app.add_option("--height_error_m", height_error_m, "calibration perturbation: camera height");
  app.add_option("--right_vertical_offset_px", right_vertical_offset_px,
                 "right principal point shift unknown to the calibration");
  app.add_option("--images_out", images_out, "directory for before/after images");
  std::string client_config;
  app.add_option("--client_config", client_config,
                 "take the edge-processing options from this client configuration's vision "
                 "(e.g. deploy/config/client_thesis.pbtxt); the per-scene stretch thresholds and "
                 "step test stay unless the file sets them");
  app.add_flag("--below_laser_only", below_laser_only,
               "positives: only bases below the scan plane (not beams without an echo)");
  bool list_dots = false;
  app.add_flag("--list_dots", list_dots,
               "list every stereo dot (TP/FP) and every missed positive on stderr");
  CLI11_PARSE(app, argc, argv);
  client::ClientConfig client;
  if (!client_config.empty()) {
    std::string error;
    if (!LoadTextConfig(client_config, &client, &error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      return 2;
    }
  }

  const std::vector<SceneCase> cases = {{"open_room", "plain", 60, 200, 0},
                                        {"corridor", "faint pattern", 30, 105, 45},
                                        {"checkerboard_room", "checkerboard", 60, 200, 0}};
  std::printf(
      "| scene | floor | frames | obstacles the laser misses | mono P / R | stereo P / R | stray "
      "NEPs "
      "| removed by NESC | real NEPs kept | align before med / p90 px | after med / p90 px | "
      "beams corrected |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const SceneCase& scene_case : cases) {
    sim::proto::Scene scene;
    std::string error;
    if (!LoadSimScene(scene_case.name, &scene, &error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      return 1;
    }
    sim::proto::SimConfig config;
    config.mutable_camera()->set_noise_sigma(noise_sigma);
    config.mutable_camera()->set_right_vertical_offset_px(right_vertical_offset_px);
    sim::proto::ArtifactConfig* artifact = config.mutable_camera()->mutable_artifact();
    artifact->set_kind(sim::proto::ArtifactConfig::DARK_BLOB);
    artifact->set_eye(sim::proto::ArtifactConfig::RIGHT);
    artifact->set_probability(artifact_probability);
    const Time start = FromUnixNanos(1'700'000'000'000'000'000);
    auto world = sim::SimWorld::Create(scene, config, start, &error);
    if (world == nullptr) {
      std::fprintf(stderr, "%s: %s\n", scene_case.name.c_str(), error.c_str());
      return 1;
    }
    const double laser_height_m = world->laser_params().height_m;
    // The client's calibration: the true one, but without the unknown vertical offset.
    sim::LaserCameraCalibration believed = world->calibration();
    believed.right_cy_px = believed.cy_px;
    VisionInput input;
    input.left_camera = SimCameraModel(believed, Eye::kLeft, laser_height_m);
    input.right_camera = SimCameraModel(believed, Eye::kRight, laser_height_m);
    const auto true_right = SimCameraModel(world->calibration(), Eye::kRight, laser_height_m);
    VisionInput perturbed_input;
    perturbed_input.left_camera = Perturbed(*input.left_camera, tilt_error_rad, height_error_m);
    perturbed_input.right_camera = Perturbed(*input.right_camera, tilt_error_rad, height_error_m);

    VisionOptions options = FromProto(client.vision());
    const proto::VisionConfig& file = client.vision();
    if (!file.edges().has_low_threshold()) options.edges.low_threshold = scene_case.low_threshold;
    if (!file.edges().has_high_threshold()) {
      options.edges.high_threshold = scene_case.high_threshold;
    }
    if (!file.nearest_edge().has_min_step_grey()) {
      options.nearest_edge.min_step_grey = scene_case.min_step_grey;
    }
    VisionPipeline pipeline(options);
    VisionPipeline perturbed_pipeline(options);
    const double edge_threshold_m = options.classifier.edge_threshold_m;
    constexpr double kMatchToleranceM = 0.15;

    Counts c;
    world->SetVelocity(0.15, 0.35);
    for (int frame = 0; frame < frames; ++frame) {
      const Time t = start + FromSeconds(1.0 * frame);
      sim::LaserGroundTruth laser_truth;
      input.scan = world->ScanAt(t, &laser_truth);
      Pose2D pose;
      const sim::StereoImages images = world->StereoAt(t, /*with_truth=*/true, &pose);
      const std::vector<float> base_m = TrueBaseDistances(*world, pose);
      input.left = images.left;
      input.right = images.right;
      const VisionResult result = pipeline.Process(input);
      if (!result.ok) {
        std::fprintf(stderr, "%s: %s\n", scene_case.name.c_str(), result.error.c_str());
        return 1;
      }
      ++c.frames;
      if (result.nesc.offset.valid) {
        ++c.offset_valid;
        c.offset_sum_px += result.nesc.offset.vertical_offset_px;
      }
      const size_t beams = input.scan.ranges_m.size();
      // Visible, unoccluded obstacle base on beam i (right image).
      const auto base_visible = [&](size_t i) {
        if (!std::isfinite(base_m[i])) return false;
        const double azimuth = input.scan.AngleOf(i);
        const auto at_base =
            true_right->Project(FloorPointLaser(azimuth, base_m[i], laser_height_m));
        const auto before =
            true_right->Project(FloorPointLaser(azimuth, base_m[i] - 0.03, laser_height_m));
        if (!at_base || !before || !true_right->IsInImage(*at_base) ||
            !true_right->IsInImage(*before)) {
          return false;
        }
        return images.right_truth.labels.at<uint8_t>(static_cast<int>(std::lround(before->y())),
                                                     static_cast<int>(std::lround(before->x()))) ==
               sim::kLabelFloor;
      };
      // Obstacles the laser misses: a visible base within NED's reach (max_range_m) that lies
      // below the scan plane (nearer than the noise-free range minus edgeTh), or on a beam
      // without a valid range (no echo from a black surface).
      std::vector<bool> positive(beams, false);
      for (size_t i = 0; i < beams; ++i) {
        const bool missed = base_m[i] < laser_truth.true_ranges_m[i] - edge_threshold_m ||
                            (!below_laser_only && !LaserScan::IsValidRange(input.scan.ranges_m[i]));
        positive[i] = base_visible(i) && base_m[i] <= options.nearest_edge.max_range_m && missed;
        c.positives += positive[i] ? 1 : 0;
      }
      // Mono: the thesis' section 8 on the right image alone.
      NepClassification mono;
      ClassifyNeps(input.scan, result.right_ned.neps, {}, options.classifier, laser_height_m, &mono,
                   &error);
      const auto score = [&](const NepClassification& cls, int* dots, int* good, int* found) {
        std::vector<bool> hit(beams, false);
        for (const PossibleObstacle& dot : cls.possible_obstacles) {
          ++*dots;
          const size_t i = static_cast<size_t>(dot.beam);
          if (positive[i] && std::abs(dot.distance_m - base_m[i]) <= kMatchToleranceM) {
            ++*good;
            hit[i] = true;
          }
        }
        for (size_t i = 0; i < beams; ++i) *found += hit[i] ? 1 : 0;
      };
      score(mono, &c.mono_dots, &c.mono_true, &c.mono_found);
      score(result.classification, &c.stereo_dots, &c.stereo_true, &c.stereo_found);
      if (list_dots) {
        // Every stereo dot (TP within kMatchToleranceM of a positive's base, else FP) and every
        // positive without one (MISS), with what NED found on that beam in each eye.
        for (const PossibleObstacle& dot : result.classification.possible_obstacles) {
          const size_t i = static_cast<size_t>(dot.beam);
          const bool good = positive[i] && std::abs(dot.distance_m - base_m[i]) <= kMatchToleranceM;
          const auto px = true_right->Project(dot.floor_point_laser);
          std::fprintf(stderr,
                       "%s frame %d beam %zu %s dot %.2f m base %.2f m laser %.2f m positive %d "
                       "pixel %.0f,%.0f\n",
                       scene_case.name.c_str(), frame, i, good ? "TP" : "FP", dot.distance_m,
                       base_m[i], laser_truth.true_ranges_m[i], positive[i] ? 1 : 0,
                       px ? px->x() : -1.0, px ? px->y() : -1.0);
        }
        for (size_t i = 0; i < beams; ++i) {
          if (!positive[i]) continue;
          bool hit = false;
          for (const PossibleObstacle& dot : result.classification.possible_obstacles) {
            hit |= static_cast<size_t>(dot.beam) == i &&
                   std::abs(dot.distance_m - base_m[i]) <= kMatchToleranceM;
          }
          if (hit) continue;
          std::fprintf(stderr,
                       "%s frame %d beam %zu MISS base %.2f m laser %.2f m left NEP %.2f m "
                       "right NEP %.2f m (nan = none)\n",
                       scene_case.name.c_str(), frame, i, base_m[i], laser_truth.true_ranges_m[i],
                       result.left_ned.neps[i].found ? result.left_ned.neps[i].distance_m : NAN,
                       result.right_ned.neps[i].found ? result.right_ned.neps[i].distance_m : NAN);
        }
      }

      // Stray NEPs: more than 6 px from any obstacle base line in their own image (contact
      // shadows put true NEPs up to a few pixels below the base).
      const cv::Mat left_distance = DistanceToBaseLines(images.left_truth.labels);
      const cv::Mat right_distance = DistanceToBaseLines(images.right_truth.labels);
      for (const auto& [ned, distance] :
           {std::pair{&result.left_ned, &left_distance}, {&result.right_ned, &right_distance}}) {
        for (size_t i = 0; i < beams; ++i) {
          const Nep& nep = ned->neps[i];
          if (!nep.found) continue;
          const bool stray = distance->at<float>(static_cast<int>(nep.pixel.y()),
                                                 static_cast<int>(nep.pixel.x())) > 6.0f;
          const Nep& used = result.selected[i];
          // Kept by NESC: used, whatever the direction and start tests then made of it.
          const bool survived =
              (result.classification.beams[i].relation != NepRelation::kNone ||
               (used.reliable && (used.along_ray || used.starts_on_object))) &&
              used.found &&
              std::abs(used.distance_m - nep.distance_m) <= options.nesc.stereo_threshold_m;
          (stray ? c.stray : c.real) += 1;
          (stray ? c.stray_survived : c.real_survived) += survived ? 1 : 0;
        }
      }

      // Alignment under the perturbed calibration, on beams whose laser point is an obstacle
      // base (a surface standing on the floor and reaching the scan plane).
      perturbed_input.scan = input.scan;
      perturbed_input.left = images.left;
      perturbed_input.right = images.right;
      const VisionResult perturbed = perturbed_pipeline.Process(perturbed_input);
      const math::CameraModel& drawn = *perturbed_input.right_camera;
      cv::Mat overlay;
      const bool draw = !images_out.empty() && frame == 0;
      if (draw) overlay = images.right.clone();
      for (size_t i = 0; i < beams; ++i) {
        if (!base_visible(i) || std::abs(base_m[i] - laser_truth.true_ranges_m[i]) > 0.03 ||
            !LaserScan::IsValidRange(input.scan.ranges_m[i])) {
          continue;
        }
        const double azimuth = input.scan.AngleOf(i);
        const Eigen::Vector2d truth_px =
            *true_right->Project(FloorPointLaser(azimuth, base_m[i], laser_height_m));
        const auto before_px =
            drawn.Project(FloorPointLaser(azimuth, input.scan.ranges_m[i], laser_height_m));
        const float corrected_m = perturbed.classification.corrected_scan.ranges_m[i];
        if (!before_px || !std::isfinite(corrected_m)) continue;
        const auto after_px = drawn.Project(FloorPointLaser(azimuth, corrected_m, laser_height_m));
        if (!after_px) continue;
        ++c.aligned_beams;
        c.corrected_beams +=
            perturbed.classification.beams[i].relation == NepRelation::kAgrees ? 1 : 0;
        c.before_px.push_back((*before_px - truth_px).norm());
        c.after_px.push_back((*after_px - truth_px).norm());
      }
      if (draw) {
        cv::Mat after = images.right.clone();
        for (size_t i = 0; i < beams; ++i) {
          const double azimuth = input.scan.AngleOf(i);
          if (LaserScan::IsValidRange(input.scan.ranges_m[i])) {
            DrawDot(&overlay, drawn,
                    FloorPointLaser(azimuth, input.scan.ranges_m[i], laser_height_m),
                    cv::Scalar(0, 0, 255), 2);
          }
          const float corrected_m = perturbed.classification.corrected_scan.ranges_m[i];
          if (LaserScan::IsValidRange(corrected_m)) {
            const bool moved = perturbed.classification.beams[i].relation == NepRelation::kAgrees;
            DrawDot(&after, drawn, FloorPointLaser(azimuth, corrected_m, laser_height_m),
                    moved ? cv::Scalar(0, 200, 0) : cv::Scalar(0, 0, 255), 2);
          }
        }
        for (const PossibleObstacle& dot : perturbed.classification.possible_obstacles) {
          DrawDot(&after, drawn, dot.floor_point_laser, cv::Scalar(0, 220, 255), 3);
        }
        const std::string prefix = images_out + "/vision_" + scene_case.name;
        cv::imwrite(prefix + "_before.png", overlay);
        cv::imwrite(prefix + "_after.png", after);
        cv::Mat both;
        cv::hconcat(result.right_edges.stretched_grey, result.right_edges.edges, both);
        cv::imwrite(prefix + "_edges.png", both);
        // NESC: right-image NEPs before (all) and after (used) stereo correspondence.
        cv::Mat mono_image = images.right.clone();
        cv::Mat stereo_image = images.right.clone();
        for (size_t i = 0; i < beams; ++i) {
          if (result.right_ned.neps[i].found) {
            DrawDot(&mono_image, *input.right_camera, result.right_ned.neps[i].floor_point_laser,
                    cv::Scalar(0, 220, 255), 2);
          }
          if (result.selected[i].found &&
              result.classification.beams[i].relation != NepRelation::kNone) {
            DrawDot(&stereo_image, *input.right_camera, result.selected[i].floor_point_laser,
                    cv::Scalar(0, 220, 255), 2);
          }
        }
        cv::imwrite(prefix + "_neps_mono.png", mono_image);
        cv::imwrite(prefix + "_neps_nesc.png", stereo_image);
      }
      world->SetVelocity(0.15, frame % 4 < 2 ? 0.35 : -0.35);
    }
    const auto ratio = [](int a, int b) { return b > 0 ? 100.0 * a / b : std::nan(""); };
    std::printf(
        "| %s | %s | %d | %d | %.0f%% / %.0f%% | %.0f%% / %.0f%% | %d | %.0f%% | %.0f%% | %.1f / "
        "%.1f | %.1f / %.1f | %.0f%% |\n",
        scene_case.name.c_str(), scene_case.floor.c_str(), c.frames, c.positives,
        ratio(c.mono_true, c.mono_dots), ratio(c.mono_found, c.positives),
        ratio(c.stereo_true, c.stereo_dots), ratio(c.stereo_found, c.positives), c.stray,
        100.0 - ratio(c.stray_survived, c.stray), ratio(c.real_survived, c.real),
        Percentile(c.before_px, 0.5), Percentile(c.before_px, 0.9), Percentile(c.after_px, 0.5),
        Percentile(c.after_px, 0.9), ratio(c.corrected_beams, c.aligned_beams));
    if (right_vertical_offset_px != 0.0) {
      std::fprintf(stderr,
                   "%s: stereo offset hint valid in %d/%d frames, mean %.2f px (true %.2f)\n",
                   scene_case.name.c_str(), c.offset_valid, c.frames,
                   c.offset_valid > 0 ? c.offset_sum_px / c.offset_valid : std::nan(""),
                   right_vertical_offset_px);
    }
  }
  return 0;
}

}  // namespace
}  // namespace mostar::vision

int main(int argc, char** argv) { return mostar::vision::Run(argc, argv); }
