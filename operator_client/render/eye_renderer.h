// Renders one eye: the camera image as a textured quad and the AR geometry over it, into an
// offscreen framebuffer the size of the camera image. The stereo compositor then combines the
// two eyes' framebuffers for the chosen display mode.
//
// Geometry is given in the laser frame (metres) and drawn with the projection and view matrices
// of the eye's camera model (common/math CameraModel::OpenGlMatrices), so the overlay lands
// where CameraModel::Project() says. Requires a current OpenGL 3.3 core context; not
// thread-safe (render thread only).
#pragma once

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>
#include <string>

#include "operator_client/fusion/vertex_array.h"
#include "operator_client/render/gl_program.h"
#include "operator_client/render/overlay_geometry.h"
#include "operator_client/render/texture.h"

namespace mostar::render {

// Stereo alignment (thesis 9.1): the eye's image is shifted by (dx, dy) pixels; parts with no
// correspondence in the other eye are cropped (drawn black).
struct EyeAlignment {
  float offset_x_px = 0.f;
  float offset_y_px = 0.f;
  float crop_left_px = 0.f;
  float crop_right_px = 0.f;
  float crop_top_px = 0.f;
  float crop_bottom_px = 0.f;
};

class EyeRenderer {
 public:
  EyeRenderer() = default;
  ~EyeRenderer();
  EyeRenderer(const EyeRenderer&) = delete;
  EyeRenderer& operator=(const EyeRenderer&) = delete;

  // Creates GL objects; false with a message on failure.
  bool Init(std::string* error);
  // Renders into the eye framebuffer (resized to the image). `image` BGR8 (may be empty: grey
  // background). `projection`/`view`: the eye's GL matrices.
  void Render(const cv::Mat& image, const Eigen::Matrix4f& projection, const Eigen::Matrix4f& view,
              const OverlayGeometry& overlay, const EyeAlignment& alignment);
  GLuint texture() const { return color_texture_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  void EnsureTarget(int width, int height);
  void DrawArray(const fusion::VertexArray& array, GLenum mode);

  GlProgram image_program_;
  GlProgram overlay_program_;
  Texture image_texture_;
  GLuint quad_vao_ = 0;
  GLuint overlay_vao_ = 0;
  GLuint position_vbo_ = 0;
  GLuint color_vbo_ = 0;
  GLuint framebuffer_ = 0;
  GLuint color_texture_ = 0;
  GLuint depth_buffer_ = 0;
  int width_ = 0;
  int height_ = 0;
};

}  // namespace mostar::render
