// Maps keyboard and gamepad state to velocity commands. Pure: no GLFW here (the window code
// samples the devices into DriveInputState).
//
// Keyboard: arrows or W/A/S/D drive while held (holding a movement key is the deadman);
//   +/- (or PageUp/PageDown) change the speed scale.
// Gamepad (GLFW standard mapping): left stick y = forward/backward, right stick x (or left
//   stick x) = turn; the right bumper is the deadman and must be held for any motion.
// Release of everything gives enable = false and zero velocity.
#pragma once

#include <string>

namespace mostar::ui {

struct DriveInputState {
  bool forward = false, backward = false, left = false, right = false;  // keyboard
  bool gamepad_present = false;
  float stick_linear = 0.f;   // [-1, 1], +1 = forward (already sign-corrected)
  float stick_angular = 0.f;  // [-1, 1], +1 = turn left (counter-clockwise)
  bool gamepad_deadman = false;
};

struct DriveLimits {
  double max_linear_mps = 0.6;
  double max_angular_radps = 1.0;
  double stick_deadzone = 0.12;  // stick values below this count as zero
  bool IsValid(std::string* error) const;
};

struct DriveOutput {
  double linear_mps = 0;
  double angular_radps = 0;
  bool enable = false;  // deadman held
};

class DriveMapper {
 public:
  explicit DriveMapper(const DriveLimits& limits) : limits_(limits) {}
  DriveOutput Map(const DriveInputState& input) const;
  // Speed scale in [0.1, 1], changed in steps of 0.1.
  void ScaleUp();
  void ScaleDown();
  double scale() const { return scale_; }

 private:
  DriveLimits limits_;
  double scale_ = 0.5;
};

}  // namespace mostar::ui
