// Nearest edges stereo correspondence, NESC (thesis 9.2), and the stereo image-offset hint
// (thesis 9.1) measured from the same NEP pairs.
//
// NED runs on both images with the same virtual rays (one per beam, from the robot base). Real
// obstacle bases are strong features seen by both eyes; artefacts and weak edges usually appear
// in one eye only. Per beam:
//   - a NEP in one image only is unreliable;
//   - NEPs in both images closer than stereoTh (floor distance; they lie on the same ray) make
//     one reliable NEP at their midpoint;
//   - NEPs farther apart are both unreliable: the one agreeing with the laser (within edgeTh) is
//     kept, the nearer one when both agree (a safety choice); none when neither agrees.
// The selected NEPs then go to ClassifyNeps, which uses unreliable NEPs only when they agree
// with the laser (alignment), and reliable ones for alignment and laser correction.
//
// Pure functions: safe to call from any thread.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/math/camera_model.h"
#include "common/types/laser_scan.h"
#include "operator_client/vision/nearest_edge.h"
#include "operator_client/vision/nep_classifier.h"

namespace mostar::vision {

struct NescOptions {
  // stereoTh, metres, in (0, 5]. The thesis used edgeTh / 2.
  double stereo_threshold_m = 0.05;
  // As NepClassifierOptions::min_threshold_px: left and right NEPs within this many pixels
  // (mean of their metres_per_px) also match; 0 = the thesis' rule alone; in [0, 20].
  double min_threshold_px = 2.0;
  // Stereo offset hint: only beams whose left and right NEP rows differ by at most this many
  // pixels (after projecting the left NEP into the right image) take part; in (0, 100].
  double offset_max_residual_px = 15.0;
  // ... and at least this many of them, else the hint is not given; >= 1.
  int offset_min_samples = 12;

  bool IsValid(std::string* error) const;
};

enum class StereoNepKind : uint8_t {
  kNone,       // no NEP in either image
  kLeftOnly,   // unreliable
  kRightOnly,  // unreliable
  kMatched,    // both, within stereoTh: one reliable NEP at the midpoint
  kDisagree,   // both, farther apart than stereoTh: both unreliable
};

const char* StereoNepKindName(StereoNepKind kind);

// Suggested vertical offset between the eyes' images (thesis 9.1, fig. 35), measured where both
// eyes found the same edge: residual = row of the right NEP - row at which the right camera
// model expects the left NEP's floor point. Over mostly horizontal obstacle bases this residual
// is the vertical misalignment of the right image relative to the left one that the calibration
// does not explain. The horizontal offset is not observable this way (along the nearly radial
// virtual rays a horizontal shift changes where a horizontal base is met very little) and is
// left to the operator's feedback calibration.
struct StereoOffsetEstimate {
  bool valid = false;             // enough samples (NescOptions::offset_min_samples)
  double vertical_offset_px = 0;  // median residual; > 0: right image content sits LOWER, so
                                  // shift the right image up (or the left down) by this much
  double spread_px = 0;           // median absolute deviation of the residuals
  int samples = 0;
};

struct NescResult {
  std::vector<StereoNepKind> kinds;  // per beam
  // Per beam: the NEP to classify (found = false when none); reliable = kMatched. Its floor
  // point is in the laser frame and its pixel is in the right image.
  std::vector<Nep> selected;
  int matched = 0;            // reliable NEPs
  int one_eye = 0;            // kLeftOnly + kRightOnly
  int disagree = 0;           // kDisagree
  int disagree_resolved = 0;  // kDisagree beams where one NEP agreed with the laser
  StereoOffsetEstimate offset;
};

// `left` and `right` are the NED results of the two images over `scan` (same beam count);
// `right_camera` is the model the right one was computed with (selected pixels and the offset
// hint are in the right image). `classifier` gives edgeTh. Returns false with `error` on size
// mismatches or invalid options (out: no NEPs).
bool RunNesc(const NedResult& left, const NedResult& right, const LaserScan& scan,
             const math::CameraModel& right_camera, const NescOptions& options,
             const NepClassifierOptions& classifier, NescResult* out, std::string* error);

}  // namespace mostar::vision
