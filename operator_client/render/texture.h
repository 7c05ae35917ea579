// An OpenGL 2D texture holding one 8-bit image (RAII: the GL name is deleted with the object).
// Requires a current OpenGL 3.3 core context for every call but the constructor; render thread
// only.
#pragma once

#include <opencv2/core/mat.hpp>

namespace mostar::render {

class Texture {
 public:
  Texture() = default;  // no GL name until the first Upload()
  ~Texture();
  Texture(const Texture&) = delete;
  Texture& operator=(const Texture&) = delete;
  Texture(Texture&& other) noexcept;
  Texture& operator=(Texture&& other) noexcept;

  // Replaces the contents with `image`: CV_8UC3 in BGR order, or CV_8UC1 sampled as grey
  // (r = g = b, alpha 1). Any row stride (ROIs included). Linear filtering, clamped to the
  // edges. Leaves the texture bound to GL_TEXTURE_2D on the active unit. An empty image is
  // ignored. An image of the size and kind of the previous one is written into the texture's
  // storage (glTexSubImage2D), with no reallocation.
  void Upload(const cv::Mat& image);

  unsigned id() const { return id_; }  // 0 before the first Upload()
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  unsigned id_ = 0;
  int width_ = 0;
  int height_ = 0;
  bool grey_ = false;
};

}  // namespace mostar::render
