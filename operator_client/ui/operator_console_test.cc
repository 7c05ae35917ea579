// The console's start-up on real OpenGL (Mesa llvmpipe under Xvfb in CI): the stereo alignment
// saved in the calibration profile is in force from the first frame. Skipped without an X
// display.
#include "operator_client/ui/operator_console.h"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include "common/math/calibration_io.h"
#include "common/time/fake_clock.h"

namespace mostar::ui {
namespace {

TEST(OperatorConsoleTest, StartsWithTheAlignmentSavedInTheCalibrationProfile) {
  if (std::getenv("DISPLAY") == nullptr) {
    GTEST_SKIP() << "no X display: run under xvfb-run (as deploy/test.sh does)";
  }
  char dir[] = "/tmp/operator_console_test_XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  const std::string path = std::string(dir) + "/profile.pbtxt";
  math::LaserCameraCalibration calibration;
  calibration.focal_px = 440;
  render::EyeAlignment left, right;
  render::CropForRightOffset(1.5f, -5.f, &left, &right);
  std::string error;
  ASSERT_TRUE(math::SaveCalibrationProfile(
      path, calibration, render::ToProfile(render::AlignmentModel::kPerEyeIntrinsics, left, right),
      "test", &error))
      << error;

  WindowOptions window_options;
  window_options.width = 640;
  window_options.height = 480;
  window_options.visible = false;
  std::unique_ptr<Window> window = Window::Create(window_options, &error);
  ASSERT_NE(window, nullptr) << error;
  FakeClock clock;
  client::StereoReceiver video(&clock);
  client::RobotState robot(&clock);
  CommandSender commands({}, {}, &clock);
  ConsoleOptions options;
  options.headless = true;
  options.calibration = calibration;
  options.calibration_path = path;
  {
    OperatorConsole console(options, window.get(), &video, &robot, &commands, &clock);
    ASSERT_TRUE(console.Init(&error)) << error;
    EXPECT_EQ(console.options().alignment_model, render::AlignmentModel::kPerEyeIntrinsics);
    EXPECT_FLOAT_EQ(console.options().right_alignment.offset_y_px, -5.f);
    EXPECT_FLOAT_EQ(console.options().right_alignment.offset_x_px, 1.5f);
    EXPECT_TRUE(console.options().left_alignment == left);
    console.Frame();  // the first frame draws with it (no pair yet: nothing shown, no crash)
  }
  // A profile that cannot be read: the console starts without offsets (one console, and its
  // ImGui context, at a time).
  {
    ConsoleOptions missing = options;
    missing.calibration_path = path + ".missing";
    OperatorConsole without(missing, window.get(), &video, &robot, &commands, &clock);
    ASSERT_TRUE(without.Init(&error)) << error;
    EXPECT_FLOAT_EQ(without.options().right_alignment.offset_y_px, 0.f);
  }
  std::remove(path.c_str());
  ::rmdir(dir);
}

}  // namespace
}  // namespace mostar::ui
