// Stereo display modes: how the two eyes' images share the window. No OpenGL here.
#pragma once

#include <string>

namespace mostar::render {

enum class DisplayMode {
  kMonoLeft,
  kMonoRight,
  kAnaglyphGrey,    // red-cyan from each eye's luminance (least retinal rivalry)
  kAnaglyphColor,   // red-cyan keeping colours: left red channel, right green and blue
  kSideBySideFull,  // left | right, each eye at full width (window twice as wide)
  kSideBySideHalf,  // left | right squeezed into one frame (3D TVs)
  kTopBottom,       // left above right, squeezed vertically
  kRowInterlaced,   // even window rows left eye, odd rows right eye (polarised monitors)
  kQuadBuffer,      // OpenGL quad-buffered stereo (needs a stereo-capable driver)
};

// Every mode, in the order of the 1..9 keys and the display combo box.
constexpr DisplayMode kDisplayModes[] = {
    DisplayMode::kMonoLeft,      DisplayMode::kMonoRight,      DisplayMode::kAnaglyphGrey,
    DisplayMode::kAnaglyphColor, DisplayMode::kSideBySideFull, DisplayMode::kSideBySideHalf,
    DisplayMode::kTopBottom,     DisplayMode::kRowInterlaced,  DisplayMode::kQuadBuffer,
};
constexpr int kDisplayModeCount = static_cast<int>(sizeof(kDisplayModes) / sizeof(DisplayMode));

const char* DisplayModeName(DisplayMode mode);
// Parses the names above ("mono-left", "anaglyph", "anaglyph-color", "sbs", "sbs-half",
// "top-bottom", "interlaced", "quad-buffer").
bool ParseDisplayMode(const std::string& text, DisplayMode* mode);
// Window size suited to a mode for eyes of `eye_width` x `eye_height`.
void WindowSizeFor(DisplayMode mode, int eye_width, int eye_height, int* width, int* height);

}  // namespace mostar::render
