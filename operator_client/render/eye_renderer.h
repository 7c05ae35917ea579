// Renders one eye: the camera image as a textured quad and the AR geometry over it, either into
// an offscreen framebuffer the size of the camera image (the stereo compositor then combines the
// two eyes' framebuffers for modes that blend them: anaglyphs, row interlacing, quad buffer), or
// straight into the eye's region of the window (mono, side by side, top-bottom: no compositor
// pass, the same pixels for a window region the image's size).
//
// The image is drawn through the eye's ImageWarp (eye_geometry.h): each displayed pixel samples
// the camera image where the eye's image model sees the same ray, which removes the lens
// distortion and applies the stereo offset in one step. Geometry is given in the laser frame
// (metres) and drawn with the pinhole matrices of the eye's display model
// (CameraModel::OpenGlMatrices), so a laser point lands on the displayed pixel that shows what
// the image model's Project() says. Requires a current OpenGL 3.3 core context; not
// thread-safe (render thread only).
#pragma once

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>
#include <string>

#include "common/math/camera_model.h"
#include "operator_client/fusion/vertex_array.h"
#include "operator_client/render/eye_geometry.h"
#include "operator_client/render/gl_program.h"
#include "operator_client/render/overlay_geometry.h"
#include "operator_client/render/texture.h"

namespace mostar::render {

// How one eye is drawn: the overlay's matrices and the image's warp.
struct EyeView {
  math::GlMatrices matrices;  // the display model's, clip 0.05..100 m
  ImageWarp warp;
};

EyeView MakeEyeView(const EyeGeometry& geometry);

// A rectangle of the bound draw framebuffer in OpenGL pixels (origin bottom-left) that shows one
// eye's whole displayed image, scaled to fill it.
struct WindowRegion {
  int x_px = 0;
  int y_px = 0;
  int width_px = 0;
  int height_px = 0;
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
  // background). Only the crop of `alignment` is used here (its offset is in view.warp).
  void Render(const cv::Mat& image, const EyeView& view, const OverlayGeometry& overlay,
              const EyeAlignment& alignment);
  // Renders into `region` of the window's framebuffer (0, its current draw buffer), which the
  // caller has cleared: outside the crop the region keeps what it had. Overlay point sizes and
  // line widths scale with the image. texture() is not touched.
  void RenderInto(const WindowRegion& region, const cv::Mat& image, const EyeView& view,
                  const OverlayGeometry& overlay, const EyeAlignment& alignment);
  GLuint texture() const { return color_texture_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  void EnsureTarget(int width, int height);
  // Draws image and overlay into `region` of the bound framebuffer (viewport already set).
  void Draw(const cv::Mat& image, const EyeView& view, const OverlayGeometry& overlay,
            const EyeAlignment& alignment, const WindowRegion& region);
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
  int width_ = 0;  // the framebuffer's
  int height_ = 0;
  int image_width_ = 0;  // the last displayed image's
  int image_height_ = 0;
};

}  // namespace mostar::render
