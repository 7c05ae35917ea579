#include "operator_client/render/display_mode.h"

#include <map>

namespace mostar::render {

namespace {

const std::map<std::string, DisplayMode>& Names() {
  static const std::map<std::string, DisplayMode> names = {
      {"mono-left", DisplayMode::kMonoLeft},     {"mono-right", DisplayMode::kMonoRight},
      {"anaglyph", DisplayMode::kAnaglyphGrey},  {"anaglyph-color", DisplayMode::kAnaglyphColor},
      {"sbs", DisplayMode::kSideBySideFull},     {"sbs-half", DisplayMode::kSideBySideHalf},
      {"top-bottom", DisplayMode::kTopBottom},   {"interlaced", DisplayMode::kRowInterlaced},
      {"quad-buffer", DisplayMode::kQuadBuffer},
  };
  return names;
}

}  // namespace

const char* DisplayModeName(DisplayMode mode) {
  for (const auto& [name, m] : Names()) {
    if (m == mode) return name.c_str();
  }
  return "?";
}

bool ParseDisplayMode(const std::string& text, DisplayMode* mode) {
  const auto it = Names().find(text);
  if (it == Names().end()) return false;
  *mode = it->second;
  return true;
}

void WindowSizeFor(DisplayMode mode, int eye_width, int eye_height, int* width, int* height) {
  *width = mode == DisplayMode::kSideBySideFull ? 2 * eye_width : eye_width;
  *height = eye_height;
}

}  // namespace mostar::render
