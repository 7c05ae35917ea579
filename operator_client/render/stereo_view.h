// The two eyes and their compositor for one window: draws the eyes a display mode shows, straight
// into their window regions where each has its own (render::DrawsEyesInPlace), else into the
// eyes' framebuffers, which Compose() then blends into the window. Requires a current OpenGL 3.3
// core context; render thread only.
#pragma once

#include <array>
#include <opencv2/core/mat.hpp>
#include <string>

#include "operator_client/render/display_mode.h"
#include "operator_client/render/eye_renderer.h"
#include "operator_client/render/stereo_compositor.h"

namespace mostar::render {

// One eye's picture: its image (BGR8, may be empty: grey background), view and alignment.
struct EyeInput {
  const cv::Mat* image = nullptr;
  EyeView view;
  EyeAlignment alignment;
};

class StereoView {
 public:
  bool Init(std::string* error);
  // Draws the eyes `mode` shows (index 0 left, 1 right) into a window of `window_w` x
  // `window_h` framebuffer pixels, each with `overlay`.
  void DrawEyes(DisplayMode mode, bool quad_buffer_available, int window_w, int window_h,
                const std::array<EyeInput, 2>& eyes, const OverlayGeometry& overlay);
  // For modes that blend both eyes: the compositor's pass into the window. Nothing for modes
  // whose eyes DrawEyes put in place.
  void Compose(DisplayMode mode, bool quad_buffer_available, int window_w, int window_h);

 private:
  EyeRenderer eyes_[2];
  StereoCompositor compositor_;
};

}  // namespace mostar::render
