#include "operator_client/render/eye_viewports.h"

namespace mostar::render {

std::vector<EyeViewport> EyeViewports(DisplayMode mode, int w, int h) {
  using math::Eye;
  switch (mode) {
    case DisplayMode::kMonoLeft:
      return {{Eye::kLeft, 0, 0, w, h}};
    case DisplayMode::kMonoRight:
      return {{Eye::kRight, 0, 0, w, h}};
    case DisplayMode::kSideBySideFull:
    case DisplayMode::kSideBySideHalf:
      return {{Eye::kLeft, 0, 0, w / 2, h}, {Eye::kRight, w / 2, 0, w - w / 2, h}};
    case DisplayMode::kTopBottom:
      return {{Eye::kLeft, 0, 0, w, h / 2}, {Eye::kRight, 0, h / 2, w, h - h / 2}};
    case DisplayMode::kAnaglyphGrey:
    case DisplayMode::kAnaglyphColor:
    case DisplayMode::kRowInterlaced:
    case DisplayMode::kQuadBuffer:
      break;
  }
  return {{Eye::kLeft, 0, 0, w, h}, {Eye::kRight, 0, 0, w, h}};
}

std::array<bool, 2> EyesShown(DisplayMode mode, bool quad_buffer_available) {
  if (mode == DisplayMode::kQuadBuffer && !quad_buffer_available) mode = DisplayMode::kMonoLeft;
  std::array<bool, 2> shown = {false, false};
  for (const EyeViewport& viewport : EyeViewports(mode, 2, 2)) {
    shown[viewport.eye == math::Eye::kLeft ? 0 : 1] = true;
  }
  return shown;
}

bool DrawsEyesInPlace(DisplayMode mode) {
  switch (mode) {
    case DisplayMode::kMonoLeft:
    case DisplayMode::kMonoRight:
    case DisplayMode::kSideBySideFull:
    case DisplayMode::kSideBySideHalf:
    case DisplayMode::kTopBottom:
      return true;
    case DisplayMode::kAnaglyphGrey:
    case DisplayMode::kAnaglyphColor:
    case DisplayMode::kRowInterlaced:
    case DisplayMode::kQuadBuffer:
      break;
  }
  return false;
}

}  // namespace mostar::render
