#include "common/time/time.h"

#include <ctime>
#include <iomanip>
#include <sstream>

namespace mostar {

SecNanosec ToSecNanosec(Time t) {
  const int64_t ns = ToUnixNanos(t);
  if (ns <= 0) return {};
  SecNanosec out;
  out.sec = static_cast<int32_t>(ns / 1000000000);
  out.nanosec = static_cast<uint32_t>(ns % 1000000000);
  return out;
}

Time FromSecNanosec(int32_t sec, uint32_t nanosec) {
  return FromUnixNanos(static_cast<int64_t>(sec) * 1000000000 + static_cast<int64_t>(nanosec));
}

std::string ToIso8601(Time t) {
  const int64_t ns = ToUnixNanos(t);
  int64_t sec = ns / 1000000000;
  int64_t frac = ns % 1000000000;
  if (frac < 0) {
    frac += 1000000000;
    --sec;
  }
  const std::time_t tt = static_cast<std::time_t>(sec);
  std::tm tm{};
  gmtime_r(&tt, &tm);
  std::ostringstream out;
  out << std::put_time(&tm, "%Y-%m-%dT%H:%M:%S") << '.' << std::setw(9) << std::setfill('0') << frac
      << 'Z';
  return out.str();
}

Time SystemClock::Now() const {
  return std::chrono::time_point_cast<Duration>(std::chrono::system_clock::now());
}

SteadyTime SystemClock::SteadyNow() const {
  return std::chrono::time_point_cast<Duration>(std::chrono::steady_clock::now());
}

const SystemClock& SystemClock::Instance() {
  static const SystemClock clock;
  return clock;
}

}  // namespace mostar
