// BumperBelt for unit tests: the test sets the pressed segments, or makes the reads fail.
// Thread-safe.
#pragma once

#include <mutex>
#include <string>

#include "robot_server/bumper/bumper_belt.h"

namespace mostar::bumper {

class FakeBumperBelt final : public BumperBelt {
 public:
  explicit FakeBumperBelt(int segments = 16) : segments_(segments) {}

  bool Read(uint32_t* pressed, std::string* error) override {
    std::lock_guard<std::mutex> lock(mutex_);
    ++reads_;
    if (!error_.empty()) {
      *error = error_;
      return false;
    }
    *pressed = pressed_;
    return true;
  }
  int segments() const override { return segments_; }
  DeviceHealth Health() const override {
    std::lock_guard<std::mutex> lock(mutex_);
    DeviceHealth health;
    health.name = "bumpers";
    health.state = error_.empty() ? DeviceState::kOk : DeviceState::kError;
    health.message = error_;
    health.counters = {{"reads", reads_}, {"pressed_mask", pressed_}};
    return health;
  }

  void Press(uint32_t mask) {
    std::lock_guard<std::mutex> lock(mutex_);
    pressed_ = mask;
  }
  // Non-empty: reads fail with this message.
  void Fail(const std::string& error) {
    std::lock_guard<std::mutex> lock(mutex_);
    error_ = error;
  }

 private:
  const int segments_;
  mutable std::mutex mutex_;
  uint32_t pressed_ = 0;
  std::string error_;
  uint64_t reads_ = 0;
};

}  // namespace mostar::bumper
