// Where the CPU side of a frame (the latency trace's `drawn` stage) goes, part by part: the
// overlay geometry (scan features, sonar sectors, dots, predicted path), the eyes (image upload
// and overlay draw calls, per shown eye), the compositor and the ImGui panels. Wall time on the
// render thread between stamps; a software renderer (llvmpipe) rasterises at the swap, which
// the trace counts in `presented`. Keeps the last `window` frames. Pure: no GL.
#pragma once

#include <array>
#include <cstddef>
#include <deque>
#include <vector>

#include "operator_client/ui/latency_trace.h"

namespace mostar::ui {

enum class FramePart : int { kOverlay = 0, kEyes, kCompose, kPanels, kCount };
inline constexpr int kFramePartCount = static_cast<int>(FramePart::kCount);
const char* FramePartName(FramePart part);

class FrameParts {
 public:
  explicit FrameParts(size_t window = 1000);

  // One frame's parts, in ms (negative values are taken as 0).
  void Add(const std::array<double, kFramePartCount>& part_ms);
  // One row per part in order (p50, p95 over the kept frames; zeros without samples).
  std::vector<LatencyRow> Rows() const;
  size_t frames() const { return part_ms_[0].size(); }

 private:
  size_t window_;
  std::array<std::deque<double>, kFramePartCount> part_ms_;
};

}  // namespace mostar::ui
