// Operator -> robot messages: velocity commands, emergency stop, control requests.
#pragma once

#include <cstdint>
#include <string>

#include "common/time/time.h"

namespace mostar {

// Velocity in the robot base frame. Units: m/s forward, rad/s counter-clockwise.
struct VelocityCommand {
  Time stamp;             // sender's clock
  uint64_t sequence = 0;  // strictly increasing per sender
  std::string sender_id;
  double linear_mps = 0;
  double angular_radps = 0;
  bool enable = false;  // deadman held
};

struct EmergencyStop {
  Time stamp;
  std::string sender_id;
  bool engage = true;
};

struct ControlRequest {
  Time stamp;
  std::string sender_id;
  int32_t strength = 0;
  bool take = true;  // false: release
};

// Who drives. An empty holder means nobody.
struct ControlLease {
  Time stamp;
  std::string holder_id;
  int32_t holder_strength = 0;
  Time since;
  uint64_t lease_sequence = 0;
};

// NTP-style probe: t0 client send, t1 robot receive, t2 robot send. In a ping, t3 is the
// client's receive time of the pong to ping `sequence - 1` (epoch when none came back), so the
// robot can complete that exchange and estimate the client's clock offset as well.
struct ClockProbe {
  std::string sender_id;
  uint64_t sequence = 0;
  Time t0, t1, t2, t3;
};

}  // namespace mostar
