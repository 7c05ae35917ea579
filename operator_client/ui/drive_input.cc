#include "operator_client/ui/drive_input.h"

#include <algorithm>
#include <cmath>

namespace mostar::ui {

bool DriveLimits::IsValid(std::string* error) const {
  if (!(max_linear_mps > 0 && max_linear_mps <= 3)) {
    *error = "max_linear_mps must be in (0, 3]";
    return false;
  }
  if (!(max_angular_radps > 0 && max_angular_radps <= 6)) {
    *error = "max_angular_radps must be in (0, 6]";
    return false;
  }
  if (!(stick_deadzone >= 0 && stick_deadzone < 0.9)) {
    *error = "stick_deadzone must be in [0, 0.9)";
    return false;
  }
  return true;
}

namespace {
// Removes the dead zone and rescales the rest to [-1, 1].
double Shape(double value, double deadzone) {
  if (!std::isfinite(value)) return 0;
  const double magnitude = std::abs(value);
  if (magnitude <= deadzone) return 0;
  return std::copysign(std::min(1.0, (magnitude - deadzone) / (1.0 - deadzone)), value);
}
}  // namespace

DriveOutput DriveMapper::Map(const DriveInputState& input) const {
  DriveOutput out;
  const bool keyboard_active = input.forward || input.backward || input.left || input.right;
  double linear = 0;
  double angular = 0;
  if (keyboard_active) {
    linear = (input.forward ? 1.0 : 0.0) - (input.backward ? 1.0 : 0.0);
    angular = (input.left ? 1.0 : 0.0) - (input.right ? 1.0 : 0.0);
    out.enable = true;
  } else if (input.gamepad_present && input.gamepad_deadman) {
    linear = Shape(input.stick_linear, limits_.stick_deadzone);
    angular = Shape(input.stick_angular, limits_.stick_deadzone);
    out.enable = true;
  }
  if (!out.enable) return out;
  out.linear_mps = linear * limits_.max_linear_mps * scale_;
  out.angular_radps = angular * limits_.max_angular_radps * scale_;
  return out;
}

void DriveMapper::ScaleUp() { scale_ = std::min(1.0, std::round(scale_ * 10 + 1) / 10); }
void DriveMapper::ScaleDown() { scale_ = std::max(0.1, std::round(scale_ * 10 - 1) / 10); }

}  // namespace mostar::ui
