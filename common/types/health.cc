#include "common/types/health.h"

namespace mostar {

const char* DeviceStateName(DeviceState state) {
  switch (state) {
    case DeviceState::kOk:
      return "OK";
    case DeviceState::kWarn:
      return "WARN";
    case DeviceState::kError:
      return "ERROR";
    case DeviceState::kOff:
      return "OFF";
  }
  return "?";
}

const char* WatchdogStateName(WatchdogState state) {
  switch (state) {
    case WatchdogState::kIdle:
      return "IDLE";
    case WatchdogState::kDriving:
      return "DRIVING";
    case WatchdogState::kStopping:
      return "STOPPING";
    case WatchdogState::kWaitRearm:
      return "WAIT_REARM";
    case WatchdogState::kEstop:
      return "ESTOP";
  }
  return "?";
}

}  // namespace mostar
