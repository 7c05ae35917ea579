#include "common/log/stamp_trace.h"

namespace mostar {

StampTrace::~StampTrace() {
  if (!open_) return;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  stop_cv_.notify_all();
  writer_.join();
  Flush();
  const std::lock_guard<std::mutex> io_lock(io_mutex_);
  const uint64_t lost = dropped();
  if (lost > 0) out_ << "#dropped," << lost << "\n";
  out_.close();
}

bool StampTrace::Open(const std::string& path) {
  if (path.empty() || open_) return true;
  out_.open(path, std::ios::trunc);
  if (!out_.good()) return false;
  open_ = true;
  writer_ = std::thread([this] { WriterLoop(); });
  return true;
}

void StampTrace::Add(const char* topic, Time stamp, uint64_t sequence) {
  if (!open_) return;
  const std::string line = std::string(topic) + ',' + std::to_string(ToUnixNanos(stamp)) + ',' +
                           std::to_string(sequence) + '\n';
  const std::lock_guard<std::mutex> lock(mutex_);
  if (buffer_.size() + line.size() > kMaxBufferedBytes) {
    ++dropped_;
    return;
  }
  buffer_ += line;
}

void StampTrace::Flush() {
  if (!open_) return;
  const std::lock_guard<std::mutex> io_lock(io_mutex_);
  WriteBuffered();
  out_.flush();
}

uint64_t StampTrace::dropped() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return dropped_;
}

void StampTrace::WriteBuffered() {
  std::string lines;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    lines.swap(buffer_);
  }
  out_ << lines;
}

void StampTrace::WriterLoop() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    stop_cv_.wait_for(lock, kWritePeriod, [this] { return stop_; });
    lock.unlock();
    {
      const std::lock_guard<std::mutex> io_lock(io_mutex_);
      WriteBuffered();
      out_.flush();
    }
    lock.lock();
  }
}

}  // namespace mostar
