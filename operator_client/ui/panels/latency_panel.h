// The latency trace (L): per stage of the last pairs shown, p50 and p95 in ms from the stage
// before, the total capture-to-presented time and what no stamp explains. ImGui; render thread.
#pragma once

#include "operator_client/ui/latency_trace.h"

namespace mostar::ui {

// `open` is cleared when the window is closed.
void DrawLatencyPanel(const LatencyTrace& trace, bool* open);

}  // namespace mostar::ui
