#include "operator_client/ui/latency_trace.h"

#include "common/stats/percentile.h"

namespace mostar::ui {

const char* LatencyStageName(LatencyStage stage) {
  switch (stage) {
    case LatencyStage::kEncoded:
      return "encoded";
    case LatencyStage::kWritten:
      return "written";
    case LatencyStage::kReceived:
      return "received";
    case LatencyStage::kQueued:
      return "queued";
    case LatencyStage::kDecoded:
      return "decoded";
    case LatencyStage::kPicked:
      return "picked";
    case LatencyStage::kVision:
      return "vision";
    case LatencyStage::kStarted:
      return "started";
    case LatencyStage::kDrawn:
      return "drawn";
    case LatencyStage::kPresented:
      return "presented";
    case LatencyStage::kCount:
      break;
  }
  return "?";
}

LatencyTrace::LatencyTrace(size_t window) : window_(window > 0 ? window : 1) {}

void LatencyTrace::Push(std::deque<double>* samples, double value) {
  samples->push_back(value);
  while (samples->size() > window_) samples->pop_front();
}

void LatencyTrace::Add(const PairTimeline& pair) {
  const std::optional<Time>& presented = pair.at[static_cast<int>(LatencyStage::kPresented)];
  if (!presented) {
    ++incomplete_;
    return;
  }
  const double total_ms = ToSeconds(*presented - pair.capture) * 1e3;
  double known_ms = 0;
  std::optional<Time> previous = pair.capture;
  for (int s = 0; s < kLatencyStageCount; ++s) {
    const std::optional<Time>& end = pair.at[s];
    if (end && previous) {
      const double ms = ToSeconds(*end - *previous) * 1e3;
      Push(&stage_ms_[s], ms);
      known_ms += ms;
    }
    previous = end;
  }
  Push(&total_ms_, total_ms);
  Push(&unexplained_ms_, total_ms - known_ms);
}

std::vector<LatencyRow> LatencyTrace::Rows() const {
  auto row = [](std::string name, const std::deque<double>& samples) {
    LatencyRow r;
    r.name = std::move(name);
    r.samples = samples.size();
    const std::vector<double> v(samples.begin(), samples.end());
    r.p50_ms = Percentile(v, 0.50).value_or(0.0);
    r.p95_ms = Percentile(v, 0.95).value_or(0.0);
    return r;
  };
  std::vector<LatencyRow> rows;
  for (int s = 0; s < kLatencyStageCount; ++s) {
    rows.push_back(row(LatencyStageName(static_cast<LatencyStage>(s)), stage_ms_[s]));
  }
  rows.push_back(row("total", total_ms_));
  rows.push_back(row("unexplained", unexplained_ms_));
  return rows;
}

}  // namespace mostar::ui
