#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "operator_client/ui/latency_trace.h"
#include "operator_client/video/stereo_receiver.h"

namespace mostar::ui {

// What the console counted over a run, for its report line.
struct ConsoleRunTotals {
  uint64_t rendered_frames = 0;
  uint64_t scripted_rearms = 0;
  uint64_t scans = 0;
  uint64_t commands_sent = 0;
  double run_s = 0;  // start of the render loop to its end, discovery included. unit: s
  double display_age_ms_p50 = 0;
  double display_age_ms_p95 = 0;
  double frame_time_ms_p50 = 0;
  double frame_time_ms_p95 = 0;
  std::optional<int64_t> captured_stamp_ns;  // the captured pair's stamp (--capture-stamp)
  uint64_t sonar_echoes = 0;
  uint64_t sonar_unseen = 0;
  uint64_t overlays_moved = 0;
  uint64_t overlays_faded = 0;
  std::vector<LatencyRow> latency;      // one p50/p95 pair of keys per row
  std::vector<LatencyRow> frame_parts;  // `drawn` by part (FrameParts): part_<name>_ms_p50/_p95
  // Edge processing: pairs shown with their result, shown when their result wait ran out (and
  // of those, the result added later), and results that came when a newer pair was on screen.
  uint64_t vision_in_time = 0;
  uint64_t vision_without_result = 0;
  uint64_t vision_added_late = 0;
  uint64_t vision_missed = 0;
};

// The console's report: one line "report: key=value ..." ending in a newline, which the tests
// and benches read (keys are stable; new ones go at the end). `pairs_per_s_run` is the run's
// average (pairs decoded / run_s), `pair_rate_hz_last_2s` the receiver's last window.
std::string FormatRunReport(const ConsoleRunTotals& console, const client::ReceiverStats& video);

}  // namespace mostar::ui
