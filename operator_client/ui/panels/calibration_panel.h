// The calibration and AR panel (C), in collapsible sections: the laser-camera calibration
// sliders in the thesis' order with save/load/reset of the profile (with the stereo alignment);
// the self-calibration's proposal against the current values with both reprojection errors
// (Apply / Reject; never applied without the click; its state in the section's title); the AR
// feature switches and colour thresholds; the stereo alignment of the right eye (model,
// offsets, NESC's vertical offset suggestion with Apply) and the display mode. Edits go
// straight into the caller's values; a calibration edit that would be invalid is refused
// (status line). ImGui; render thread.
#pragma once

#include <optional>
#include <string>

#include "common/math/camera_model.h"
#include "operator_client/fusion/ar_features.h"
#include "operator_client/render/display_mode.h"
#include "operator_client/render/eye_geometry.h"
#include "operator_client/ui/console_self_calibration.h"
#include "operator_client/ui/stereo_hint.h"

namespace mostar::ui {

// What the panel edits; every pointer non-null and owned by the caller.
struct CalibrationPanelTargets {
  bool* open;  // cleared when the operator closes the panel
  math::LaserCameraCalibration* calibration;
  fusion::ArFeatureOptions* ar;
  render::EyeAlignment* left_alignment;   // crop follows the right eye's offset
  render::EyeAlignment* right_alignment;  // offset edited here
  render::AlignmentModel* alignment_model;
  render::DisplayMode* mode;
  std::string* status_line;  // outcome of save/load, refused edits
  // The self-refining calibration's proposal with Apply and Reject; null: no such section.
  ConsoleSelfCalibration* self_calibration = nullptr;
};

// `profile_path`: where Save writes and Load reads (empty: calibration_profile.pbtxt).
// `hint`: NESC's suggestion for the right eye's vertical offset, when there is one.
void DrawCalibrationPanel(const std::string& profile_path, const CalibrationPanelTargets& edit,
                          const std::optional<StereoOffsetHint>& hint);

}  // namespace mostar::ui
