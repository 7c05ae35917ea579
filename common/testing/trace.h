// Reads the CSV traces written with --trace (common/log/stamp_trace.h), for cross-process tests.
#pragma once

#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "common/testing/subprocess.h"

namespace mostar::testing {

struct TraceLine {
  std::string topic;
  int64_t stamp_ns = 0;
  uint64_t sequence = 0;
};

inline std::vector<TraceLine> ReadTrace(const std::string& path) {
  std::vector<TraceLine> lines;
  std::istringstream in(ReadFile(path));
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    TraceLine t;
    std::string stamp, sequence;
    if (std::getline(fields, t.topic, ',') && std::getline(fields, stamp, ',') &&
        std::getline(fields, sequence)) {
      t.stamp_ns = std::stoll(stamp);
      t.sequence = std::stoull(sequence);
      lines.push_back(t);
    }
  }
  return lines;
}

}  // namespace mostar::testing
