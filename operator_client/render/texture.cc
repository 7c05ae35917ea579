#include "operator_client/render/texture.h"

#include <cassert>
#include <utility>

#include "operator_client/render/gl.h"

namespace mostar::render {

Texture::~Texture() {
  if (id_ != 0) glDeleteTextures(1, &id_);
}

Texture::Texture(Texture&& other) noexcept
    : id_(std::exchange(other.id_, 0)),
      width_(other.width_),
      height_(other.height_),
      grey_(other.grey_) {}

Texture& Texture::operator=(Texture&& other) noexcept {
  if (this != &other) {
    if (id_ != 0) glDeleteTextures(1, &id_);
    id_ = std::exchange(other.id_, 0);
    width_ = other.width_;
    height_ = other.height_;
    grey_ = other.grey_;
  }
  return *this;
}

void Texture::Upload(const cv::Mat& image) {
  if (image.empty()) return;
  assert(image.type() == CV_8UC1 || image.type() == CV_8UC3);
  const bool grey = image.channels() == 1;
  if (id_ == 0) {
    glGenTextures(1, &id_);
    glBindTexture(GL_TEXTURE_2D, id_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  }
  glBindTexture(GL_TEXTURE_2D, id_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, static_cast<GLint>(image.step / image.elemSize()));
  if (image.cols == width_ && image.rows == height_ && grey == grey_) {
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, image.cols, image.rows, grey ? GL_RED : GL_BGR,
                    GL_UNSIGNED_BYTE, image.data);
  } else {
    glTexImage2D(GL_TEXTURE_2D, 0, grey ? GL_R8 : GL_RGB8, image.cols, image.rows, 0,
                 grey ? GL_RED : GL_BGR, GL_UNSIGNED_BYTE, image.data);
  }
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  const GLint grey_swizzle[] = {GL_RED, GL_RED, GL_RED, GL_ONE};
  const GLint colour_swizzle[] = {GL_RED, GL_GREEN, GL_BLUE, GL_ALPHA};
  glTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_RGBA, grey ? grey_swizzle : colour_swizzle);
  width_ = image.cols;
  height_ = image.rows;
  grey_ = grey;
}

}  // namespace mostar::render
