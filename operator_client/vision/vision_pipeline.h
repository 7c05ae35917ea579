// One frame pair through the whole edge processing of the operator client: contrast stretching
// and Canny on each eye (thesis 8.1), NED on each (8.2), NESC (9.2), then the laser
// double-check and overlay correction (8.3, 8.4). Plain data in, plain data out: no OpenGL, no
// DDS. EdgeWorker runs it on a thread; benchmarks and the ground-truth bench call it directly.
//
// Threading: not thread-safe (Process() caches each eye's virtual-ray pixels, rebuilt when the
// camera model pointer or the scan geometry changes); use one pipeline per thread.
#pragma once

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/math/camera_model.h"
#include "common/time/time.h"
#include "common/types/laser_scan.h"
#include "operator_client/vision/edge_detector.h"
#include "operator_client/vision/nearest_edge.h"
#include "operator_client/vision/nep_classifier.h"
#include "operator_client/vision/nesc.h"
#include "operator_client/vision/vision_config.pb.h"

namespace mostar::vision {

// Every parameter of the edge processing. Defaults = the proto defaults.
struct VisionOptions {
  EdgeDetectorOptions edges;
  NearestEdgeOptions nearest_edge;
  NepClassifierOptions classifier;  // edgeTh
  NescOptions nesc;                 // stereoTh (FromProto: edgeTh / 2 unless set)
  bool stereo = true;               // false: monoscopic processing of the left image
  bool keep_edge_images = true;     // keep EdgeImages in the result

  // Checks every part and the thesis' remark that stereoTh < 2 edgeTh is expected (not an
  // error). Returns false with `error` naming the first violated constraint.
  bool IsValid(std::string* error) const;
};

proto::VisionConfig ToProto(const VisionOptions& options);
// Converts a config (ranges already checked by the loader); IsValid() the result before use.
VisionOptions FromProto(const proto::VisionConfig& config);

// Where VisionInput::scan stands relative to the images. The pipeline reads only the scan; the
// placement travels with it to the result, so that whoever draws the result's corrected scan
// knows whether it is already at the images' time (ui::PlaceScanForVision, motion_overlay.h).
struct ScanPlacement {
  // The scan was moved to the images' capture time and resampled on its beam grid
  // (fusion::ResampleAtImageTime): its frame is the base at that time, its stamp the images'.
  // False: the scan as measured.
  bool at_image_time = false;
  bool extrapolated = false;  // at_image_time, with odometry extrapolated for some pose
  Time measured_stamp;        // the stamp of the scan as measured (its first beam)
  std::string reason;         // why it could not be moved; empty when moved or not asked to
};

// The input of one frame pair: both images of one capture, the scan matched to that capture and
// the calibration in force. Images: CV_8UC1, CV_8UC3 (BGR) or CV_8UC4 (BGRA) of the cameras'
// size; `right` may be empty in monoscopic mode. cv::Mat shares its buffer: the caller must not
// write into the images after handing them over.
struct VisionInput {
  Time stamp;             // capture time of the images (the result carries it back)
  uint64_t sequence = 0;  // frame pair counter of the producer
  cv::Mat left;
  cv::Mat right;
  // The scan matched to the images, laser frame; at the images' time when placement says so.
  // Virtual rays start at the laser origin of this scan's frame: a scan not moved to the images'
  // time misregisters edges by the robot's motion in between.
  LaserScan scan;
  ScanPlacement placement;
  // Fusion's discontinuity labelling: one flag per beam, or empty.
  std::vector<bool> potential_outliers;
  std::shared_ptr<const math::CameraModel> left_camera;   // Eye::kLeft (or math::kMonoCamera)
  std::shared_ptr<const math::CameraModel> right_camera;  // Eye::kRight; may be null in mono
};

struct VisionResult {
  Time stamp;             // = VisionInput::stamp: draw this over the frame with this stamp
  uint64_t sequence = 0;  // = VisionInput::sequence
  bool ok = false;        // false: `error` says why; nothing else is meaningful
  std::string error;
  bool stereo = false;    // NESC ran (else `selected` comes from the left image alone)
  EdgeImages left_edges;  // empty unless keep_edge_images
  EdgeImages right_edges;
  NedResult left_ned;
  NedResult right_ned;
  NescResult nesc;            // stereo only
  std::vector<Nep> selected;  // per beam, the NEPs that were classified
  NepClassification classification;
  LaserScan scan;               // = VisionInput::scan: the beams the decisions refer to
  ScanPlacement placement;      // = VisionInput::placement
  Duration processing_time{0};  // wall time of Process()
  SteadyTime published;         // when EdgeWorker published it (its clock); unset by Process()
};

class VisionPipeline {
 public:
  // `options` must be valid (asserted).
  explicit VisionPipeline(const VisionOptions& options);

  // Processes one input. Bad input (missing camera, wrong image type or size, beam count
  // mismatch) gives ok = false with a message; never throws for bad data.
  VisionResult Process(const VisionInput& input);
  void Process(const VisionInput& input, VisionResult* out);

  const VisionOptions& options() const { return options_; }

 private:
  VisionOptions options_;
  EdgeDetector detector_;
  NearestEdgeFinder left_finder_;
  NearestEdgeFinder right_finder_;
  // The floor test (NearestEdgeOptions::floor_stereo): each eye's warp of the other's image.
  FloorWarp left_floor_warp_;
  FloorWarp right_floor_warp_;
  FloorStereoImages left_floor_;
  FloorStereoImages right_floor_;
};

}  // namespace mostar::vision
