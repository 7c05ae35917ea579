// Where the capture-to-screen time of each stereo pair goes: one stamp per stage, all on the
// robot's clock (the operator's stamps are offset-corrected), and per stage the time since the
// stage before it. Stages are consecutive, so with every stamp known they add up to the total;
// what a missing stamp leaves unattributed is reported as "unexplained". Pure: no GL, no DDS.
#pragma once

#include <array>
#include <cstddef>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "common/time/time.h"

namespace mostar::ui {

// Each stage ends at its stamp and starts at the previous stage's (capture for the first).
enum class LatencyStage : int {
  kEncoded = 0,  // robot: capture to both JPEGs encoded (incl. waiting for the encoder)
  kWritten,      // robot: handed to DDS (ack-clock lane, serialisation)
  kReceived,     // network and DDS delivery: both eyes here
  kQueued,       // the decoder thread took the pair (waiting behind the pair being decoded)
  kDecoded,      // both eyes decoded (the decode work, both eyes at once)
  kPicked,       // the render loop took the pair (its wake-up, or a frame being drawn)
  kVision,       // its edge result published, or its result wait ran out (zero when off)
  kStarted,      // the frame that shows it began (waiting for the render loop)
  kDrawn,        // images, overlay and panels drawn (CPU side of the frame)
  kPresented,    // buffers swapped and the GPU finished (glFinish)
  kCount
};
inline constexpr int kLatencyStageCount = static_cast<int>(LatencyStage::kCount);
const char* LatencyStageName(LatencyStage stage);

struct PairTimeline {
  Time capture;
  std::array<std::optional<Time>, kLatencyStageCount> at;  // when each stage ended

  void Set(LatencyStage stage, Time t) { at[static_cast<int>(stage)] = t; }
};

struct LatencyRow {
  std::string name;  // a stage, "total" (capture to presented) or "unexplained"
  double p50_ms = 0;
  double p95_ms = 0;
  size_t samples = 0;
};

class LatencyTrace {
 public:
  // Keeps the last `window` pairs (> 0).
  explicit LatencyTrace(size_t window = 1000);

  // A pair that reached the screen (its kPresented stamp is set; others are ignored and
  // counted). A stage's time counts only when its stamp and the previous one are both known.
  void Add(const PairTimeline& pair);

  // One row per stage in order, then "total" and "unexplained" (total minus the stage times
  // known for that pair). Rows without samples show zeros.
  std::vector<LatencyRow> Rows() const;
  size_t pairs() const { return total_ms_.size(); }
  size_t incomplete() const { return incomplete_; }  // pairs without a presented stamp

 private:
  void Push(std::deque<double>* samples, double value);

  size_t window_;
  std::array<std::deque<double>, kLatencyStageCount> stage_ms_;
  std::deque<double> total_ms_;
  std::deque<double> unexplained_ms_;
  size_t incomplete_ = 0;
};

}  // namespace mostar::ui
