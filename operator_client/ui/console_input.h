// Samples the keyboard (GLFW) and the first gamepad into what the operator asked for in one
// frame. Key actions fire on the press (a held key acts once); drive keys act while held.
// Render thread only (GLFW).
#pragma once

#include <map>
#include <optional>

#include "operator_client/render/display_mode.h"
#include "operator_client/ui/drive_input.h"

struct GLFWwindow;

namespace mostar::ui {

struct ConsoleInput {
  bool quit = false;                        // Esc
  bool toggle_help = false;                 // F1
  bool toggle_calibration = false;          // C
  bool toggle_hud = false;                  // H
  bool toggle_map = false;                  // M
  bool toggle_sonar = false;                // N
  bool toggle_latency = false;              // L
  bool toggle_vision = false;               // E
  bool toggle_edge_view = false;            // V
  std::optional<render::DisplayMode> mode;  // 1..9
  bool take_control = false;                // T
  bool release_control = false;             // R
  bool emergency_stop = false;              // X
  bool release_emergency_stop = false;      // U
  bool speed_up = false;                    // + or PageUp
  bool speed_down = false;                  // - or PageDown
  DriveInputState drive;                    // arrows/WASD and gamepad
};

// The view switches the keys flip; each pointer may be null (that key does nothing).
struct ViewSwitches {
  bool* help = nullptr;
  bool* calibration_panel = nullptr;
  bool* hud = nullptr;
  bool* map = nullptr;
  bool* sonar = nullptr;
  bool* latency = nullptr;
  bool* vision = nullptr;
  bool* edge_view = nullptr;
};
// Flips the switch of every toggle key pressed in `in`.
void ApplyToggles(const ConsoleInput& in, const ViewSwitches& switches);

class ConsoleKeys {
 public:
  // `typing`: a text field has the keyboard (ImGui): no key acts and drive keys read as up.
  ConsoleInput Poll(GLFWwindow* window, bool typing);

 private:
  // True on the first poll that sees `key` down.
  bool Pressed(GLFWwindow* window, int key);
  std::map<int, bool> down_;  // last seen state per key
};

}  // namespace mostar::ui
