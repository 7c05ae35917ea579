#include "operator_client/ui/panels/latency_panel.h"

#include <imgui.h>

namespace mostar::ui {

void DrawLatencyPanel(const LatencyTrace& trace, const std::vector<LatencyRow>& parts, bool* open) {
  ImGui::SetNextWindowPos(ImVec2(8, 300), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.75f);
  if (!ImGui::Begin("Latency: capture to screen", open, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::End();
    return;
  }
  ImGui::Text("last %zu pairs shown (robot clock; %zu not presented)", trace.pairs(),
              trace.incomplete());
  if (ImGui::BeginTable("latency", 3, ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg)) {
    ImGui::TableSetupColumn("stage");
    ImGui::TableSetupColumn("p50 ms");
    ImGui::TableSetupColumn("p95 ms");
    ImGui::TableHeadersRow();
    std::vector<LatencyRow> rows = trace.Rows();
    for (LatencyRow part : parts) {
      part.name = "  drawn: " + part.name;
      rows.push_back(part);
    }
    for (const LatencyRow& row : rows) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(row.name.c_str());
      ImGui::TableNextColumn();
      ImGui::Text("%.1f", row.p50_ms);
      ImGui::TableNextColumn();
      ImGui::Text("%.1f", row.p95_ms);
    }
    ImGui::EndTable();
  }
  ImGui::End();
}

}  // namespace mostar::ui
