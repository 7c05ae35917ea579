#include "operator_client/render/screenshot.h"

#include <opencv2/core.hpp>

#include "operator_client/render/gl.h"

namespace mostar::render {

cv::Mat ReadFramebuffer(int width, int height) {
  cv::Mat image(height, width, CV_8UC3);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_BGR, GL_UNSIGNED_BYTE, image.data);
  cv::flip(image, image, 0);
  return image;
}

}  // namespace mostar::render
