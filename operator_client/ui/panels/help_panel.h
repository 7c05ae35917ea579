// The key help window (F1). ImGui; render thread.
#pragma once

namespace mostar::ui {

// `open`: cleared when the operator closes the window.
void DrawHelpPanel(bool* open);

}  // namespace mostar::ui
