// Where each eye's image lands in the window for a display mode: the one layout both the
// stereo compositor (drawing) and the console (distance labels over each eye) use. Pure.
#pragma once

#include <array>
#include <vector>

#include "common/math/camera_model.h"
#include "operator_client/render/display_mode.h"

namespace mostar::render {

// A rectangle of the window showing one eye's whole image, in framebuffer pixels with the
// origin at the window's top-left corner (x right, y down).
struct EyeViewport {
  math::Eye eye = math::Eye::kLeft;  // kLeft or kRight
  int x_px = 0;
  int y_px = 0;
  int width_px = 0;
  int height_px = 0;

  // The rectangle's bottom edge counted from the window's bottom, as glViewport wants it.
  int GlY(int window_h) const { return window_h - y_px - height_px; }
  bool SameRect(const EyeViewport& other) const {
    return x_px == other.x_px && y_px == other.y_px && width_px == other.width_px &&
           height_px == other.height_px;
  }
};

// The eyes' rectangles for `mode` in a window of `window_w` x `window_h` framebuffer pixels,
// left eye first. Side-by-side and top-bottom split the window (the left or top part gets
// the smaller half of an odd size); mono modes give their eye the whole window; modes that
// blend both eyes over the whole window (anaglyphs, row interlacing, quad buffer) give both
// eyes the whole window.
std::vector<EyeViewport> EyeViewports(DisplayMode mode, int window_w, int window_h);

// Which eyes (by math::Eye index: left, right) `mode` puts on screen; the others need not be
// drawn. Quad-buffer stereo without a stereo framebuffer shows the left eye (the compositor's
// fallback).
std::array<bool, 2> EyesShown(DisplayMode mode, bool quad_buffer_available);

// True when `mode` shows each eye in a region of its own (mono, side by side, top-bottom): the
// eyes can be drawn straight into the window, without the compositor's pass over both.
bool DrawsEyesInPlace(DisplayMode mode);

}  // namespace mostar::render
