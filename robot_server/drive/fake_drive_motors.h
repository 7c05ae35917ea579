// DriveMotors for unit tests and dry runs: records commands and turns them into encoder counts
// when `Advance` is called (ideal wheels, no slip, no delay). Thread-safe.
#pragma once

#include <cmath>
#include <mutex>
#include <vector>

#include "robot_server/drive/drive_motors.h"

namespace mostar::drive {

class FakeDriveMotors final : public DriveMotors {
 public:
  FakeDriveMotors(double track_width_m, double metres_per_tick, int counter_bits = 16)
      : track_width_m_(track_width_m), metres_per_tick_(metres_per_tick), bits_(counter_bits) {}

  bool SetWheelVelocities(const WheelVelocities& wheels, std::string* /*error*/) override {
    std::lock_guard<std::mutex> lock(mutex_);
    wheels_ = wheels;
    return true;
  }
  bool SetVelocity(double linear_mps, double angular_radps, std::string* error) override {
    return SetWheelVelocities(WheelsFromBase(linear_mps, angular_radps, track_width_m_), error);
  }
  bool Stop(std::string* /*error*/, bool /*clear_faults*/ = false) override {
    std::lock_guard<std::mutex> lock(mutex_);
    wheels_ = {};
    ++stops_;
    return true;
  }
  MotorStatus Status() const override {
    MotorStatus status;
    status.link_ok = true;
    return status;
  }
  bool ReadEncoders(EncoderReading* reading, std::string* /*error*/) override {
    std::lock_guard<std::mutex> lock(mutex_);
    *reading = reading_;
    return true;
  }
  int counter_bits() const override { return bits_; }

  // Rolls the wheels at the current set-point for `dt`; stamps the reading with `now`.
  void Advance(Duration dt, Time now, SteadyTime steady_now) {
    std::lock_guard<std::mutex> lock(mutex_);
    left_m_ += wheels_.left_mps * ToSeconds(dt);
    right_m_ += wheels_.right_mps * ToSeconds(dt);
    const uint64_t mask = (uint64_t{1} << bits_) - 1;
    reading_.left_count = static_cast<uint32_t>(
        static_cast<uint64_t>(std::llround(left_m_ / metres_per_tick_)) & mask);
    reading_.right_count = static_cast<uint32_t>(
        static_cast<uint64_t>(std::llround(right_m_ / metres_per_tick_)) & mask);
    reading_.stamp = now;
    reading_.steady_stamp = steady_now;
  }

  WheelVelocities wheels() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return wheels_;
  }
  int stops() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return stops_;
  }

 private:
  const double track_width_m_;
  const double metres_per_tick_;
  const int bits_;
  mutable std::mutex mutex_;
  WheelVelocities wheels_;
  int stops_ = 0;
  double left_m_ = 0;
  double right_m_ = 0;
  EncoderReading reading_;
};

}  // namespace mostar::drive
