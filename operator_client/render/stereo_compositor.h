// Combines the two eyes' rendered images (EyeRenderer textures) into the window for a display
// mode. Requires a current OpenGL 3.3 core context; render thread only.
#pragma once

#include <string>

#include "operator_client/render/display_mode.h"
#include "operator_client/render/gl_program.h"

namespace mostar::render {

class StereoCompositor {
 public:
  bool Init(std::string* error);
  // Draws into the default framebuffer of `window_width` x `window_height` pixels, each eye
  // where EyeViewports() puts it. For kQuadBuffer, `quad_buffer_available` must be true (else it
  // falls back to kMonoLeft).
  void Compose(DisplayMode mode, unsigned left_texture, unsigned right_texture, int window_width,
               int window_height, bool quad_buffer_available);
  // Binds the window's framebuffer (back buffer) and clears it to black with the state the
  // eyes' RenderInto expects: what Compose does before its pass, for modes whose eyes are drawn
  // in place (DrawsEyesInPlace).
  static void ClearWindow(int window_width, int window_height);
  ~StereoCompositor();

 private:
  void DrawQuad(unsigned left_texture, unsigned right_texture, int shader_mode, int viewport_x,
                int viewport_y, int viewport_w, int viewport_h, int window_height);
  GlProgram program_;
  unsigned vao_ = 0;
};

}  // namespace mostar::render
