#include "operator_client/render/stereo_view.h"

#include "operator_client/render/eye_viewports.h"

namespace mostar::render {

namespace {
const cv::Mat kNoImage;
}  // namespace

bool StereoView::Init(std::string* error) {
  return eyes_[0].Init(error) && eyes_[1].Init(error) && compositor_.Init(error);
}

void StereoView::DrawEyes(DisplayMode mode, bool quad_buffer_available, int window_w, int window_h,
                          const std::array<EyeInput, 2>& eyes, const OverlayGeometry& overlay) {
  const auto image = [&](int e) -> const cv::Mat& {
    const cv::Mat* mat = eyes[static_cast<size_t>(e)].image;
    return mat != nullptr ? *mat : kNoImage;
  };
  if (DrawsEyesInPlace(mode)) {
    StereoCompositor::ClearWindow(window_w, window_h);
    for (const EyeViewport& v : EyeViewports(mode, window_w, window_h)) {
      const int e = v.eye == math::Eye::kLeft ? 0 : 1;
      const EyeInput& eye = eyes[static_cast<size_t>(e)];
      eyes_[e].RenderInto({v.x_px, v.GlY(window_h), v.width_px, v.height_px}, image(e), eye.view,
                          overlay, eye.alignment);
    }
    return;
  }
  const std::array<bool, 2> shown = EyesShown(mode, quad_buffer_available);
  for (int e = 0; e < 2; ++e) {
    if (!shown[static_cast<size_t>(e)]) continue;
    const EyeInput& eye = eyes[static_cast<size_t>(e)];
    eyes_[e].Render(image(e), eye.view, overlay, eye.alignment);
  }
}

void StereoView::Compose(DisplayMode mode, bool quad_buffer_available, int window_w, int window_h) {
  if (DrawsEyesInPlace(mode)) return;
  compositor_.Compose(mode, eyes_[0].texture(), eyes_[1].texture(), window_w, window_h,
                      quad_buffer_available);
}

}  // namespace mostar::render
