#include "operator_client/render/stereo_compositor.h"

#include <map>

#include "operator_client/render/gl.h"

namespace mostar::render {

namespace {

// Shader modes: 0 left only, 1 right only, 2 grey anaglyph, 3 colour anaglyph, 4 interlaced.
constexpr const char* kVertex = R"(#version 330 core
out vec2 v_uv;
void main() {
  vec2 corner = vec2(float((gl_VertexID & 1)), float((gl_VertexID >> 1) & 1));
  v_uv = corner;
  gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
)";

constexpr const char* kFragment = R"(#version 330 core
uniform sampler2D u_left;
uniform sampler2D u_right;
uniform int u_mode;
uniform int u_window_height;
in vec2 v_uv;
out vec4 color;
float luma(vec3 c) { return dot(c, vec3(0.299, 0.587, 0.114)); }
void main() {
  vec3 l = texture(u_left, v_uv).rgb;
  vec3 r = texture(u_right, v_uv).rgb;
  if (u_mode == 0) color = vec4(l, 1.0);
  else if (u_mode == 1) color = vec4(r, 1.0);
  else if (u_mode == 2) color = vec4(luma(l), luma(r), luma(r), 1.0);
  else if (u_mode == 3) color = vec4(l.r, r.g, r.b, 1.0);
  else {
    // Window row counted from the top: even rows left eye, odd rows right eye.
    int row = u_window_height - 1 - int(gl_FragCoord.y);
    color = vec4((row % 2 == 0) ? l : r, 1.0);
  }
}
)";

const std::map<std::string, DisplayMode>& Names() {
  static const std::map<std::string, DisplayMode> names = {
      {"mono-left", DisplayMode::kMonoLeft},     {"mono-right", DisplayMode::kMonoRight},
      {"anaglyph", DisplayMode::kAnaglyphGrey},  {"anaglyph-color", DisplayMode::kAnaglyphColor},
      {"sbs", DisplayMode::kSideBySideFull},     {"sbs-half", DisplayMode::kSideBySideHalf},
      {"top-bottom", DisplayMode::kTopBottom},   {"interlaced", DisplayMode::kRowInterlaced},
      {"quad-buffer", DisplayMode::kQuadBuffer},
  };
  return names;
}

}  // namespace

const char* DisplayModeName(DisplayMode mode) {
  for (const auto& [name, m] : Names()) {
    if (m == mode) return name.c_str();
  }
  return "?";
}

bool ParseDisplayMode(const std::string& text, DisplayMode* mode) {
  const auto it = Names().find(text);
  if (it == Names().end()) return false;
  *mode = it->second;
  return true;
}

void WindowSizeFor(DisplayMode mode, int eye_width, int eye_height, int* width, int* height) {
  *width = mode == DisplayMode::kSideBySideFull ? 2 * eye_width : eye_width;
  *height = eye_height;
}

bool StereoCompositor::Init(std::string* error) {
  if (!program_.Build(kVertex, kFragment, error)) return false;
  glGenVertexArrays(1, &vao_);
  return true;
}

StereoCompositor::~StereoCompositor() {
  if (vao_) glDeleteVertexArrays(1, &vao_);
}

void StereoCompositor::DrawQuad(unsigned left_texture, unsigned right_texture, int shader_mode,
                                int viewport_x, int viewport_y, int viewport_w, int viewport_h,
                                int window_height) {
  glViewport(viewport_x, viewport_y, viewport_w, viewport_h);
  program_.Use();
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, left_texture);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, right_texture);
  glUniform1i(program_.Uniform("u_left"), 0);
  glUniform1i(program_.Uniform("u_right"), 1);
  glUniform1i(program_.Uniform("u_mode"), shader_mode);
  glUniform1i(program_.Uniform("u_window_height"), window_height);
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
  glBindVertexArray(0);
  glActiveTexture(GL_TEXTURE0);
}

void StereoCompositor::Compose(DisplayMode mode, unsigned left_texture, unsigned right_texture,
                               int w, int h, bool quad_buffer_available) {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDisable(GL_BLEND);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_SCISSOR_TEST);
  glClearColor(0, 0, 0, 1);
  if (mode == DisplayMode::kQuadBuffer && !quad_buffer_available) mode = DisplayMode::kMonoLeft;
  if (mode != DisplayMode::kQuadBuffer) {
    glDrawBuffer(GL_BACK);
    glClear(GL_COLOR_BUFFER_BIT);
  }
  switch (mode) {
    case DisplayMode::kMonoLeft:
      DrawQuad(left_texture, right_texture, 0, 0, 0, w, h, h);
      break;
    case DisplayMode::kMonoRight:
      DrawQuad(left_texture, right_texture, 1, 0, 0, w, h, h);
      break;
    case DisplayMode::kAnaglyphGrey:
      DrawQuad(left_texture, right_texture, 2, 0, 0, w, h, h);
      break;
    case DisplayMode::kAnaglyphColor:
      DrawQuad(left_texture, right_texture, 3, 0, 0, w, h, h);
      break;
    case DisplayMode::kSideBySideFull:
    case DisplayMode::kSideBySideHalf:
      DrawQuad(left_texture, right_texture, 0, 0, 0, w / 2, h, h);
      DrawQuad(left_texture, right_texture, 1, w / 2, 0, w - w / 2, h, h);
      break;
    case DisplayMode::kTopBottom:
      DrawQuad(left_texture, right_texture, 0, 0, h - h / 2, w, h / 2, h);
      DrawQuad(left_texture, right_texture, 1, 0, 0, w, h - h / 2, h);
      break;
    case DisplayMode::kRowInterlaced:
      DrawQuad(left_texture, right_texture, 4, 0, 0, w, h, h);
      break;
    case DisplayMode::kQuadBuffer:
      glDrawBuffer(GL_BACK_LEFT);
      glClear(GL_COLOR_BUFFER_BIT);
      DrawQuad(left_texture, right_texture, 0, 0, 0, w, h, h);
      glDrawBuffer(GL_BACK_RIGHT);
      glClear(GL_COLOR_BUFFER_BIT);
      DrawQuad(left_texture, right_texture, 1, 0, 0, w, h, h);
      glDrawBuffer(GL_BACK);
      break;
  }
}

}  // namespace mostar::render
