// The edge thresholds as the operator edits them live (edge view, V), keeping the thesis'
// relation stereoTh = edgeTh / 2 (9.2) until the operator sets stereoTh on its own, and their
// save/load as a VisionConfig text file (operator_client/vision/vision_config.proto, the same
// message as the client configuration's `vision`) beside the calibration profile. Pure.
#pragma once

#include <string>

#include "operator_client/vision/vision_pipeline.h"

namespace mostar::ui {

class VisionSettings {
 public:
  // `options` must be valid (asserted). stereoTh follows edgeTh when it is edgeTh / 2.
  explicit VisionSettings(const vision::VisionOptions& options);

  const vision::VisionOptions& options() const { return options_; }
  // True while stereoTh is edgeTh / 2 and follows it.
  bool stereo_follows_edge() const { return stereo_follows_edge_; }

  // Each returns false with `error` (and changes nothing) when the result would be invalid.
  // edgeTh, metres; stereoTh follows it unless set on its own.
  bool SetEdgeThreshold(double edge_threshold_m, std::string* error);
  // stereoTh, metres; from now on it no longer follows edgeTh.
  bool SetStereoThreshold(double stereo_threshold_m, std::string* error);
  // stereoTh follows edgeTh again (stereoTh = edgeTh / 2 at once).
  bool FollowEdgeThreshold(std::string* error);
  // Any options (the other sliders); stereoTh keeps following edgeTh if it did.
  bool Set(const vision::VisionOptions& options, std::string* error);

  // The config to save: stereo_threshold_m only when set on its own.
  vision::proto::VisionConfig ToConfig() const;
  bool Save(const std::string& path, std::string* error) const;
  // Replaces everything from the file (refused with file, key and reason; nothing changes).
  bool Load(const std::string& path, std::string* error);

 private:
  bool Apply(const vision::VisionOptions& next, bool follows, std::string* error);

  vision::VisionOptions options_;
  bool stereo_follows_edge_ = true;
};

// Where the vision settings live beside a calibration profile: "<profile without .pbtxt>
// .vision.pbtxt" ("calibration_profile.vision.pbtxt" for an empty path).
std::string VisionSettingsPath(const std::string& calibration_path);

}  // namespace mostar::ui
