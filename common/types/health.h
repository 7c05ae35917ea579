// Robot health as published periodically by robot_server.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "common/time/time.h"

namespace mostar {

enum class DeviceState : uint8_t { kOk = 0, kWarn = 1, kError = 2, kOff = 3 };
const char* DeviceStateName(DeviceState state);

enum class WatchdogState : uint8_t {
  kIdle = 0,       // no pilot command yet, or released
  kDriving = 1,    // fresh commands arrive
  kStopping = 2,   // deadman expired: ramping to zero
  kWaitRearm = 3,  // stopped after a link loss; the pilot must re-arm (deadman up, then down)
  kEstop = 4,      // emergency stop engaged
};
const char* WatchdogStateName(WatchdogState state);

struct DeviceHealth {
  std::string name;
  DeviceState state = DeviceState::kOk;
  std::string message;
  float rate_hz = 0;
  std::vector<std::pair<std::string, uint64_t>> counters;
};

struct RobotHealth {
  Time stamp;
  std::string robot_id;
  std::vector<DeviceHealth> devices;
  std::string lease_holder;
  WatchdogState watchdog_state = WatchdogState::kIdle;
  float last_command_age_s = -1;
  uint64_t last_command_sequence = 0;  // of the last accepted command
  bool estop_engaged = false;
};

}  // namespace mostar
