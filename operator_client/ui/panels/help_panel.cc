#include "operator_client/ui/panels/help_panel.h"

#include <imgui.h>

namespace mostar::ui {

void DrawHelpPanel(bool* open) {
  ImGui::SetNextWindowPos(ImVec2(240, 120), ImGuiCond_FirstUseEver);
  ImGui::Begin("Help", open, ImGuiWindowFlags_AlwaysAutoResize);
  ImGui::TextUnformatted(
      "Arrows / WASD   drive while held (release = stop)\n"
      "Gamepad         left stick drive, right stick turn, hold RB\n"
      "+ / -           speed scale\n"
      "T / R           take / release control\n"
      "X / U           emergency stop / release it\n"
      "1..9            display mode (mono L/R, anaglyph, colour anaglyph,\n"
      "                sbs, sbs-half, top-bottom, interlaced, quad-buffer)\n"
      "C               calibration and AR panel\n"
      "E / V           edge processing on/off / edge view (thresholds)\n"
      "H / M           HUD / laser map\n"
      "N               sonar sectors on/off\n"
      "L               latency trace (capture to screen, per stage)\n"
      "Esc             quit");
  ImGui::End();
}

}  // namespace mostar::ui
