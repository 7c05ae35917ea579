// Statistics of a whole recording, for mostar_record_info and tests.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/record/recording_reader.h"

namespace mostar::record {

struct Gap {
  Time from;  // log time of the record before the gap
  Time to;    // log time of the record after it
};

struct TopicSummary {
  uint64_t count = 0;
  uint64_t total_bytes = 0;  // frame sizes on disk
  Time first;
  Time last;
  Duration largest_gap{0};
  std::vector<Gap> long_gaps;  // gaps longer than the threshold, in order

  // Records per second between the first and the last; 0 with fewer than 2 records.
  double rate_hz() const;
  double mean_bytes() const;
};

struct RecordingSummary {
  RecordingInfo info;
  uint64_t file_size_bytes = 0;
  bool has_footer = false;
  uint64_t record_count = 0;
  uint64_t index_records = 0;
  uint64_t unknown_records = 0;
  Time start;  // first and last log time (zero without records)
  Time end;
  std::map<std::string, TopicSummary> topics;  // by TopicName()
  std::optional<RecordDamage> damage;

  Duration duration() const { return end - start; }
};

// Reads every record from the beginning. Gaps longer than `long_gap` are listed per topic.
RecordingSummary SummarizeRecording(RecordingReader* reader, Duration long_gap = FromSeconds(1.0));

// Human-readable report (what mostar_record_info prints). At most `max_gaps_listed` long gaps
// are listed per topic; the rest are counted.
std::string FormatSummary(const RecordingSummary& summary, size_t max_gaps_listed = 20);

}  // namespace mostar::record
