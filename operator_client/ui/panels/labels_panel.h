// The AR distance labels ("1.35 m"), drawn as ImGui text over each eye's image at the
// projection of their anchors. ImGui; render thread.
#pragma once

#include "common/math/camera_model.h"
#include "operator_client/fusion/ar_features.h"
#include "operator_client/render/display_mode.h"

namespace mostar::ui {

// Eyes are placed by render::EyeViewports(mode, framebuffer_w, framebuffer_h); where both
// eyes share one rectangle (anaglyphs, interlaced, quad buffer) the labels follow the first.
// `left_display`/`right_display`: each eye's display model (render/eye_geometry.h); the
// displayed image has no lens distortion, so labels sit at its pinhole projection.
void DrawLabelsPanel(const fusion::ArFeatures& features, const math::CameraModel& left_display,
                     const math::CameraModel& right_display, render::DisplayMode mode,
                     int framebuffer_w, int framebuffer_h);

}  // namespace mostar::ui
