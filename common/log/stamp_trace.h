// A CSV trace of stamped events ("topic,stamp_ns,sequence" per line), written by both programs
// with --trace FILE, so that tests and field diagnostics can match what one side published with
// what the other received. Thread-safe; a no-op when not opened.
#pragma once

#include <cstdint>
#include <fstream>
#include <mutex>
#include <string>

#include "common/time/time.h"

namespace mostar {

class StampTrace {
 public:
  // Empty path: stays disabled. False when the file cannot be written.
  bool Open(const std::string& path) {
    if (path.empty()) return true;
    out_.open(path, std::ios::trunc);
    return out_.good();
  }
  void Add(const char* topic, Time stamp, uint64_t sequence) {
    if (!out_.is_open()) return;
    std::lock_guard<std::mutex> lock(mutex_);
    out_ << topic << ',' << ToUnixNanos(stamp) << ',' << sequence << '\n';
  }
  void Flush() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (out_.is_open()) out_.flush();
  }

 private:
  std::mutex mutex_;
  std::ofstream out_;
};

}  // namespace mostar
