// The latency trace (L): per stage of the last pairs shown, p50 and p95 in ms from the stage
// before, the total capture-to-presented time and what no stamp explains. ImGui; render thread.
#pragma once

#include <vector>

#include "operator_client/ui/latency_trace.h"

namespace mostar::ui {

// `parts`: the drawn stage by part (FrameParts::Rows), shown below the stages. `open` is
// cleared when the window is closed.
void DrawLatencyPanel(const LatencyTrace& trace, const std::vector<LatencyRow>& parts, bool* open);

}  // namespace mostar::ui
