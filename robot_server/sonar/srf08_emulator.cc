#include "robot_server/sonar/srf08_emulator.h"

#include <algorithm>
#include <cmath>

#include "robot_server/sonar/srf08.h"

namespace mostar::sonar {

Srf08BusEmulator::Sensor* Srf08BusEmulator::Acknowledging(uint8_t address, std::string* error) {
  const auto it = sensors_.find(address);
  if (it == sensors_.end() || !it->second.answering || clock_.SteadyNow() < it->second.busy_until) {
    *error = "no acknowledge from address " + std::to_string(address);
    return nullptr;
  }
  return &it->second;
}

bool Srf08BusEmulator::WriteRegister(uint8_t address, uint8_t reg, uint8_t value,
                                     std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  Sensor* sensor = Acknowledging(address, error);
  if (sensor == nullptr) return false;
  if (reg == kSrf08RangeRegister) {
    sensor->range_register = value;
  } else if (reg == kSrf08GainRegister) {
    sensor->gain = value;
  } else if (reg == kSrf08CommandRegister && value == kSrf08RangeCentimetres) {
    const double window_m = Srf08WindowMetres(sensor->range_register);
    const SteadyTime now = clock_.SteadyNow();
    sensor->busy_until = now + FromSeconds(std::min(0.065, 2 * window_m / 343.0));
    ++sensor->rangings;
    const float range_m = source_(address);
    sensor->echo_cm = std::isfinite(range_m) && range_m <= window_m
                          ? static_cast<int>(std::lround(std::max(0.01f, range_m) * 100))
                          : 0;
    int busy = 0;
    for (const auto& [a, s] : sensors_) busy += now < s.busy_until ? 1 : 0;
    max_simultaneous_ = std::max(max_simultaneous_, busy);
  } else {
    *error = "unsupported register write";
    return false;
  }
  return true;
}

bool Srf08BusEmulator::ReadRegisters(uint8_t address, uint8_t reg, uint8_t* out, size_t count,
                                     std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  Sensor* sensor = Acknowledging(address, error);
  if (sensor == nullptr) return false;
  for (size_t i = 0; i < count; ++i) {
    const size_t r = reg + i;
    if (r == kSrf08CommandRegister) {
      out[i] = 6;  // software revision
    } else if (r == kSrf08FirstEchoRegister) {
      out[i] = static_cast<uint8_t>(sensor->echo_cm >> 8);
    } else if (r == kSrf08FirstEchoRegister + 1) {
      out[i] = static_cast<uint8_t>(sensor->echo_cm & 0xFF);
    } else {
      out[i] = 0;  // light sensor, later echoes
    }
  }
  return true;
}

}  // namespace mostar::sonar
