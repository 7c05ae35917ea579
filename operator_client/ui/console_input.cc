#include "operator_client/ui/console_input.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <utility>

namespace mostar::ui {

bool ConsoleKeys::Pressed(GLFWwindow* window, int key) {
  const bool down = glfwGetKey(window, key) == GLFW_PRESS;
  const bool was = down_[key];
  down_[key] = down;
  return down && !was;
}

ConsoleInput ConsoleKeys::Poll(GLFWwindow* w, bool typing) {
  ConsoleInput in;
  if (!typing) {
    in.quit = Pressed(w, GLFW_KEY_ESCAPE);
    in.toggle_help = Pressed(w, GLFW_KEY_F1);
    in.toggle_calibration = Pressed(w, GLFW_KEY_C);
    in.toggle_hud = Pressed(w, GLFW_KEY_H);
    in.toggle_map = Pressed(w, GLFW_KEY_M);
    in.toggle_sonar = Pressed(w, GLFW_KEY_N);
    in.toggle_latency = Pressed(w, GLFW_KEY_L);
    in.toggle_vision = Pressed(w, GLFW_KEY_E);
    in.toggle_edge_view = Pressed(w, GLFW_KEY_V);
    for (int i = 0; i < render::kDisplayModeCount; ++i) {
      if (Pressed(w, GLFW_KEY_1 + i)) in.mode = render::kDisplayModes[i];
    }
    in.take_control = Pressed(w, GLFW_KEY_T);
    in.release_control = Pressed(w, GLFW_KEY_R);
    in.emergency_stop = Pressed(w, GLFW_KEY_X);
    in.release_emergency_stop = Pressed(w, GLFW_KEY_U);
    in.speed_up =
        Pressed(w, GLFW_KEY_EQUAL) || Pressed(w, GLFW_KEY_KP_ADD) || Pressed(w, GLFW_KEY_PAGE_UP);
    in.speed_down = Pressed(w, GLFW_KEY_MINUS) || Pressed(w, GLFW_KEY_KP_SUBTRACT) ||
                    Pressed(w, GLFW_KEY_PAGE_DOWN);
  }
  auto down = [w, typing](int key) { return !typing && glfwGetKey(w, key) == GLFW_PRESS; };
  in.drive.forward = down(GLFW_KEY_UP) || down(GLFW_KEY_W);
  in.drive.backward = down(GLFW_KEY_DOWN) || down(GLFW_KEY_S);
  in.drive.left = down(GLFW_KEY_LEFT) || down(GLFW_KEY_A);
  in.drive.right = down(GLFW_KEY_RIGHT) || down(GLFW_KEY_D);
  GLFWgamepadstate pad;
  if (glfwJoystickIsGamepad(GLFW_JOYSTICK_1) && glfwGetGamepadState(GLFW_JOYSTICK_1, &pad)) {
    in.drive.gamepad_present = true;
    in.drive.stick_linear = -pad.axes[GLFW_GAMEPAD_AXIS_LEFT_Y];
    in.drive.stick_angular = -pad.axes[GLFW_GAMEPAD_AXIS_RIGHT_X];
    in.drive.gamepad_deadman = pad.buttons[GLFW_GAMEPAD_BUTTON_RIGHT_BUMPER] == GLFW_PRESS;
  }
  return in;
}

void ApplyToggles(const ConsoleInput& in, const ViewSwitches& s) {
  const std::pair<bool, bool*> toggles[] = {
      {in.toggle_help, s.help},     {in.toggle_calibration, s.calibration_panel},
      {in.toggle_hud, s.hud},       {in.toggle_map, s.map},
      {in.toggle_sonar, s.sonar},   {in.toggle_latency, s.latency},
      {in.toggle_vision, s.vision}, {in.toggle_edge_view, s.edge_view}};
  for (const auto& [pressed, value] : toggles) {
    if (pressed && value) *value = !*value;
  }
}

}  // namespace mostar::ui
