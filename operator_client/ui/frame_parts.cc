#include "operator_client/ui/frame_parts.h"

#include <algorithm>
#include <string>

#include "common/stats/percentile.h"

namespace mostar::ui {

const char* FramePartName(FramePart part) {
  switch (part) {
    case FramePart::kOverlay:
      return "overlay";
    case FramePart::kEyes:
      return "eyes";
    case FramePart::kCompose:
      return "compose";
    case FramePart::kPanels:
      return "panels";
    case FramePart::kCount:
      break;
  }
  return "?";
}

FrameParts::FrameParts(size_t window) : window_(window > 0 ? window : 1) {}

void FrameParts::Add(const std::array<double, kFramePartCount>& part_ms) {
  for (int p = 0; p < kFramePartCount; ++p) {
    std::deque<double>& samples = part_ms_[static_cast<size_t>(p)];
    samples.push_back(std::max(part_ms[static_cast<size_t>(p)], 0.0));
    while (samples.size() > window_) samples.pop_front();
  }
}

std::vector<LatencyRow> FrameParts::Rows() const {
  std::vector<LatencyRow> rows;
  for (int p = 0; p < kFramePartCount; ++p) {
    const std::deque<double>& samples = part_ms_[static_cast<size_t>(p)];
    const std::vector<double> v(samples.begin(), samples.end());
    LatencyRow row;
    row.name = FramePartName(static_cast<FramePart>(p));
    row.samples = v.size();
    row.p50_ms = Percentile(v, 0.50).value_or(0.0);
    row.p95_ms = Percentile(v, 0.95).value_or(0.0);
    rows.push_back(row);
  }
  return rows;
}

}  // namespace mostar::ui
