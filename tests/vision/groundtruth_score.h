// For tests and benches only (links the simulator): edge processing scored against the
// simulator's ground truth, scene by scene (docs/vision.md, "Against the simulator's ground
// truth"). Per scene: precision and recall of the "obstacle the laser misses" dots (mono = right
// image alone, thesis 8; stereo = NESC, thesis 9.2), the stray NEPs NESC removes, and the
// overlay misalignment in pixels before and after NEP correction under a deliberately perturbed
// calibration.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "operator_client/vision/vision_config.pb.h"

namespace mostar::vision {

// A scene of deploy/scenes/ with the edge profile an operator would tune for its floor in the
// edge-calibration view.
struct GroundTruthScene {
  std::string name;   // deploy/scenes/<name>.pbtxt
  std::string floor;  // a word for the table
  int low_threshold = 60;
  int high_threshold = 200;
  int min_step_grey = 0;  // step test against thin floor lines (0 = off)
};

// The open room (plain floor), the corridor (faint tiles), the checkerboard room and the tiled
// room (tiles with dark joints, tape, obstacles below the laser).
std::vector<GroundTruthScene> GroundTruthScenes();

// The frames scored and how the images are made.
struct GroundTruthRun {
  int frames = 12;
  // Held-out frames: the tuning frames (false: one per second from the start, turning left
  // first) or others (true: half a second later, along a path that turns right first), never
  // used to choose a threshold.
  bool held_out = false;
  double noise_sigma = 3.0;           // image noise, grey levels
  double artifact_probability = 0.5;  // dark blob in the right eye, per frame
  double tilt_error_rad = 0.012;      // the perturbed calibration of the alignment columns
  double height_error_m = 0.02;
  double right_vertical_offset_px = 0.0;  // right principal point shift unknown to the client
  double k1 = 0.0;                        // radial lens distortion of both cameras (known)
  bool below_laser_only = false;   // positives: bases below the scan plane only (not no-echo)
  std::FILE* list_dots = nullptr;  // every stereo dot (TP/FP) and missed positive, when set
  std::string images_out;          // directory for the first frame's debug images, when set
};

// Counts over a scene's frames; ratios in percent (NaN without a denominator).
struct GroundTruthScore {
  int frames = 0;
  int positives = 0;  // beams with an obstacle the laser misses, visible and within reach
  int mono_dots = 0, mono_true = 0, mono_found = 0;
  int stereo_dots = 0, stereo_true = 0, stereo_found = 0;
  int stray = 0, stray_survived = 0;  // NEPs > 6 px from every base line, and kept after NESC
  int real = 0, real_survived = 0;
  std::vector<double> before_px, after_px;  // alignment error per beam, perturbed calibration
  int aligned_beams = 0, corrected_beams = 0;
  int offset_valid = 0;  // frames with a stereo offset hint, and their sum
  double offset_sum_px = 0;

  double MonoPrecision() const;
  double MonoRecall() const;
  double StereoPrecision() const;
  double StereoRecall() const;
  // The docs/vision.md table's row: | scene | floor | frames | ... | beams corrected |
  std::string TableRow(const GroundTruthScene& scene) const;
};

// The table's header (two lines).
std::string GroundTruthTableHeader();

// Runs the pipeline over `run`'s frames of `scene` with the options of `file` (a client
// configuration's `vision`; the scene's stretch thresholds and step test where `file` leaves
// them unset). False with a message when the scene or the pipeline fails.
bool ScoreAgainstGroundTruth(const GroundTruthScene& scene, const proto::VisionConfig& file,
                             const GroundTruthRun& run, GroundTruthScore* score,
                             std::string* error);

}  // namespace mostar::vision
