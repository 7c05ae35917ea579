// The calibration panel laid out by Dear ImGui itself (no renderer needed): in a 640 x 480
// window it stays inside the window, scrolling, so the stereo alignment and NESC's hint at its
// bottom can be reached; in a large window it is as tall as its content.
#include "operator_client/ui/panels/calibration_panel.h"

#include <gtest/gtest.h>
#include <imgui.h>
#include <imgui_internal.h>

namespace mostar::ui {
namespace {

struct Panel {
  ImVec2 pos;
  ImVec2 size;
  float scroll_max_y = 0;
};

// Lays out the panel for a few frames in a display of `w` x `h` and returns its window.
Panel LayOut(float w, float h, ConsoleSelfCalibration* self = nullptr) {
  ImGuiContext* context = ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;
  io.DisplaySize = ImVec2(w, h);
  io.DeltaTime = 1.f / 30.f;
  unsigned char* pixels = nullptr;
  int tw = 0, th = 0;
  io.Fonts->GetTexDataAsRGBA32(&pixels, &tw, &th);  // builds the font atlas
  bool open = true;
  math::LaserCameraCalibration calibration;
  fusion::ArFeatureOptions ar;
  render::EyeAlignment left, right;
  render::AlignmentModel model = render::AlignmentModel::kSharedModel;
  render::DisplayMode mode = render::DisplayMode::kMonoLeft;
  std::string status;
  StereoOffsetHint hint;
  hint.suggested_right_offset_y_px = -4.f;
  hint.residual_px = 4.0;
  hint.samples = 30;
  Panel panel;
  for (int frame = 0; frame < 4; ++frame) {
    ImGui::NewFrame();
    DrawCalibrationPanel(
        "", {&open, &calibration, &ar, &left, &right, &model, &mode, &status, self}, hint);
    ImGui::EndFrame();
    const ImGuiWindow* window = ImGui::FindWindowByName("Calibration");
    if (window != nullptr) panel = {window->Pos, window->Size, window->ScrollMax.y};
  }
  ImGui::DestroyContext(context);
  return panel;
}

TEST(CalibrationPanelTest, FitsA640By480WindowAndScrolls) {
  const Panel small = LayOut(640, 480);
  EXPECT_GE(small.pos.y, 0.f);
  EXPECT_LE(small.pos.y + small.size.y, 480.f);
  EXPECT_GT(small.scroll_max_y, 0.f) << "the content is taller than the window: it scrolls";
  const Panel large = LayOut(1280, 1200);
  EXPECT_FLOAT_EQ(large.scroll_max_y, 0.f) << "everything fits";
  EXPECT_GT(large.size.y, small.size.y);
}

TEST(CalibrationPanelTest, SelfCalibrationSectionAddsToThePanelAndStillScrolls) {
  ConsoleSelfCalibration self;  // no proposal yet: the section says so
  const Panel small = LayOut(640, 480, &self);
  EXPECT_LE(small.pos.y + small.size.y, 480.f);
  EXPECT_GT(small.scroll_max_y, LayOut(640, 480).scroll_max_y);
  EXPECT_GT(LayOut(1280, 1200, &self).size.y, LayOut(1280, 1200).size.y);
}

}  // namespace
}  // namespace mostar::ui
