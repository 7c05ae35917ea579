#include "operator_client/render/stereo_compositor.h"

#include "operator_client/render/eye_viewports.h"
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

}  // namespace

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

void StereoCompositor::ClearWindow(int window_width, int window_height) {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDrawBuffer(GL_BACK);
  glDisable(GL_BLEND);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_SCISSOR_TEST);
  glViewport(0, 0, window_width, window_height);
  glClearColor(0, 0, 0, 1);
  glClear(GL_COLOR_BUFFER_BIT);
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
  // Shader mode of a single quad showing both eyes; -1 for modes that draw each eye apart.
  int blend_mode = -1;
  if (mode == DisplayMode::kAnaglyphGrey) blend_mode = 2;
  if (mode == DisplayMode::kAnaglyphColor) blend_mode = 3;
  if (mode == DisplayMode::kRowInterlaced) blend_mode = 4;
  const std::vector<EyeViewport> viewports = EyeViewports(mode, w, h);
  if (blend_mode >= 0) {
    const EyeViewport& v = viewports.front();
    DrawQuad(left_texture, right_texture, blend_mode, v.x_px, v.GlY(h), v.width_px, v.height_px, h);
    return;
  }
  for (const EyeViewport& v : viewports) {
    const bool left = v.eye == math::Eye::kLeft;
    if (mode == DisplayMode::kQuadBuffer) {
      glDrawBuffer(left ? GL_BACK_LEFT : GL_BACK_RIGHT);
      glClear(GL_COLOR_BUFFER_BIT);
    }
    DrawQuad(left_texture, right_texture, left ? 0 : 1, v.x_px, v.GlY(h), v.width_px, v.height_px,
             h);
  }
  if (mode == DisplayMode::kQuadBuffer) glDrawBuffer(GL_BACK);
}

}  // namespace mostar::render
