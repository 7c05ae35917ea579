// Logging with levels and per-call-site rate limiting, to stderr.
//
//   MOSTAR_LOG(INFO) << "opened " << port;
//   MOSTAR_LOG_EVERY_SEC(WARNING, 5) << "CRC error";   // at most once per 5 s per call site;
//                                                       // the next line says how many were skipped
// Levels: DEBUG < INFO < WARNING < ERROR. The threshold comes from SetLogLevel() or the
// MOSTAR_LOG_LEVEL environment variable (debug|info|warning|error). Thread-safe.
#pragma once

#include <atomic>
#include <cstdint>
#include <sstream>
#include <string>

namespace mostar {

enum class LogLevel { kDEBUG = 0, kINFO = 1, kWARNING = 2, kERROR = 3 };

void SetLogLevel(LogLevel level);
LogLevel GetLogLevel();
// Parses "debug", "info", "warning"/"warn", "error" (case-insensitive).
bool ParseLogLevel(const std::string& text, LogLevel* level);
inline bool LogEnabled(LogLevel level) { return level >= GetLogLevel(); }

// One log line; written atomically when destroyed.
class LogMessage {
 public:
  LogMessage(LogLevel level, const char* file, int line, uint64_t suppressed = 0);
  ~LogMessage();
  LogMessage(const LogMessage&) = delete;
  LogMessage& operator=(const LogMessage&) = delete;
  std::ostream& stream() { return stream_; }

 private:
  LogLevel level_;
  uint64_t suppressed_;
  std::ostringstream stream_;
};

// Lets through one event per period (seconds, monotonic); counts the rest.
class LogRateLimiter {
 public:
  explicit LogRateLimiter(double period_s) : period_ns_(static_cast<int64_t>(period_s * 1e9)) {}
  static constexpr uint64_t kDenied = ~uint64_t{0};
  // True when this event should be logged; `suppressed` gets the number skipped since the last.
  bool Allow(uint64_t* suppressed);
  // The number skipped since the last allowed event, or kDenied when this one is not allowed.
  uint64_t TryAcquire() {
    uint64_t suppressed = 0;
    return Allow(&suppressed) ? suppressed : kDenied;
  }

 private:
  const int64_t period_ns_;
  std::atomic<int64_t> next_ns_{0};
  std::atomic<uint64_t> skipped_{0};
};

}  // namespace mostar

// Each macro is a single `for` statement that runs its body at most once, so it is safe inside
// an unbraced if/else and evaluates the streamed expressions only when the line is logged.
#define MOSTAR_LOG(level)                                                          \
  for (bool mostar_log_once_ = ::mostar::LogEnabled(::mostar::LogLevel::k##level); \
       mostar_log_once_; mostar_log_once_ = false)                                 \
  ::mostar::LogMessage(::mostar::LogLevel::k##level, __FILE__, __LINE__).stream()

#define MOSTAR_LOG_EVERY_SEC(level, seconds)                                                       \
  for (uint64_t mostar_log_suppressed_ = ::mostar::LogEnabled(::mostar::LogLevel::k##level)        \
                                             ? ([]() -> ::mostar::LogRateLimiter& {                \
                                                 static ::mostar::LogRateLimiter limiter(seconds); \
                                                 return limiter;                                   \
                                               }())                                                \
                                                   .TryAcquire()                                   \
                                             : ::mostar::LogRateLimiter::kDenied;                  \
       mostar_log_suppressed_ != ::mostar::LogRateLimiter::kDenied;                                \
       mostar_log_suppressed_ = ::mostar::LogRateLimiter::kDenied)                                 \
  ::mostar::LogMessage(::mostar::LogLevel::k##level, __FILE__, __LINE__, mostar_log_suppressed_)   \
      .stream()
