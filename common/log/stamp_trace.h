// A CSV trace of stamped events ("topic,stamp_ns,sequence" per line), written by both programs
// with --trace FILE, so that tests and field diagnostics can match what one side published with
// what the other received. Thread-safe; a no-op when not opened.
//
// Add() never touches the disk: it appends the line to a buffer in memory, and a background
// thread writes the buffer to the file every kWritePeriod. A write that stalls on the disk
// (writeback of a busy machine) therefore never stalls the caller, the robot's control loop
// among them. Above kMaxBufferedBytes (the disk has stalled for long) new lines are dropped and
// counted; the file then ends with a line "#dropped,N". Flush() writes what is buffered, on the
// calling thread.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>

#include "common/time/time.h"

namespace mostar {

class StampTrace {
 public:
  static constexpr std::chrono::milliseconds kWritePeriod{200};
  static constexpr size_t kMaxBufferedBytes = 16u << 20;

  StampTrace() = default;
  StampTrace(const StampTrace&) = delete;
  StampTrace& operator=(const StampTrace&) = delete;
  ~StampTrace();  // writes what is buffered and closes the file

  // Empty path: stays disabled. False when the file cannot be written. Call once.
  bool Open(const std::string& path);
  void Add(const char* topic, Time stamp, uint64_t sequence);
  // Writes every line added so far to the file.
  void Flush();
  // Lines dropped because the buffer was full.
  uint64_t dropped() const;

 private:
  void WriterLoop();
  // Moves the buffer out and writes it; the caller holds io_mutex_.
  void WriteBuffered();

  mutable std::mutex mutex_;  // guards buffer_, dropped_, stop_
  std::condition_variable stop_cv_;
  std::string buffer_;
  uint64_t dropped_ = 0;
  bool stop_ = false;
  std::atomic<bool> open_{false};  // set once by Open()
  std::mutex io_mutex_;  // guards out_: one write at a time, in the order lines were added
  std::ofstream out_;
  std::thread writer_;
};

}  // namespace mostar
