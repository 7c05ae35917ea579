#include "operator_client/render/eye_renderer.h"

#include <algorithm>

namespace mostar::render {

namespace {

// Full-viewport quad from a vertex id; v_corner runs 0..1 across the viewport, bottom-left up.
constexpr const char* kImageVertex = R"(#version 330 core
out vec2 v_corner;
void main() {
  vec2 corner = vec2(float((gl_VertexID & 1)), float((gl_VertexID >> 1) & 1));
  v_corner = corner;
  gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
)";

// Each displayed pixel q (u right, v down, pixel centres at integers) shows the camera-image
// pixel image_c + f * Distort(R (q - display_c) / f): eye_geometry.h, WarpToImage. Texture row 0 is
// the image's top row. Outside the camera image: black. The viewport shows the whole displayed
// image, scaled to fit; the position comes from the quad, not gl_FragCoord, whose transform
// Mesa 22 can leave stale when one program draws into a window and then a framebuffer object.
constexpr const char* kImageFragment = R"(#version 330 core
uniform sampler2D u_image;
uniform int u_has_image;
uniform vec2 u_size;  // displayed image size, px
in vec2 v_corner;
uniform vec2 u_focal;
uniform vec2 u_rotation;  // cos, sin
uniform vec2 u_display_c;
uniform vec2 u_image_c;
uniform vec3 u_radial;      // k1, k2, k3
uniform vec2 u_tangential;  // p1, p2
out vec4 color;
void main() {
  if (u_has_image == 0) {
    color = vec4(0.25, 0.25, 0.25, 1.0);
    return;
  }
  vec2 p = v_corner * u_size;  // from the bottom-left corner, displayed px
  vec2 q = vec2(p.x - 0.5, u_size.y - 0.5 - p.y);
  vec2 m = (q - u_display_c) / u_focal;
  vec2 n = vec2(u_rotation.x * m.x - u_rotation.y * m.y, u_rotation.y * m.x + u_rotation.x * m.y);
  float r2 = dot(n, n);
  float radial = 1.0 + r2 * (u_radial.x + r2 * (u_radial.y + r2 * u_radial.z));
  float p1 = u_tangential.x;
  float p2 = u_tangential.y;
  vec2 d = vec2(n.x * radial + 2.0 * p1 * n.x * n.y + p2 * (r2 + 2.0 * n.x * n.x),
                n.y * radial + p1 * (r2 + 2.0 * n.y * n.y) + 2.0 * p2 * n.x * n.y);
  vec2 uv = (u_image_c + u_focal * d + 0.5) / u_size;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
    color = vec4(0.0, 0.0, 0.0, 1.0);
    return;
  }
  color = vec4(texture(u_image, uv).rgb, 1.0);
}
)";

constexpr const char* kOverlayVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_color;
uniform mat4 u_projection;
uniform mat4 u_view;
uniform float u_point_size;
out vec4 v_color;
void main() {
  gl_Position = u_projection * u_view * vec4(a_position, 1.0);
  gl_PointSize = u_point_size;
  v_color = a_color;
}
)";

constexpr const char* kOverlayFragment = R"(#version 330 core
in vec4 v_color;
out vec4 color;
void main() { color = v_color; }
)";

}  // namespace

EyeView MakeEyeView(const EyeGeometry& geometry) {
  return EyeView{geometry.display.OpenGlMatrices(0.05, 100.0), MakeImageWarp(geometry)};
}

EyeRenderer::~EyeRenderer() {
  if (color_texture_) glDeleteTextures(1, &color_texture_);
  if (depth_buffer_) glDeleteRenderbuffers(1, &depth_buffer_);
  if (framebuffer_) glDeleteFramebuffers(1, &framebuffer_);
  if (position_vbo_) glDeleteBuffers(1, &position_vbo_);
  if (color_vbo_) glDeleteBuffers(1, &color_vbo_);
  if (quad_vao_) glDeleteVertexArrays(1, &quad_vao_);
  if (overlay_vao_) glDeleteVertexArrays(1, &overlay_vao_);
}

bool EyeRenderer::Init(std::string* error) {
  if (!image_program_.Build(kImageVertex, kImageFragment, error)) return false;
  if (!overlay_program_.Build(kOverlayVertex, kOverlayFragment, error)) return false;
  glGenVertexArrays(1, &quad_vao_);
  glGenVertexArrays(1, &overlay_vao_);
  glGenBuffers(1, &position_vbo_);
  glGenBuffers(1, &color_vbo_);
  glBindVertexArray(overlay_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, position_vbo_);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, color_vbo_);
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(1);
  glBindVertexArray(0);
  glGenFramebuffers(1, &framebuffer_);
  return true;
}

void EyeRenderer::EnsureTarget(int width, int height) {
  if (width == width_ && height == height_) return;
  width_ = width;
  height_ = height;
  if (color_texture_) glDeleteTextures(1, &color_texture_);
  if (depth_buffer_) glDeleteRenderbuffers(1, &depth_buffer_);
  glGenTextures(1, &color_texture_);
  glBindTexture(GL_TEXTURE_2D, color_texture_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glGenRenderbuffers(1, &depth_buffer_);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_buffer_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color_texture_, 0);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_buffer_);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void EyeRenderer::DrawArray(const fusion::VertexArray& array, GLenum mode) {
  if (array.empty()) return;
  glBindBuffer(GL_ARRAY_BUFFER, position_vbo_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(array.positions.size() * sizeof(float)),
               array.positions.data(), GL_STREAM_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, color_vbo_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(array.colors.size() * sizeof(float)),
               array.colors.data(), GL_STREAM_DRAW);
  glDrawArrays(mode, 0, static_cast<GLsizei>(array.vertex_count()));
}

void EyeRenderer::Render(const cv::Mat& image, const EyeView& view, const OverlayGeometry& overlay,
                         const EyeAlignment& alignment) {
  const int width = image.empty() ? std::max(width_, 640) : image.cols;
  const int height = image.empty() ? std::max(height_, 480) : image.rows;
  EnsureTarget(width, height);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, width, height);
  glDisable(GL_SCISSOR_TEST);
  glClearColor(0, 0, 0, 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  Draw(image, view, overlay, alignment, {0, 0, width, height});
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void EyeRenderer::RenderInto(const WindowRegion& region, const cv::Mat& image, const EyeView& view,
                             const OverlayGeometry& overlay, const EyeAlignment& alignment) {
  if (region.width_px <= 0 || region.height_px <= 0) return;
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(region.x_px, region.y_px, region.width_px, region.height_px);
  Draw(image, view, overlay, alignment, region);
}

void EyeRenderer::Draw(const cv::Mat& image, const EyeView& view, const OverlayGeometry& overlay,
                       const EyeAlignment& alignment, const WindowRegion& region) {
  // The displayed image's size (the last image's while there is none).
  if (!image.empty()) {
    image_width_ = image.cols;
    image_height_ = image.rows;
  }
  const int width = image.empty() ? std::max(image_width_, 640) : image.cols;
  const int height = image.empty() ? std::max(image_height_, 480) : image.rows;
  // Target pixels per displayed pixel (1 in the eye's own framebuffer).
  const float scale_x = static_cast<float>(region.width_px) / static_cast<float>(width);
  const float scale_y = static_cast<float>(region.height_px) / static_cast<float>(height);
  // Crop: only the region with a correspondence in the other eye is drawn.
  glEnable(GL_SCISSOR_TEST);
  const auto to_target = [](float px, float scale) { return static_cast<int>(px * scale); };
  const int x0 = to_target(alignment.crop_left_px, scale_x);
  const int y0 = to_target(alignment.crop_bottom_px, scale_y);
  const int x1 = region.width_px - to_target(alignment.crop_right_px, scale_x);
  const int y1 = region.height_px - to_target(alignment.crop_top_px, scale_y);
  glScissor(region.x_px + x0, region.y_px + y0, std::max(0, x1 - x0), std::max(0, y1 - y0));
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  image_program_.Use();
  glActiveTexture(GL_TEXTURE0);
  image_texture_.Upload(image);  // no-op when empty
  glBindTexture(GL_TEXTURE_2D, image_texture_.id());
  glUniform1i(image_program_.Uniform("u_image"), 0);
  glUniform1i(image_program_.Uniform("u_has_image"), image.empty() ? 0 : 1);
  const ImageWarp& w = view.warp;
  glUniform2f(image_program_.Uniform("u_size"), static_cast<float>(width),
              static_cast<float>(height));
  glUniform2f(image_program_.Uniform("u_focal"), w.fx, w.fy);
  glUniform2f(image_program_.Uniform("u_rotation"), w.rotation_cos, w.rotation_sin);
  glUniform2f(image_program_.Uniform("u_display_c"), w.display_cx, w.display_cy);
  glUniform2f(image_program_.Uniform("u_image_c"), w.image_cx, w.image_cy);
  glUniform3f(image_program_.Uniform("u_radial"), w.k1, w.k2, w.k3);
  glUniform2f(image_program_.Uniform("u_tangential"), w.p1, w.p2);
  glBindVertexArray(quad_vao_);
  glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);

  // Overlay: semi-transparent, no depth test (the image has no depth; walls blend). Point sizes
  // and line widths are in displayed pixels, scaled with the image.
  const float size_scale = scale_y;
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glEnable(GL_PROGRAM_POINT_SIZE);
  overlay_program_.Use();
  glUniformMatrix4fv(overlay_program_.Uniform("u_projection"), 1, GL_FALSE,
                     view.matrices.projection.data());
  glUniformMatrix4fv(overlay_program_.Uniform("u_view"), 1, GL_FALSE, view.matrices.view.data());
  glUniform1f(overlay_program_.Uniform("u_point_size"), overlay.point_size_px * size_scale);
  glBindVertexArray(overlay_vao_);
  DrawArray(overlay.triangles, GL_TRIANGLES);
  glLineWidth(std::max(1.f, 2.f * size_scale));
  DrawArray(overlay.lines, GL_LINES);
  DrawArray(overlay.points, GL_POINTS);
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);
}

}  // namespace mostar::render
