#include "common/log/log.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "common/time/time.h"

namespace mostar {
namespace {

LogLevel InitialLevel() {
  LogLevel level = LogLevel::kINFO;
  if (const char* env = std::getenv("MOSTAR_LOG_LEVEL")) ParseLogLevel(env, &level);
  return level;
}

std::atomic<int>& LevelStorage() {
  static std::atomic<int> level{static_cast<int>(InitialLevel())};
  return level;
}

char LevelLetter(LogLevel level) {
  switch (level) {
    case LogLevel::kDEBUG:
      return 'D';
    case LogLevel::kINFO:
      return 'I';
    case LogLevel::kWARNING:
      return 'W';
    case LogLevel::kERROR:
      return 'E';
  }
  return '?';
}

std::mutex& OutputMutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace

void SetLogLevel(LogLevel level) { LevelStorage() = static_cast<int>(level); }
LogLevel GetLogLevel() { return static_cast<LogLevel>(LevelStorage().load()); }

bool ParseLogLevel(const std::string& text, LogLevel* level) {
  std::string t = text;
  std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return std::tolower(c); });
  if (t == "debug") {
    *level = LogLevel::kDEBUG;
  } else if (t == "info") {
    *level = LogLevel::kINFO;
  } else if (t == "warning" || t == "warn") {
    *level = LogLevel::kWARNING;
  } else if (t == "error") {
    *level = LogLevel::kERROR;
  } else {
    return false;
  }
  return true;
}

LogMessage::LogMessage(LogLevel level, const char* file, int line, uint64_t suppressed)
    : level_(level), suppressed_(suppressed) {
  const char* base = std::strrchr(file, '/');
  stream_ << LevelLetter(level) << ' ' << ToIso8601(SystemClock::Instance().Now()) << ' '
          << (base ? base + 1 : file) << ':' << line << "] ";
}

LogMessage::~LogMessage() {
  if (suppressed_ > 0) stream_ << " (" << suppressed_ << " similar suppressed)";
  stream_ << '\n';
  const std::string text = stream_.str();
  std::lock_guard<std::mutex> lock(OutputMutex());
  std::fwrite(text.data(), 1, text.size(), stderr);
  if (level_ >= LogLevel::kWARNING) std::fflush(stderr);
}

bool LogRateLimiter::Allow(uint64_t* suppressed) {
  const int64_t now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                          std::chrono::steady_clock::now().time_since_epoch())
                          .count();
  int64_t next = next_ns_.load();
  if (now >= next && next_ns_.compare_exchange_strong(next, now + period_ns_)) {
    *suppressed = skipped_.exchange(0);
    return true;
  }
  ++skipped_;
  return false;
}

}  // namespace mostar
