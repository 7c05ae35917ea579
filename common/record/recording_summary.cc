#include "common/record/recording_summary.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace mostar::record {
namespace {

std::string Seconds(Duration d) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3f s", ToSeconds(d));
  return text;
}

std::string Bytes(double bytes) {
  char text[32];
  if (bytes >= 1024.0 * 1024.0) {
    std::snprintf(text, sizeof(text), "%.1f MiB", bytes / (1024.0 * 1024.0));
  } else if (bytes >= 1024.0) {
    std::snprintf(text, sizeof(text), "%.1f KiB", bytes / 1024.0);
  } else {
    std::snprintf(text, sizeof(text), "%.0f B", bytes);
  }
  return text;
}

}  // namespace

double TopicSummary::rate_hz() const {
  const double span_s = ToSeconds(last - first);
  if (count < 2 || span_s <= 0) return 0;
  return static_cast<double>(count - 1) / span_s;
}

double TopicSummary::mean_bytes() const {
  return count == 0 ? 0 : static_cast<double>(total_bytes) / static_cast<double>(count);
}

RecordingSummary SummarizeRecording(RecordingReader* reader, Duration long_gap) {
  RecordingSummary summary;
  summary.info = reader->info();
  summary.file_size_bytes = reader->file_size_bytes();
  summary.has_footer = reader->has_footer();
  reader->Rewind();
  const uint64_t index_before = reader->index_records_seen();
  const uint64_t unknown_before = reader->unknown_records_skipped();
  RecordedMessage message;
  while (reader->Next(&message)) {
    if (summary.record_count == 0) {
      summary.start = summary.end = message.log_time;
    }
    summary.start = std::min(summary.start, message.log_time);
    summary.end = std::max(summary.end, message.log_time);
    ++summary.record_count;
    TopicSummary& topic = summary.topics[TopicName(message)];
    if (topic.count > 0) {
      const Duration gap = message.log_time - topic.last;
      if (gap > topic.largest_gap) topic.largest_gap = gap;
      if (gap > long_gap) topic.long_gaps.push_back(Gap{topic.last, message.log_time});
    } else {
      topic.first = message.log_time;
    }
    topic.last = message.log_time;
    ++topic.count;
    topic.total_bytes += message.size_bytes;
  }
  summary.damage = reader->damage();
  summary.index_records = reader->index_records_seen() - index_before;
  summary.unknown_records = reader->unknown_records_skipped() - unknown_before;
  return summary;
}

std::string FormatSummary(const RecordingSummary& s, size_t max_gaps_listed) {
  std::ostringstream out;
  const RecordingInfo& info = s.info;
  out << "format version:  " << info.format_version << "\n";
  out << "robot:           " << (info.robot_id.empty() ? "(unknown)" : info.robot_id) << "\n";
  out << "created:         " << ToIso8601(info.creation_time) << "\n";
  out << "file size:       " << Bytes(static_cast<double>(s.file_size_bytes)) << " ("
      << s.file_size_bytes << " bytes)\n";
  out << "closed cleanly:  "
      << (s.has_footer ? "yes (footer index present)" : "no (no footer: index rebuilt by scanning)")
      << "\n";
  const SensorDescription& sensors = info.sensors;
  if (sensors.laser_beam_count > 0) {
    out << "laser:           " << sensors.laser_beam_count << " beams from "
        << sensors.laser_angle_min_rad << " rad, step " << sensors.laser_angle_increment_rad
        << " rad, max " << sensors.laser_range_max_m << " m, " << sensors.laser_scan_rate_hz
        << " Hz\n";
  }
  if (sensors.camera_width_px > 0) {
    out << "camera:          " << sensors.camera_width_px << "x" << sensors.camera_height_px << " "
        << sensors.camera_format << " at " << sensors.camera_frame_rate_hz << " Hz\n";
  }
  out << "calibration:     "
      << (info.calibration_text.empty() ? "none"
                                        : std::to_string(info.calibration_text.size()) + " bytes")
      << "\n";
  for (const auto& [key, value] : info.metadata) out << "meta " << key << ": " << value << "\n";

  if (s.record_count == 0) {
    out << "records:         none\n";
  } else {
    out << "start:           " << ToIso8601(s.start) << "\n";
    out << "end:             " << ToIso8601(s.end) << "\n";
    out << "duration:        " << Seconds(s.duration()) << "\n";
    out << "records:         " << s.record_count << " (+" << s.index_records << " index records";
    if (s.unknown_records > 0) out << ", " << s.unknown_records << " of unknown type skipped";
    out << ")\n\n";
    char line[256];
    std::snprintf(line, sizeof(line), "%-16s %9s %9s %12s %11s %12s\n", "topic", "count", "rate Hz",
                  "total", "mean", "largest gap");
    out << line;
    for (const auto& [name, t] : s.topics) {
      std::snprintf(line, sizeof(line), "%-16s %9llu %9.2f %12s %11s %12s\n", name.c_str(),
                    static_cast<unsigned long long>(t.count), t.rate_hz(),
                    Bytes(static_cast<double>(t.total_bytes)).c_str(),
                    Bytes(t.mean_bytes()).c_str(), Seconds(t.largest_gap).c_str());
      out << line;
    }
    for (const auto& [name, t] : s.topics) {
      if (t.long_gaps.empty()) continue;
      out << "\ngaps in " << name << " (" << t.long_gaps.size() << "):\n";
      for (size_t i = 0; i < t.long_gaps.size() && i < max_gaps_listed; ++i) {
        const Gap& gap = t.long_gaps[i];
        out << "  " << Seconds(gap.to - gap.from) << " at +" << Seconds(gap.from - s.start) << " ("
            << ToIso8601(gap.from) << ")\n";
      }
      if (t.long_gaps.size() > max_gaps_listed) {
        out << "  ... and " << t.long_gaps.size() - max_gaps_listed << " more\n";
      }
    }
  }
  out << "\ndamage:          ";
  if (s.damage.has_value()) {
    out << "at byte " << s.damage->offset << ": " << s.damage->reason
        << " (records before it are intact)\n";
  } else {
    out << "none\n";
  }
  return out.str();
}

}  // namespace mostar::record
