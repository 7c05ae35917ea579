// Combines the two eyes' rendered images (EyeRenderer textures) into the window for a display
// mode. Requires a current OpenGL 3.3 core context; render thread only.
#pragma once

#include <string>

#include "operator_client/render/gl_program.h"

namespace mostar::render {

enum class DisplayMode {
  kMonoLeft,
  kMonoRight,
  kAnaglyphGrey,    // red-cyan from each eye's luminance (least retinal rivalry)
  kAnaglyphColor,   // red-cyan keeping colours: left red channel, right green and blue
  kSideBySideFull,  // left | right, each eye at full width (window twice as wide)
  kSideBySideHalf,  // left | right squeezed into one frame (3D TVs)
  kTopBottom,       // left above right, squeezed vertically
  kRowInterlaced,   // even window rows left eye, odd rows right eye (polarised monitors)
  kQuadBuffer,      // OpenGL quad-buffered stereo (needs a stereo-capable driver)
};

const char* DisplayModeName(DisplayMode mode);
// Parses the names above ("mono-left", "anaglyph", "anaglyph-color", "sbs", "sbs-half",
// "top-bottom", "interlaced", "quad-buffer").
bool ParseDisplayMode(const std::string& text, DisplayMode* mode);
// Window size suited to a mode for eyes of `eye_width` x `eye_height`.
void WindowSizeFor(DisplayMode mode, int eye_width, int eye_height, int* width, int* height);

class StereoCompositor {
 public:
  bool Init(std::string* error);
  // Draws into the default framebuffer of `window_width` x `window_height` pixels.
  // For kQuadBuffer, `quad_buffer_available` must be true (else it falls back to kMonoLeft).
  void Compose(DisplayMode mode, unsigned left_texture, unsigned right_texture, int window_width,
               int window_height, bool quad_buffer_available);
  ~StereoCompositor();

 private:
  void DrawQuad(unsigned left_texture, unsigned right_texture, int shader_mode, int viewport_x,
                int viewport_y, int viewport_w, int viewport_h, int window_height);
  GlProgram program_;
  unsigned vao_ = 0;
};

}  // namespace mostar::render
