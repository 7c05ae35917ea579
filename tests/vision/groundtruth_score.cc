#include "tests/vision/groundtruth_score.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/stats/percentile.h"
#include "operator_client/vision/vision_pipeline.h"
#include "robot_server/sim/sim_world.h"
#include "tests/vision/sim_calibration.h"

namespace mostar::vision {
namespace {

double Percentile(const std::vector<double>& v, double q) {
  return mostar::Percentile(v, q).value_or(std::nan(""));
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

double Ratio(int a, int b) { return b > 0 ? 100.0 * a / b : std::nan(""); }

}  // namespace

std::vector<GroundTruthScene> GroundTruthScenes() {
  return {{"open_room", "plain", 60, 200, 0},
          {"corridor", "faint pattern", 30, 105, 45},
          {"checkerboard_room", "checkerboard", 60, 200, 0},
          {"tiled_room", "tiles and tape", 60, 200, 0}};
}

double GroundTruthScore::MonoPrecision() const { return Ratio(mono_true, mono_dots); }
double GroundTruthScore::MonoRecall() const { return Ratio(mono_found, positives); }
double GroundTruthScore::StereoPrecision() const { return Ratio(stereo_true, stereo_dots); }
double GroundTruthScore::StereoRecall() const { return Ratio(stereo_found, positives); }

std::string GroundTruthTableHeader() {
  return "| scene | floor | frames | obstacles the laser misses | mono P / R | stereo P / R | "
         "stray "
         "NEPs | removed by NESC | real NEPs kept | align before med / p90 px | after med / p90 "
         "px | beams corrected |\n|---|---|---|---|---|---|---|---|---|---|---|---|";
}

std::string GroundTruthScore::TableRow(const GroundTruthScene& scene) const {
  char row[512];
  std::snprintf(row, sizeof(row),
                "| %s | %s | %d | %d | %.0f%% / %.0f%% | %.0f%% / %.0f%% | %d | %.0f%% | %.0f%% | "
                "%.1f / %.1f | %.1f / %.1f | %.0f%% |",
                scene.name.c_str(), scene.floor.c_str(), frames, positives, MonoPrecision(),
                MonoRecall(), StereoPrecision(), StereoRecall(), stray,
                100.0 - Ratio(stray_survived, stray), Ratio(real_survived, real),
                Percentile(before_px, 0.5), Percentile(before_px, 0.9), Percentile(after_px, 0.5),
                Percentile(after_px, 0.9), Ratio(corrected_beams, aligned_beams));
  return row;
}

bool ScoreAgainstGroundTruth(const GroundTruthScene& scene_case, const proto::VisionConfig& file,
                             const GroundTruthRun& run, GroundTruthScore* score,
                             std::string* error) {
  *score = {};
  sim::proto::Scene scene;
  if (!LoadSimScene(scene_case.name, &scene, error)) return false;
  sim::proto::SimConfig config;
  config.mutable_camera()->set_noise_sigma(run.noise_sigma);
  config.mutable_camera()->set_right_vertical_offset_px(run.right_vertical_offset_px);
  sim::proto::ArtifactConfig* artifact = config.mutable_camera()->mutable_artifact();
  artifact->set_kind(sim::proto::ArtifactConfig::DARK_BLOB);
  artifact->set_eye(sim::proto::ArtifactConfig::RIGHT);
  artifact->set_probability(run.artifact_probability);
  config.mutable_camera()->set_k1(run.k1);
  const Time start = FromUnixNanos(1'700'000'000'000'000'000);
  auto world = sim::SimWorld::Create(scene, config, start, error);
  if (world == nullptr) {
    *error = scene_case.name + ": " + *error;
    return false;
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
  perturbed_input.left_camera =
      Perturbed(*input.left_camera, run.tilt_error_rad, run.height_error_m);
  perturbed_input.right_camera =
      Perturbed(*input.right_camera, run.tilt_error_rad, run.height_error_m);

  VisionOptions options = FromProto(file);
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

  GroundTruthScore& c = *score;
  // Tuning frames: one per second from the start, turning left for two frames, then right for
  // two. Held-out frames: half a second later, turning right first.
  const double turn_radps = run.held_out ? -0.35 : 0.35;
  const double first_s = run.held_out ? 0.5 : 0.0;
  world->SetVelocity(0.15, turn_radps);
  for (int frame = 0; frame < run.frames; ++frame) {
    const Time t = start + FromSeconds(first_s + 1.0 * frame);
    sim::LaserGroundTruth laser_truth;
    input.scan = world->ScanAt(t, &laser_truth);
    Pose2D pose;
    const sim::StereoImages images = world->StereoAt(t, /*with_truth=*/true, &pose);
    const std::vector<float> base_m = TrueBaseDistances(*world, pose);
    input.left = images.left;
    input.right = images.right;
    const VisionResult result = pipeline.Process(input);
    if (!result.ok) {
      *error = scene_case.name + ": " + result.error;
      return false;
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
      const auto at_base = true_right->Project(FloorPointLaser(azimuth, base_m[i], laser_height_m));
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
      const bool missed =
          base_m[i] < laser_truth.true_ranges_m[i] - edge_threshold_m ||
          (!run.below_laser_only && !LaserScan::IsValidRange(input.scan.ranges_m[i]));
      positive[i] = base_visible(i) && base_m[i] <= options.nearest_edge.max_range_m && missed;
      c.positives += positive[i] ? 1 : 0;
    }
    // Mono: the thesis' section 8 on the right image alone.
    NepClassification mono;
    std::string mono_error;
    ClassifyNeps(input.scan, result.right_ned.neps, {}, options.classifier, laser_height_m, &mono,
                 &mono_error);
    const auto count_dots = [&](const NepClassification& cls, int* dots, int* good, int* found) {
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
    count_dots(mono, &c.mono_dots, &c.mono_true, &c.mono_found);
    count_dots(result.classification, &c.stereo_dots, &c.stereo_true, &c.stereo_found);
    if (run.list_dots != nullptr) {
      // Every stereo dot (TP within kMatchToleranceM of a positive's base, else FP) and every
      // positive without one (MISS), with what NED found on that beam in each eye.
      for (const PossibleObstacle& dot : result.classification.possible_obstacles) {
        const size_t i = static_cast<size_t>(dot.beam);
        const bool good = positive[i] && std::abs(dot.distance_m - base_m[i]) <= kMatchToleranceM;
        const auto px = true_right->Project(dot.floor_point_laser);
        std::fprintf(run.list_dots,
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
        std::fprintf(run.list_dots,
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
    const bool draw = !run.images_out.empty() && frame == 0;
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
          DrawDot(&overlay, drawn, FloorPointLaser(azimuth, input.scan.ranges_m[i], laser_height_m),
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
      const std::string prefix = run.images_out + "/vision_" + scene_case.name;
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
    world->SetVelocity(0.15, frame % 4 < 2 ? turn_radps : -turn_radps);
  }
  return true;
}

}  // namespace mostar::vision
