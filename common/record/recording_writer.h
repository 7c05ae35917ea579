// Writes a recording file (format: recording_format.h, docs/recording.md).
//
// Threading: Write() may be called from any thread (DDS listeners); it converts the message
// and queues it, never blocking on the disk. A background thread appends queued records in
// order, handing each to the operating system as it is written and calling fdatasync every
// `sync_period`. Guarantee: after a process crash, every record written before the last
// queue drain is readable (the queue holds milliseconds of data unless the disk stalls); after
// a power loss, at most the last `sync_period` of records is lost. In both cases the file reads
// cleanly up to the last complete record; only the footer index is missing (the reader then
// rebuilds it by scanning).
//
// Queue bound: when queued bytes exceed `max_queue_bytes`, a new camera frame is dropped; a new
// scan/odometry/command/lease/health record evicts queued frames instead and is always kept
// (up to twice the bound, then it is dropped too: the disk has stalled). Drops are counted.
//
// Failures: a write error (disk full, I/O error) stops the recording. The partly written record
// is cut off so the file stays readable up to the last complete record, the error is logged
// once and kept in stats().error, and later Write() calls are counted as dropped.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/record/byte_sink.h"
#include "common/record/recording_format.h"
#include "common/time/time.h"

namespace mostar::record {

struct RecordingWriterOptions {
  // fdatasync period: the most data a power loss can cost.
  Duration sync_period = FromSeconds(1.0);
  // One index entry per period of log time.
  Duration index_period = FromSeconds(1.0);
  // A periodic index record (entries since the previous one) per period of log time.
  Duration index_record_period = FromSeconds(10.0);
  // Queue bound in bytes of serialized records (see the class comment for the drop policy).
  size_t max_queue_bytes = 64u << 20;

  // False with a message naming the offending option.
  bool IsValid(std::string* error) const;
};

struct RecordingWriterStats {
  uint64_t records_written = 0;  // data records (index records not counted)
  uint64_t bytes_written = 0;    // file size so far
  uint64_t frames_dropped = 0;   // camera eyes dropped because the queue was full
  // Other records dropped because the disk stalled, and every record offered after a failure
  // or Close().
  uint64_t records_dropped = 0;
  uint64_t syncs = 0;
  size_t queued_bytes = 0;
  bool failed = false;
  std::string error;  // set when failed
};

class RecordingWriter {
 public:
  // Creates `path` and writes the prelude and header (synchronously, so a bad path or a full
  // disk is reported here). `clock` gives log times (Now) and the sync period (SteadyNow); it
  // must outlive the writer. Null with a message on failure.
  static std::unique_ptr<RecordingWriter> Open(const std::string& path,
                                               const RecordingWriterOptions& options,
                                               const RecordingInfo& info, const Clock& clock,
                                               std::string* error);
  // The same over any sink (tests inject failing sinks). `name` is used in messages.
  static std::unique_ptr<RecordingWriter> OpenSink(std::unique_ptr<ByteSink> sink,
                                                   const std::string& name,
                                                   const RecordingWriterOptions& options,
                                                   const RecordingInfo& info, const Clock& clock,
                                                   std::string* error);

  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;
  // Closes (see Close()).
  ~RecordingWriter();

  // Queue one record, stamped with the clock's Now() as its log time. Thread-safe. False when
  // the record was dropped (queue full, or the writer failed or is closed).
  bool Write(const CompressedImage& image, Eye eye);
  bool Write(const CompressedStereoPair& pair);  // both eyes, same log time
  bool Write(const LaserScan& scan);
  bool Write(const Odometry& odometry);
  bool Write(const VelocityCommand& command);
  bool Write(const EmergencyStop& stop);
  bool Write(const ControlRequest& request);
  bool Write(const ControlLease& lease);
  bool Write(const RobotHealth& health);
  bool Write(const SonarRanges& ranges);
  bool Write(const BumperState& state);
  // Records larger than kMaxRecordBytes serialized are dropped and counted.
  // Queues a record with its own log time (re-recording, filtering, tests). Log times should be
  // non-decreasing in write order for SeekToTime to be exact.
  bool Write(const RecordedMessage& message);

  // Writes everything queued, then the footer index and trailer, syncs and closes the file.
  // Idempotent. False with a message if anything failed since Open (the file is still readable
  // up to the last complete record).
  bool Close(std::string* error = nullptr);

  RecordingWriterStats stats() const;

 private:
  struct Item {
    Time log_time;
    bool is_frame = false;
    std::string bytes;  // serialized proto::Record
  };

  RecordingWriter(std::unique_ptr<ByteSink> sink, std::string name,
                  const RecordingWriterOptions& options, const Clock& clock);
  bool WriteHeader(const RecordingInfo& info, std::string* error);
  bool Enqueue(Item item);
  void Run();
  // Writer thread only.
  bool AppendBytes(const std::string& bytes);
  bool AppendRecord(const std::string& record_bytes, bool is_data, Time log_time);
  void MaybeWriteIndexRecord(Time log_time, bool force);
  void MaybeSync(bool force);
  void Fail(const std::string& error);

  const std::string name_;
  const RecordingWriterOptions options_;
  const Clock& clock_;
  std::unique_ptr<ByteSink> sink_;

  std::mutex close_mutex_;  // serializes Close()
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Item> queue_;
  bool closing_ = false;
  bool closed_ = false;
  RecordingWriterStats stats_;
  std::thread thread_;

  // Writer thread only (and Close after the join).
  uint64_t offset_ = 0;  // bytes completely written
  std::vector<IndexEntry> index_;
  size_t index_entries_in_records_ = 0;  // entries already in a periodic index record
  bool have_index_time_ = false;
  Time next_index_time_;
  Time last_index_record_time_;
  Time max_log_time_;
  SteadyTime last_sync_;
  bool failed_ = false;
};

}  // namespace mostar::record
