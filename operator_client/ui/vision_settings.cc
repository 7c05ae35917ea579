#include "operator_client/ui/vision_settings.h"

#include <cmath>

#include "common/check/check.h"
#include "common/config/config_loader.h"

namespace mostar::ui {

VisionSettings::VisionSettings(const vision::VisionOptions& options) : options_(options) {
  MOSTAR_CHECK(options_.IsValid(nullptr));
  stereo_follows_edge_ = std::abs(options_.nesc.stereo_threshold_m -
                                  0.5 * options_.classifier.edge_threshold_m) < 1e-12;
}

bool VisionSettings::Apply(const vision::VisionOptions& next, bool follows, std::string* error) {
  vision::VisionOptions candidate = next;
  if (follows) candidate.nesc.stereo_threshold_m = 0.5 * candidate.classifier.edge_threshold_m;
  if (!candidate.IsValid(error)) return false;
  options_ = candidate;
  stereo_follows_edge_ = follows;
  return true;
}

bool VisionSettings::SetEdgeThreshold(double edge_threshold_m, std::string* error) {
  vision::VisionOptions next = options_;
  next.classifier.edge_threshold_m = edge_threshold_m;
  return Apply(next, stereo_follows_edge_, error);
}

bool VisionSettings::SetStereoThreshold(double stereo_threshold_m, std::string* error) {
  vision::VisionOptions next = options_;
  next.nesc.stereo_threshold_m = stereo_threshold_m;
  return Apply(next, false, error);
}

bool VisionSettings::FollowEdgeThreshold(std::string* error) {
  return Apply(options_, true, error);
}

bool VisionSettings::Set(const vision::VisionOptions& options, std::string* error) {
  return Apply(options, stereo_follows_edge_, error);
}

vision::proto::VisionConfig VisionSettings::ToConfig() const {
  vision::proto::VisionConfig config = vision::ToProto(options_);
  if (stereo_follows_edge_) config.clear_stereo_threshold_m();
  return config;
}

bool VisionSettings::Save(const std::string& path, std::string* error) const {
  return SaveTextConfig(path, ToConfig(), error);
}

bool VisionSettings::Load(const std::string& path, std::string* error) {
  vision::proto::VisionConfig config;
  if (!LoadTextConfig(path, &config, error)) return false;
  std::string why;
  const vision::VisionOptions loaded = vision::FromProto(config);
  if (!loaded.IsValid(&why)) {
    if (error != nullptr) *error = path + ": " + why;
    return false;
  }
  options_ = loaded;
  stereo_follows_edge_ = !config.has_stereo_threshold_m();
  return true;
}

std::string VisionSettingsPath(const std::string& calibration_path) {
  std::string base = calibration_path.empty() ? "calibration_profile.pbtxt" : calibration_path;
  const std::string suffix = ".pbtxt";
  if (base.size() >= suffix.size() &&
      base.compare(base.size() - suffix.size(), suffix.size(), suffix) == 0) {
    base.resize(base.size() - suffix.size());
  }
  return base + ".vision.pbtxt";
}

}  // namespace mostar::ui
