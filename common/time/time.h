// Typed time for mostar. No raw doubles for stamps anywhere in the code base.
//
// - `Time`: wall-clock instant, nanoseconds since the Unix epoch (UTC). Used for stamps that
//   travel on the wire (capture time of a frame, first beam of a scan, command creation).
// - `SteadyTime`: monotonic instant, for watchdogs, rates and timeouts; never sent to another
//   machine and never compared with `Time`.
// - `Duration`: signed nanoseconds.
// Clocks are injected (`Clock`), so watchdogs and rate logic are tested without sleeping.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace mostar {

using Duration = std::chrono::nanoseconds;
using Time = std::chrono::time_point<std::chrono::system_clock, std::chrono::nanoseconds>;
using SteadyTime = std::chrono::time_point<std::chrono::steady_clock, std::chrono::nanoseconds>;

constexpr double ToSeconds(Duration d) { return static_cast<double>(d.count()) * 1e-9; }
constexpr Duration FromSeconds(double seconds) {
  return Duration(static_cast<int64_t>(seconds * 1e9));
}
constexpr Duration FromMilliseconds(double ms) { return FromSeconds(ms * 1e-3); }

constexpr int64_t ToUnixNanos(Time t) { return t.time_since_epoch().count(); }
constexpr Time FromUnixNanos(int64_t ns) { return Time(Duration(ns)); }

// Splits into the ROS 2 builtin_interfaces/Time representation. Times before the epoch are
// clamped to the epoch (the wire format has an unsigned nanosecond field).
struct SecNanosec {
  int32_t sec = 0;
  uint32_t nanosec = 0;
};
SecNanosec ToSecNanosec(Time t);
Time FromSecNanosec(int32_t sec, uint32_t nanosec);

// "2026-11-21T23:59:59.123456789Z".
std::string ToIso8601(Time t);

// Source of the current time. Implementations are thread-safe.
class Clock {
 public:
  virtual ~Clock() = default;
  virtual Time Now() const = 0;
  virtual SteadyTime SteadyNow() const = 0;
};

// The process's real clocks.
class SystemClock final : public Clock {
 public:
  Time Now() const override;
  SteadyTime SteadyNow() const override;
  // A shared instance for wiring code.
  static const SystemClock& Instance();
};

}  // namespace mostar
