// Reads the current default framebuffer back into an image (for headless mode and tests).
#pragma once

#include <opencv2/core/mat.hpp>

namespace mostar::render {

// BGR8 image of the window's back buffer, row 0 at the top. Call before swapping buffers.
cv::Mat ReadFramebuffer(int width, int height);

}  // namespace mostar::render
