#include "common/record/recording_writer.h"

#include <algorithm>
#include <utility>

#include "common/log/log.h"
#include "common/record/record_conversions.h"
#include "common/record/recording.pb.h"

namespace mostar::record {
namespace {

template <typename T>
RecordedMessage Stamped(const Clock& clock, const T& value) {
  RecordedMessage message;
  message.log_time = clock.Now();
  message.payload = value;
  return message;
}

}  // namespace

bool RecordingWriterOptions::IsValid(std::string* error) const {
  if (sync_period <= Duration::zero()) {
    *error = "sync_period must be positive";
    return false;
  }
  if (index_period <= Duration::zero()) {
    *error = "index_period must be positive";
    return false;
  }
  if (index_record_period < index_period) {
    *error = "index_record_period must be at least index_period";
    return false;
  }
  if (max_queue_bytes < (1u << 20)) {
    *error = "max_queue_bytes must be at least 1 MiB";
    return false;
  }
  return true;
}

std::unique_ptr<RecordingWriter> RecordingWriter::Open(const std::string& path,
                                                       const RecordingWriterOptions& options,
                                                       const RecordingInfo& info,
                                                       const Clock& clock, std::string* error) {
  std::string option_error;
  if (!options.IsValid(&option_error)) {
    *error = "recording " + path + ": bad writer option: " + option_error;
    return nullptr;
  }
  std::unique_ptr<ByteSink> sink = OpenFileSink(path, error);
  if (sink == nullptr) return nullptr;
  return OpenSink(std::move(sink), path, options, info, clock, error);
}

std::unique_ptr<RecordingWriter> RecordingWriter::OpenSink(std::unique_ptr<ByteSink> sink,
                                                           const std::string& name,
                                                           const RecordingWriterOptions& options,
                                                           const RecordingInfo& info,
                                                           const Clock& clock, std::string* error) {
  std::string option_error;
  if (!options.IsValid(&option_error)) {
    *error = "recording " + name + ": bad writer option: " + option_error;
    return nullptr;
  }
  std::unique_ptr<RecordingWriter> writer(
      new RecordingWriter(std::move(sink), name, options, clock));
  if (!writer->WriteHeader(info, error)) return nullptr;
  writer->thread_ = std::thread([w = writer.get()] { w->Run(); });
  return writer;
}

RecordingWriter::RecordingWriter(std::unique_ptr<ByteSink> sink, std::string name,
                                 const RecordingWriterOptions& options, const Clock& clock)
    : name_(std::move(name)), options_(options), clock_(clock), sink_(std::move(sink)) {
  last_sync_ = clock_.SteadyNow();
}

RecordingWriter::~RecordingWriter() { Close(); }

bool RecordingWriter::WriteHeader(const RecordingInfo& info, std::string* error) {
  RecordingInfo stamped = info;
  if (stamped.creation_time == Time{}) stamped.creation_time = clock_.Now();
  proto::Header header;
  ToProto(stamped, &header);
  std::string bytes(kMagic, kMagicSize);
  for (int i = 0; i < 4; ++i)
    bytes.push_back(static_cast<char>((kFormatVersion >> (8 * i)) & 0xFFu));
  AppendFrame(header.SerializeAsString(), &bytes);
  std::string sink_error;
  if (!sink_->Append(bytes.data(), bytes.size(), &sink_error) || !sink_->Sync(&sink_error)) {
    *error = "cannot write the header of recording " + name_ + ": " + sink_error;
    std::string ignored;
    sink_->Close(&ignored);
    closed_ = true;
    return false;
  }
  offset_ = bytes.size();
  stats_.bytes_written = offset_;
  return true;
}

bool RecordingWriter::Write(const CompressedImage& image, Eye eye) {
  RecordedMessage message;
  message.log_time = clock_.Now();
  message.payload = RecordedImage{eye, 0, image};
  return Write(message);
}

bool RecordingWriter::Write(const CompressedStereoPair& pair) {
  RecordedMessage message;
  message.log_time = clock_.Now();
  message.payload = RecordedImage{Eye::kLeft, pair.sequence, pair.left};
  const bool left = Write(message);
  message.payload = RecordedImage{Eye::kRight, pair.sequence, pair.right};
  const bool right = Write(message);
  return left && right;
}

bool RecordingWriter::Write(const LaserScan& scan) { return Write(Stamped(clock_, scan)); }
bool RecordingWriter::Write(const Odometry& odometry) { return Write(Stamped(clock_, odometry)); }
bool RecordingWriter::Write(const VelocityCommand& command) {
  return Write(Stamped(clock_, command));
}
bool RecordingWriter::Write(const EmergencyStop& stop) { return Write(Stamped(clock_, stop)); }
bool RecordingWriter::Write(const ControlRequest& request) {
  return Write(Stamped(clock_, request));
}
bool RecordingWriter::Write(const ControlLease& lease) { return Write(Stamped(clock_, lease)); }
bool RecordingWriter::Write(const SonarRanges& ranges) { return Write(Stamped(clock_, ranges)); }
bool RecordingWriter::Write(const BumperState& state) { return Write(Stamped(clock_, state)); }
bool RecordingWriter::Write(const RobotHealth& health) { return Write(Stamped(clock_, health)); }

bool RecordingWriter::Write(const RecordedMessage& message) {
  proto::Record record;
  ToProto(message, &record);
  Item item;
  item.log_time = message.log_time;
  item.is_frame = message.kind() == RecordKind::kImage;
  item.bytes = record.SerializeAsString();
  if (item.bytes.size() > kMaxRecordBytes) {
    MOSTAR_LOG_EVERY_SEC(ERROR, 5)
        << "recording " << name_ << ": dropping a " << TopicName(message) << " record of "
        << item.bytes.size() << " bytes (limit " << kMaxRecordBytes << ")";
    std::lock_guard<std::mutex> lock(mutex_);
    ++(item.is_frame ? stats_.frames_dropped : stats_.records_dropped);
    return false;
  }
  return Enqueue(std::move(item));
}

bool RecordingWriter::Enqueue(Item item) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (closing_ || closed_ || stats_.failed) {
    ++stats_.records_dropped;
    return false;
  }
  const size_t size = item.bytes.size();
  if (stats_.queued_bytes + size > options_.max_queue_bytes) {
    if (item.is_frame) {
      ++stats_.frames_dropped;
      MOSTAR_LOG_EVERY_SEC(WARNING, 5)
          << "recording " << name_ << ": disk too slow, dropping camera frames";
      return false;
    }
    // Make room by dropping queued frames, oldest first.
    for (auto it = queue_.begin();
         it != queue_.end() && stats_.queued_bytes + size > options_.max_queue_bytes;) {
      if (it->is_frame) {
        stats_.queued_bytes -= it->bytes.size();
        ++stats_.frames_dropped;
        it = queue_.erase(it);
      } else {
        ++it;
      }
    }
    if (stats_.queued_bytes + size > 2 * options_.max_queue_bytes) {
      ++stats_.records_dropped;
      MOSTAR_LOG_EVERY_SEC(ERROR, 5) << "recording " << name_ << ": disk stalled, dropping records";
      return false;
    }
  }
  stats_.queued_bytes += size;
  queue_.push_back(std::move(item));
  wake_.notify_one();
  return true;
}

void RecordingWriter::Run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait_for(lock, options_.sync_period, [this] { return closing_ || !queue_.empty(); });
    std::deque<Item> batch;
    batch.swap(queue_);
    stats_.queued_bytes = 0;
    const bool closing = closing_;
    lock.unlock();
    size_t written = 0;
    for (const Item& item : batch) {
      if (failed_ || !AppendRecord(item.bytes, true, item.log_time)) break;
      ++written;
    }
    if (!failed_) MaybeSync(false);
    lock.lock();
    stats_.records_dropped += batch.size() - written;
    if (closing && queue_.empty()) break;
  }
}

bool RecordingWriter::AppendBytes(const std::string& bytes) {
  std::string error;
  if (!sink_->Append(bytes.data(), bytes.size(), &error)) {
    std::string cut_error;
    const bool cut = sink_->Truncate(offset_, &cut_error);
    Fail(error + "; the file is readable up to byte " + std::to_string(offset_) +
         (cut ? "" : " (the partly written record could not be cut off: " + cut_error + ")"));
    return false;
  }
  offset_ += bytes.size();
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.bytes_written = offset_;
  return true;
}

bool RecordingWriter::AppendRecord(const std::string& record_bytes, bool is_data, Time log_time) {
  std::string frame;
  frame.reserve(record_bytes.size() + kMaxFrameOverheadBytes);
  AppendFrame(record_bytes, &frame);
  const uint64_t frame_offset = offset_;
  if (!AppendBytes(frame)) return false;
  if (!is_data) return true;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.records_written;
  }
  max_log_time_ = std::max(max_log_time_, log_time);
  if (!have_index_time_) {
    have_index_time_ = true;
    last_index_record_time_ = log_time;
    next_index_time_ = log_time;
  }
  if (log_time >= next_index_time_) {
    index_.push_back(IndexEntry{log_time, frame_offset});
    next_index_time_ = log_time + options_.index_period;
  }
  MaybeWriteIndexRecord(log_time, false);
  return true;
}

void RecordingWriter::MaybeWriteIndexRecord(Time log_time, bool force) {
  if (index_.size() == index_entries_in_records_) return;
  if (!force && log_time - last_index_record_time_ < options_.index_record_period) return;
  proto::Record record;
  record.set_log_time_unix_ns(ToUnixNanos(log_time));
  proto::Index* index = record.mutable_index();
  for (size_t i = index_entries_in_records_; i < index_.size(); ++i) {
    proto::IndexEntry* entry = index->add_entries();
    entry->set_log_time_unix_ns(ToUnixNanos(index_[i].log_time));
    entry->set_offset(index_[i].offset);
  }
  if (AppendRecord(record.SerializeAsString(), false, log_time)) {
    index_entries_in_records_ = index_.size();
    last_index_record_time_ = log_time;
  }
}

void RecordingWriter::MaybeSync(bool force) {
  const SteadyTime now = clock_.SteadyNow();
  if (!force && now - last_sync_ < options_.sync_period) return;
  last_sync_ = now;
  std::string error;
  if (!sink_->Sync(&error)) {
    Fail(error);
    return;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  ++stats_.syncs;
}

void RecordingWriter::Fail(const std::string& error) {
  if (failed_) return;
  failed_ = true;
  const std::string message = "recording " + name_ + " stopped: " + error;
  MOSTAR_LOG(ERROR) << message;
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.failed = true;
  stats_.error = message;
}

bool RecordingWriter::Close(std::string* error) {
  std::lock_guard<std::mutex> close_lock(close_mutex_);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_) {
      if (stats_.failed && error != nullptr) *error = stats_.error;
      return !stats_.failed;
    }
    closing_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();

  if (!failed_) {
    // Footer: every index entry, then the trailer pointing at it.
    proto::Record record;
    record.set_log_time_unix_ns(ToUnixNanos(max_log_time_));
    proto::Index* index = record.mutable_index();
    index->set_footer(true);
    for (const IndexEntry& entry : index_) {
      proto::IndexEntry* e = index->add_entries();
      e->set_log_time_unix_ns(ToUnixNanos(entry.log_time));
      e->set_offset(entry.offset);
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      index->set_data_record_count(stats_.records_written);
    }
    index->set_end_time_unix_ns(ToUnixNanos(max_log_time_));
    const uint64_t footer_offset = offset_;
    if (AppendRecord(record.SerializeAsString(), false, max_log_time_)) {
      std::string trailer;
      for (int i = 0; i < 8; ++i) {
        trailer.push_back(static_cast<char>((footer_offset >> (8 * i)) & 0xFFu));
      }
      trailer.append(kTrailerMagic, 8);
      if (AppendBytes(trailer)) MaybeSync(true);
    }
  }
  std::string close_error;
  if (!sink_->Close(&close_error)) Fail(close_error);

  std::lock_guard<std::mutex> lock(mutex_);
  closed_ = true;
  if (stats_.failed && error != nullptr) *error = stats_.error;
  return !stats_.failed;
}

RecordingWriterStats RecordingWriter::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

}  // namespace mostar::record
