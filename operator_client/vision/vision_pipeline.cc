#include "operator_client/vision/vision_pipeline.h"

#include <chrono>
#include <opencv2/core/utility.hpp>
#include <sstream>

#include "common/check/check.h"

namespace mostar::vision {

bool VisionOptions::IsValid(std::string* error) const {
  std::string why;
  const auto fail = [&](const char* part) {
    if (error != nullptr) *error = std::string(part) + ": " + why;
    return false;
  };
  if (!edges.IsValid(&why)) return fail("edges");
  if (!nearest_edge.IsValid(&why)) return fail("nearest_edge");
  if (!classifier.IsValid(&why)) return fail("classifier");
  if (!nesc.IsValid(&why)) return fail("nesc");
  return true;
}

proto::VisionConfig ToProto(const VisionOptions& options) {
  proto::VisionConfig config;
  proto::EdgeDetectionConfig* edges = config.mutable_edges();
  edges->set_low_threshold(options.edges.low_threshold);
  edges->set_high_threshold(options.edges.high_threshold);
  edges->set_canny_threshold1(options.edges.canny_threshold1);
  edges->set_canny_threshold2(options.edges.canny_threshold2);
  edges->set_canny_aperture_px(options.edges.canny_aperture_px);
  edges->set_l2_gradient(options.edges.l2_gradient);
  edges->set_colour_edges(options.edges.colour_edges);
  proto::NearestEdgeConfig* ned = config.mutable_nearest_edge();
  ned->set_max_range_m(options.nearest_edge.max_range_m);
  ned->set_step_px(options.nearest_edge.step_px);
  ned->set_lateral_tolerance_px(options.nearest_edge.lateral_tolerance_px);
  ned->set_bottom_margin_px(options.nearest_edge.bottom_margin_px);
  ned->set_base_search_m(options.nearest_edge.base_search_m);
  ned->set_min_step_grey(options.nearest_edge.min_step_grey);
  ned->set_step_offset_px(options.nearest_edge.step_offset_px);
  ned->set_min_crossing_angle_deg(options.nearest_edge.min_crossing_angle_deg);
  ned->set_start_grey_deviation(options.nearest_edge.start_grey_deviation);
  const FloorStereoOptions& floor = options.nearest_edge.floor_stereo;
  proto::FloorStereoConfig* floor_config = ned->mutable_floor_stereo();
  floor_config->set_enabled(floor.enabled);
  floor_config->set_near_px(floor.near_px);
  floor_config->set_far_px(floor.far_px);
  floor_config->set_half_width_px(floor.half_width_px);
  floor_config->set_min_gradient(floor.min_gradient);
  floor_config->set_max_difference(floor.max_difference);
  floor_config->set_min_judged(floor.min_judged);
  floor_config->set_floor_share(floor.floor_share);
  floor_config->set_margin(floor.margin);
  floor_config->set_min_separation_px(floor.min_separation_px);
  floor_config->set_half_width_m(floor.half_width_m);
  config.set_edge_threshold_m(options.classifier.edge_threshold_m);
  config.set_stereo_threshold_m(options.nesc.stereo_threshold_m);
  config.set_stereo(options.stereo);
  config.set_keep_edge_images(options.keep_edge_images);
  config.set_min_threshold_px(options.classifier.min_threshold_px);
  config.set_neighbour_beams(options.classifier.neighbour_beams);
  config.set_min_obstacle_beams(options.classifier.min_obstacle_beams);
  return config;
}

VisionOptions FromProto(const proto::VisionConfig& config) {
  VisionOptions options;
  const proto::EdgeDetectionConfig& edges = config.edges();
  options.edges.low_threshold = edges.low_threshold();
  options.edges.high_threshold = edges.high_threshold();
  options.edges.canny_threshold1 = edges.canny_threshold1();
  options.edges.canny_threshold2 = edges.canny_threshold2();
  options.edges.canny_aperture_px = edges.canny_aperture_px();
  options.edges.l2_gradient = edges.l2_gradient();
  options.edges.colour_edges = edges.colour_edges();
  const proto::NearestEdgeConfig& ned = config.nearest_edge();
  options.nearest_edge.max_range_m = ned.max_range_m();
  options.nearest_edge.step_px = ned.step_px();
  options.nearest_edge.lateral_tolerance_px = ned.lateral_tolerance_px();
  options.nearest_edge.bottom_margin_px = ned.bottom_margin_px();
  options.nearest_edge.base_search_m = ned.base_search_m();
  options.nearest_edge.min_step_grey = ned.min_step_grey();
  options.nearest_edge.step_offset_px = ned.step_offset_px();
  options.nearest_edge.min_crossing_angle_deg = ned.min_crossing_angle_deg();
  options.nearest_edge.start_grey_deviation = ned.start_grey_deviation();
  const proto::FloorStereoConfig& floor_config = ned.floor_stereo();
  FloorStereoOptions& floor = options.nearest_edge.floor_stereo;
  floor.enabled = floor_config.enabled();
  floor.near_px = floor_config.near_px();
  floor.far_px = floor_config.far_px();
  floor.half_width_px = floor_config.half_width_px();
  floor.min_gradient = floor_config.min_gradient();
  floor.max_difference = floor_config.max_difference();
  floor.min_judged = floor_config.min_judged();
  floor.floor_share = floor_config.floor_share();
  floor.margin = floor_config.margin();
  floor.min_separation_px = floor_config.min_separation_px();
  floor.half_width_m = floor_config.half_width_m();
  options.classifier.edge_threshold_m = config.edge_threshold_m();
  options.nesc.stereo_threshold_m = config.has_stereo_threshold_m()
                                        ? config.stereo_threshold_m()
                                        : 0.5 * config.edge_threshold_m();
  options.stereo = config.stereo();
  options.keep_edge_images = config.keep_edge_images();
  options.classifier.min_threshold_px = config.min_threshold_px();
  options.nesc.min_threshold_px = config.min_threshold_px();
  options.classifier.neighbour_beams = config.neighbour_beams();
  options.classifier.min_obstacle_beams = config.min_obstacle_beams();
  return options;
}

VisionPipeline::VisionPipeline(const VisionOptions& options)
    : options_(options),
      detector_(options.edges),
      left_finder_(options.nearest_edge),
      right_finder_(options.nearest_edge) {
  MOSTAR_CHECK(options_.IsValid(nullptr));
}

VisionResult VisionPipeline::Process(const VisionInput& input) {
  VisionResult result;
  Process(input, &result);
  return result;
}

void VisionPipeline::Process(const VisionInput& input, VisionResult* out) {
  MOSTAR_CHECK(out != nullptr);
  const auto start = std::chrono::steady_clock::now();
  out->stamp = input.stamp;
  out->sequence = input.sequence;
  out->scan = input.scan;
  out->placement = input.placement;
  out->ok = false;
  out->error.clear();
  out->stereo = options_.stereo;
  out->nesc = NescResult{};
  const auto finish = [&](bool ok, const std::string& error) {
    out->ok = ok;
    out->error = error;
    if (!options_.keep_edge_images) {
      out->left_edges = EdgeImages{};
      out->right_edges = EdgeImages{};
    }
    out->processing_time =
        std::chrono::duration_cast<Duration>(std::chrono::steady_clock::now() - start);
  };
  std::string error;
  if (input.left_camera == nullptr || (options_.stereo && input.right_camera == nullptr)) {
    return finish(false, "missing camera model");
  }
  const size_t beams = input.scan.ranges_m.size();
  if (!input.potential_outliers.empty() && input.potential_outliers.size() != beams) {
    std::ostringstream why;
    why << "got " << input.potential_outliers.size() << " outlier labels for " << beams << " beams";
    return finish(false, why.str());
  }

  // One eye: the ray cache first (it gives the highest row the rays reach), then the
  // pre-processing below that row only. Writes only its own outputs and `why`.
  const auto detect_eye =
      [&](const cv::Mat& image, const std::shared_ptr<const math::CameraModel>& camera_ptr,
          NearestEdgeFinder* finder, const char* name, EdgeImages* edges, std::string* why) {
        const math::CameraModel& camera = *camera_ptr;
        if (image.cols != camera.width_px() || image.rows != camera.height_px()) {
          std::ostringstream message;
          message << name << " image is " << image.cols << "x" << image.rows << ", camera model is "
                  << camera.width_px() << "x" << camera.height_px();
          *why = message.str();
          return false;
        }
        std::string detail;
        if (!finder->Prepare(camera_ptr, input.scan, &detail) ||
            !detector_.Detect(image, edges, &detail, finder->top_row())) {
          *why = std::string(name) + ": " + detail;
          return false;
        }
        return true;
      };
  // Then NED on that eye (`floor`: its images for the floor test, or null).
  const auto find_eye = [&](const std::shared_ptr<const math::CameraModel>& camera_ptr,
                            NearestEdgeFinder* finder, const char* name, const EdgeImages& edges,
                            const FloorStereoImages* floor, NedResult* ned, std::string* why) {
    std::string detail;
    if (!finder->Find(edges.edges, camera_ptr, input.scan, ned, &detail, edges.stretched_grey,
                      floor)) {
      *why = std::string(name) + ": " + detail;
      return false;
    }
    return true;
  };
  const auto run_eye = [&](const cv::Mat& image,
                           const std::shared_ptr<const math::CameraModel>& camera_ptr,
                           NearestEdgeFinder* finder, const char* name, EdgeImages* edges,
                           NedResult* ned, std::string* why) {
    return detect_eye(image, camera_ptr, finder, name, edges, why) &&
           find_eye(camera_ptr, finder, name, *edges, nullptr, ned, why);
  };

  if (options_.stereo) {
    // The two eyes are independent: one on each core. With the floor test, each eye's NED also
    // needs the other eye's stretched image: edges on both first, then the warps and NED.
    bool ok[2] = {false, false};
    std::string why[2];
    const bool floor_test = options_.nearest_edge.floor_stereo.enabled;
    cv::parallel_for_(cv::Range(0, 2), [&](const cv::Range& range) {
      for (int eye = range.start; eye < range.end; ++eye) {
        if (floor_test) {
          ok[eye] = eye == 0 ? detect_eye(input.left, input.left_camera, &left_finder_, "left",
                                          &out->left_edges, &why[0])
                             : detect_eye(input.right, input.right_camera, &right_finder_, "right",
                                          &out->right_edges, &why[1]);
        } else {
          ok[eye] = eye == 0 ? run_eye(input.left, input.left_camera, &left_finder_, "left",
                                       &out->left_edges, &out->left_ned, &why[0])
                             : run_eye(input.right, input.right_camera, &right_finder_, "right",
                                       &out->right_edges, &out->right_ned, &why[1]);
        }
      }
    });
    if (!ok[0] || !ok[1]) return finish(false, !ok[0] ? why[0] : why[1]);
    if (floor_test) {
      cv::parallel_for_(cv::Range(0, 2), [&](const cv::Range& range) {
        for (int eye = range.start; eye < range.end; ++eye) {
          const bool left = eye == 0;
          FloorWarp& warp = left ? left_floor_warp_ : right_floor_warp_;
          FloorStereoImages& images = left ? left_floor_ : right_floor_;
          const auto& self = left ? input.left_camera : input.right_camera;
          const auto& other = left ? input.right_camera : input.left_camera;
          NearestEdgeFinder& finder = left ? left_finder_ : right_finder_;
          const EdgeImages& own = left ? out->left_edges : out->right_edges;
          const EdgeImages& others = left ? out->right_edges : out->left_edges;
          if (!warp.Prepare(self, other, finder.top_row(), &why[eye])) {
            ok[eye] = false;
            continue;
          }
          images.grey = own.stretched_grey;
          images.other = others.stretched_grey;
          warp.Warp(others.stretched_grey, &images.warped);
          images.valid = warp.valid();
          images.shift = warp.shift();
          images.focal_px = self->calibration().fx();
          ok[eye] = find_eye(self, &finder, left ? "left" : "right", own, &images,
                             left ? &out->left_ned : &out->right_ned, &why[eye]);
        }
      });
      if (!ok[0] || !ok[1]) return finish(false, !ok[0] ? why[0] : why[1]);
    }
    if (!RunNesc(out->left_ned, out->right_ned, input.scan, *input.right_camera, options_.nesc,
                 options_.classifier, &out->nesc, &error)) {
      return finish(false, "nesc: " + error);
    }
    out->selected = out->nesc.selected;
  } else {
    if (!run_eye(input.left, input.left_camera, &left_finder_, "left", &out->left_edges,
                 &out->left_ned, &error)) {
      return finish(false, error);
    }
    out->right_edges = EdgeImages{};
    out->right_ned = NedResult{};
    out->selected = out->left_ned.neps;
  }
  if (!ClassifyNeps(input.scan, out->selected, input.potential_outliers, options_.classifier,
                    input.left_camera->calibration().laser_height_m, &out->classification,
                    &error)) {
    return finish(false, "classifier: " + error);
  }
  finish(true, "");
}

}  // namespace mostar::vision
