#include "operator_client/render/eye_viewports.h"

#include <gtest/gtest.h>

namespace mostar::render {
namespace {

using math::Eye;

void ExpectViewport(const EyeViewport& v, Eye eye, int x, int y, int w, int h) {
  EXPECT_EQ(v.eye, eye);
  EXPECT_EQ(v.x_px, x);
  EXPECT_EQ(v.y_px, y);
  EXPECT_EQ(v.width_px, w);
  EXPECT_EQ(v.height_px, h);
}

TEST(EyeViewportsTest, MonoLeftShowsTheLeftEyeOverTheWholeWindow) {
  const auto v = EyeViewports(DisplayMode::kMonoLeft, 640, 480);
  ASSERT_EQ(v.size(), 1u);
  ExpectViewport(v[0], Eye::kLeft, 0, 0, 640, 480);
}

TEST(EyeViewportsTest, MonoRightShowsTheRightEyeOverTheWholeWindow) {
  const auto v = EyeViewports(DisplayMode::kMonoRight, 640, 480);
  ASSERT_EQ(v.size(), 1u);
  ExpectViewport(v[0], Eye::kRight, 0, 0, 640, 480);
}

TEST(EyeViewportsTest, SideBySidePutsLeftEyeInTheLeftHalf) {
  for (const DisplayMode mode : {DisplayMode::kSideBySideFull, DisplayMode::kSideBySideHalf}) {
    const auto v = EyeViewports(mode, 1280, 480);
    ASSERT_EQ(v.size(), 2u) << DisplayModeName(mode);
    ExpectViewport(v[0], Eye::kLeft, 0, 0, 640, 480);
    ExpectViewport(v[1], Eye::kRight, 640, 0, 640, 480);
  }
}

TEST(EyeViewportsTest, TopBottomPutsLeftEyeOnTop) {
  const auto v = EyeViewports(DisplayMode::kTopBottom, 640, 480);
  ASSERT_EQ(v.size(), 2u);
  ExpectViewport(v[0], Eye::kLeft, 0, 0, 640, 240);
  ExpectViewport(v[1], Eye::kRight, 0, 240, 640, 240);
  // OpenGL counts rows from the bottom: the top half starts half way up.
  EXPECT_EQ(v[0].GlY(480), 240);
  EXPECT_EQ(v[1].GlY(480), 0);
}

TEST(EyeViewportsTest, BlendedModesGiveBothEyesTheWholeWindow) {
  for (const DisplayMode mode : {DisplayMode::kAnaglyphGrey, DisplayMode::kAnaglyphColor,
                                 DisplayMode::kRowInterlaced, DisplayMode::kQuadBuffer}) {
    const auto v = EyeViewports(mode, 640, 480);
    ASSERT_EQ(v.size(), 2u) << DisplayModeName(mode);
    ExpectViewport(v[0], Eye::kLeft, 0, 0, 640, 480);
    ExpectViewport(v[1], Eye::kRight, 0, 0, 640, 480);
    EXPECT_TRUE(v[0].SameRect(v[1]));
  }
}

// Property over every mode and some odd sizes: the viewports lie inside the window, tile it
// without gaps (split modes) or cover it (the others), and the left eye comes first.
TEST(EyeViewportsTest, EveryModeCoversTheWindowExactly) {
  for (const DisplayMode mode : kDisplayModes) {
    for (const auto& [w, h] : {std::pair{640, 480}, std::pair{641, 479}, std::pair{1, 1}}) {
      const auto v = EyeViewports(mode, w, h);
      ASSERT_FALSE(v.empty());
      EXPECT_EQ(v.front().eye, mode == DisplayMode::kMonoRight ? Eye::kRight : Eye::kLeft);
      long long area = 0;
      for (const EyeViewport& r : v) {
        EXPECT_GE(r.x_px, 0);
        EXPECT_GE(r.y_px, 0);
        EXPECT_LE(r.x_px + r.width_px, w);
        EXPECT_LE(r.y_px + r.height_px, h);
        area += static_cast<long long>(r.width_px) * r.height_px;
      }
      const bool split = v.size() == 2 && !v[0].SameRect(v[1]);
      if (split || v.size() == 1) {
        EXPECT_EQ(area, static_cast<long long>(w) * h) << DisplayModeName(mode) << " " << w;
      } else {
        EXPECT_EQ(v[0].width_px, w);
        EXPECT_EQ(v[0].height_px, h);
      }
    }
  }
}

TEST(EyeViewportsTest, OddSizesGiveTheExtraPixelToTheRightEye) {
  auto v = EyeViewports(DisplayMode::kSideBySideHalf, 641, 480);
  EXPECT_EQ(v[0].width_px, 320);
  EXPECT_EQ(v[1].x_px, 320);
  EXPECT_EQ(v[1].width_px, 321);
  v = EyeViewports(DisplayMode::kTopBottom, 640, 481);
  EXPECT_EQ(v[0].height_px, 240);
  EXPECT_EQ(v[1].y_px, 240);
  EXPECT_EQ(v[1].height_px, 241);
}

TEST(EyeViewportsTest, MonoModesShowOneEyeAndTheOthersBoth) {
  using Shown = std::array<bool, 2>;
  EXPECT_EQ(EyesShown(DisplayMode::kMonoLeft, false), (Shown{true, false}));
  EXPECT_EQ(EyesShown(DisplayMode::kMonoRight, true), (Shown{false, true}));
  EXPECT_EQ(EyesShown(DisplayMode::kAnaglyphColor, false), (Shown{true, true}));
  EXPECT_EQ(EyesShown(DisplayMode::kSideBySideHalf, false), (Shown{true, true}));
  EXPECT_EQ(EyesShown(DisplayMode::kQuadBuffer, true), (Shown{true, true}));
  // Without a stereo framebuffer the compositor shows the left eye only.
  EXPECT_EQ(EyesShown(DisplayMode::kQuadBuffer, false), (Shown{true, false}));
}

// Drawn in place exactly where the eyes' rectangles do not overlap (nothing to blend).
TEST(EyeViewportsTest, EyesAreDrawnInPlaceWhereTheirRectanglesAreApart) {
  for (const DisplayMode mode :
       {DisplayMode::kMonoLeft, DisplayMode::kMonoRight, DisplayMode::kSideBySideFull,
        DisplayMode::kSideBySideHalf, DisplayMode::kTopBottom, DisplayMode::kAnaglyphGrey,
        DisplayMode::kAnaglyphColor, DisplayMode::kRowInterlaced, DisplayMode::kQuadBuffer}) {
    const std::vector<EyeViewport> v = EyeViewports(mode, 640, 480);
    const bool apart = v.size() == 1 || (v[0].x_px + v[0].width_px <= v[1].x_px ||
                                         v[0].y_px + v[0].height_px <= v[1].y_px);
    EXPECT_EQ(DrawsEyesInPlace(mode), apart) << DisplayModeName(mode);
  }
}

}  // namespace
}  // namespace mostar::render
