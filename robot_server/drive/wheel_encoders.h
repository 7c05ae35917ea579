// Wheel encoder readings and the device interface that provides them.
//
// Contract of a reading:
// - `left_count` / `right_count` are the raw values of free-running counters, of which only
//   the low `counter_bits` are significant (16 or 32 in practice). Counters wrap around in both
//   directions: forward past 2^bits - 1 to 0, backward past 0 to 2^bits - 1.
// - A count increases when its wheel turns so as to drive the robot forward (the driver or
//   the board flips the sign of a mirrored motor, never the consumer).
// - Between two readings each wheel must move less than half the counter range, otherwise
//   the wrap-around is ambiguous (at 16 bits and 500 ticks/turn that is 65 turns).
// - Ticks per wheel turn (500 pulses/turn on MORDUC by default, after any gearbox and any
//   quadrature multiplication) come from the configuration, not from the device.
#pragma once

#include <cstdint>
#include <string>

#include "common/time/time.h"

namespace mostar::drive {

struct EncoderReading {
  Time stamp;               // robot wall clock when the counters were sampled (for publishing)
  SteadyTime steady_stamp;  // robot monotonic clock, same instant (for rates)
  uint32_t left_count = 0;  // raw counter, low `counter_bits` significant
  uint32_t right_count = 0;
};

// Source of encoder readings. Implementations: the motor board (SerialDriveMotors), fakes in
// tests, the simulator. Non-copyable.
class WheelEncoders {
 public:
  WheelEncoders() = default;
  WheelEncoders(const WheelEncoders&) = delete;
  WheelEncoders& operator=(const WheelEncoders&) = delete;
  virtual ~WheelEncoders() = default;

  // The most recent reading. Returns false with a message when none is available or the
  // device has gone silent (then `reading` is untouched). Thread-safe; never blocks for long.
  virtual bool ReadEncoders(EncoderReading* reading, std::string* error) = 0;
  // Number of significant counter bits, in [8, 32].
  virtual int counter_bits() const = 0;
};

// Signed tick difference `current - previous` of a `bits`-wide wrapping counter, in
// (-2^(bits-1), 2^(bits-1)].
inline int64_t WrappedTickDelta(uint32_t previous, uint32_t current, int bits) {
  const uint64_t modulus = uint64_t{1} << bits;
  const uint64_t mask = modulus - 1;
  const uint64_t forward = (uint64_t{current} - uint64_t{previous}) & mask;
  return forward > modulus / 2 ? static_cast<int64_t>(forward) - static_cast<int64_t>(modulus)
                               : static_cast<int64_t>(forward);
}

}  // namespace mostar::drive
