#include "operator_client/ui/run_report.h"

#include <algorithm>
#include <sstream>

namespace mostar::ui {

std::string FormatRunReport(const ConsoleRunTotals& c, const client::ReceiverStats& v) {
  std::ostringstream out;
  const double run_s = std::max(1e-3, c.run_s);
  out << "report: rendered_frames=" << c.rendered_frames << " scripted_rearms=" << c.scripted_rearms
      << " pairs_decoded=" << v.pairs_decoded << " images=" << v.images
      << " broken_images=" << v.broken_images << " scans=" << c.scans
      << " commands_sent=" << c.commands_sent << " pair_rate_hz_last_2s=" << v.pair_rate_hz
      << " pairs_per_s_run=" << static_cast<double>(v.pairs_decoded) / run_s
      << " display_age_ms_p50=" << c.display_age_ms_p50
      << " display_age_ms_p95=" << c.display_age_ms_p95
      << " frame_time_ms_p50=" << c.frame_time_ms_p50
      << " frame_time_ms_p95=" << c.frame_time_ms_p95;
  if (c.captured_stamp_ns) out << " captured_stamp_ns=" << *c.captured_stamp_ns;
  out << " sonar_echoes=" << c.sonar_echoes << " sonar_unseen=" << c.sonar_unseen
      << " overlays_moved=" << c.overlays_moved << " overlays_faded=" << c.overlays_faded;
  for (const LatencyRow& row : c.latency) {
    out << " latency_" << row.name << "_ms_p50=" << row.p50_ms << " latency_" << row.name
        << "_ms_p95=" << row.p95_ms;
  }
  out << " oversized_images=" << v.oversized_images << " future_pairs=" << v.future_dropped
      << " stamp_resyncs=" << v.stamp_resyncs << " left_decodes=" << v.left_decodes
      << " right_decodes=" << v.right_decodes << " scaled_decodes=" << v.scaled_decodes
      << " video_frames=" << v.video_frames << " video_gaps=" << v.video_gaps
      << " video_errors=" << v.video_errors << " video_skipped=" << v.video_skipped
      << " video_queue_dropped=" << v.video_queue_dropped
      << " keyframe_requests=" << v.keyframe_requests << " pairs_dropped=" << v.pairs_dropped
      << " late_pairs=" << v.late_dropped << " vision_in_time=" << c.vision_in_time
      << " vision_without_result=" << c.vision_without_result
      << " vision_added_late=" << c.vision_added_late << " vision_missed=" << c.vision_missed;
  for (const LatencyRow& row : c.frame_parts) {
    out << " part_" << row.name << "_ms_p50=" << row.p50_ms << " part_" << row.name
        << "_ms_p95=" << row.p95_ms;
  }
  out << "\n";
  return out.str();
}

}  // namespace mostar::ui
