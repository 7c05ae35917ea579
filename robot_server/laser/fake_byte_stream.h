// A scripted ByteStream for unit tests, driven by a FakeClock: no threads, no sleeping.
//
// Bytes written by the code under test go to `on_write` (which may queue a reply with
// `QueueInput`). `Read` returns queued input immediately; with nothing queued it advances
// the clock by the whole timeout and returns 0, so timeouts and watchdogs run in zero wall
// time. `SetUnplugged(true)` makes every call fail until `Reopen` after `SetUnplugged(false)`.
#pragma once

#include <algorithm>
#include <deque>
#include <functional>
#include <string>
#include <vector>

#include "common/time/fake_clock.h"
#include "robot_server/laser/byte_stream.h"

namespace mostar::laser {

class FakeByteStream final : public ByteStream {
 public:
  using WriteHook = std::function<void(const std::vector<uint8_t>& written, FakeByteStream*)>;

  explicit FakeByteStream(FakeClock* clock) : clock_(clock) {}

  void set_on_write(WriteHook hook) { on_write_ = std::move(hook); }
  void QueueInput(const std::vector<uint8_t>& bytes) {
    input_.insert(input_.end(), bytes.begin(), bytes.end());
  }
  void SetUnplugged(bool unplugged) {
    unplugged_ = unplugged;
    if (unplugged) open_ = false;
  }
  const std::vector<std::vector<uint8_t>>& writes() const { return writes_; }
  int reopen_count() const { return reopen_count_; }

  bool Write(const uint8_t* data, size_t size, std::string* error) override {
    if (!open_) return Fail(error);
    writes_.emplace_back(data, data + size);
    if (on_write_) on_write_(writes_.back(), this);
    return true;
  }
  int Read(uint8_t* buffer, size_t max, Duration timeout, std::string* error) override {
    if (!open_) {
      Fail(error);
      return -1;
    }
    if (input_.empty()) {
      clock_->Advance(timeout);
      return 0;
    }
    const size_t n = std::min(max, input_.size());
    std::copy(input_.begin(), input_.begin() + static_cast<std::ptrdiff_t>(n), buffer);
    input_.erase(input_.begin(), input_.begin() + static_cast<std::ptrdiff_t>(n));
    return static_cast<int>(n);
  }
  void SetWriteByteGap(Duration gap) override { write_byte_gap_ = gap; }
  Duration write_byte_gap() const { return write_byte_gap_; }
  // Rates above `max` are refused, like an adapter that cannot produce them.
  void set_max_baud(int max) { max_baud_ = max; }
  bool SetBaudRate(int baud, std::string* error) override {
    if (baud > max_baud_) {
      if (error) *error = "fake adapter: no " + std::to_string(baud) + " Bd";
      return false;
    }
    baud_ = baud;
    return true;
  }
  int baud_rate() const override { return baud_; }
  void Flush() override { input_.clear(); }
  bool IsOpen() const override { return open_; }
  bool Reopen(std::string* error) override {
    ++reopen_count_;
    if (unplugged_) return Fail(error);
    open_ = true;
    return true;
  }
  void Close() override { open_ = false; }
  std::string name() const override { return "fake"; }

 private:
  bool Fail(std::string* error) {
    if (error) *error = "fake device unplugged";
    return false;
  }
  FakeClock* clock_;
  WriteHook on_write_;
  std::deque<uint8_t> input_;
  std::vector<std::vector<uint8_t>> writes_;
  int baud_ = 9600;
  int max_baud_ = 1 << 30;
  Duration write_byte_gap_{0};
  bool open_ = false;
  bool unplugged_ = false;
  int reopen_count_ = 0;
};

}  // namespace mostar::laser
