// SRF08 sensors on an emulated I2C bus, as the datasheet describes them: a ranging command
// makes the sensor deaf to the bus for the echo time of its window (at most 65 ms), then its
// first-echo registers hold the range in centimetres (0 = no echo within the window). The
// range of each ranging comes from a callback at the moment of the command. For tests and for
// the simulator (the same driver then runs against simulated echoes). Thread-safe.
#pragma once

#include <functional>
#include <map>
#include <mutex>
#include <string>

#include "common/time/time.h"
#include "robot_server/sonar/i2c_bus.h"

namespace mostar::sonar {

class Srf08BusEmulator final : public I2cBus {
 public:
  // Metres of the first echo the sensor at `address` hears now; +Inf = nothing.
  using RangeSource = std::function<float(uint8_t address)>;

  struct Sensor {
    uint8_t range_register = 255;  // power-on values
    uint8_t gain = 31;
    int rangings = 0;
    bool answering = true;  // false: unplugged or dead (never acknowledges)
    SteadyTime busy_until{};
    int echo_cm = 0;
  };

  Srf08BusEmulator(const Clock& clock, RangeSource source)
      : clock_(clock), source_(std::move(source)) {}

  void AddSensor(uint8_t address) {
    std::lock_guard<std::mutex> lock(mutex_);
    sensors_[address] = Sensor{};
  }
  void SetAnswering(uint8_t address, bool answering) {
    std::lock_guard<std::mutex> lock(mutex_);
    sensors_[address].answering = answering;
  }
  Sensor State(uint8_t address) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = sensors_.find(address);
    return it == sensors_.end() ? Sensor{} : it->second;
  }
  // The most sensors ever ranging at the same time (cross-talk between ping groups).
  int max_simultaneous() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return max_simultaneous_;
  }

  bool WriteRegister(uint8_t address, uint8_t reg, uint8_t value, std::string* error) override;
  bool ReadRegisters(uint8_t address, uint8_t reg, uint8_t* out, size_t count,
                     std::string* error) override;

 private:
  Sensor* Acknowledging(uint8_t address, std::string* error);  // mutex_ held

  const Clock& clock_;
  const RangeSource source_;
  mutable std::mutex mutex_;
  std::map<uint8_t, Sensor> sensors_;
  int max_simultaneous_ = 0;
};

}  // namespace mostar::sonar
