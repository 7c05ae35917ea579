#include "common/log/log.h"

#include <gtest/gtest.h>

namespace mostar {
namespace {

TEST(LogTest, ParsesLevels) {
  LogLevel level = LogLevel::kINFO;
  EXPECT_TRUE(ParseLogLevel("DEBUG", &level));
  EXPECT_EQ(level, LogLevel::kDEBUG);
  EXPECT_TRUE(ParseLogLevel("warn", &level));
  EXPECT_EQ(level, LogLevel::kWARNING);
  EXPECT_FALSE(ParseLogLevel("loud", &level));
  EXPECT_EQ(level, LogLevel::kWARNING);
}

TEST(LogTest, ThresholdFiltersLines) {
  const LogLevel saved = GetLogLevel();
  SetLogLevel(LogLevel::kERROR);
  testing::internal::CaptureStderr();
  MOSTAR_LOG(INFO) << "hidden";
  MOSTAR_LOG(ERROR) << "shown";
  const std::string out = testing::internal::GetCapturedStderr();
  SetLogLevel(saved);
  EXPECT_EQ(out.find("hidden"), std::string::npos);
  EXPECT_NE(out.find("shown"), std::string::npos);
  EXPECT_EQ(out[0], 'E');
}

TEST(LogTest, RateLimiterCountsSuppressed) {
  LogRateLimiter limiter(3600.0);
  uint64_t suppressed = 99;
  EXPECT_TRUE(limiter.Allow(&suppressed));
  EXPECT_EQ(suppressed, 0u);
  for (int i = 0; i < 5; ++i) EXPECT_FALSE(limiter.Allow(&suppressed));
}

TEST(LogTest, EverySecMacroLogsOncePerPeriod) {
  testing::internal::CaptureStderr();
  for (int i = 0; i < 10; ++i) MOSTAR_LOG_EVERY_SEC(WARNING, 3600) << "burst " << i;
  const std::string out = testing::internal::GetCapturedStderr();
  EXPECT_NE(out.find("burst 0"), std::string::npos);
  EXPECT_EQ(out.find("burst 1"), std::string::npos);
}

TEST(LogTest, MacroIsOneStatementInsideUnbracedIfWithoutElse) {
  testing::internal::CaptureStderr();
  const bool flag = true;
  if (flag) MOSTAR_LOG(ERROR) << "logged";
  if (!flag) MOSTAR_LOG_EVERY_SEC(ERROR, 1) << "never";
  const std::string out = testing::internal::GetCapturedStderr();
  EXPECT_NE(out.find("logged"), std::string::npos);
  EXPECT_EQ(out.find("never"), std::string::npos);
}

TEST(LogTest, DisabledLevelDoesNotEvaluateTheMessage) {
  const LogLevel saved = GetLogLevel();
  SetLogLevel(LogLevel::kERROR);
  int evaluated = 0;
  auto count = [&evaluated] { return ++evaluated; };
  MOSTAR_LOG(DEBUG) << count();
  SetLogLevel(saved);
  EXPECT_EQ(evaluated, 0);
}

TEST(LogTest, MacroIsOneStatementInsideUnbracedIf) {
  testing::internal::CaptureStderr();
  bool flag = false;
  if (flag)
    MOSTAR_LOG(ERROR) << "not this";
  else
    MOSTAR_LOG(ERROR) << "this one";
  const std::string out = testing::internal::GetCapturedStderr();
  EXPECT_EQ(out.find("not this"), std::string::npos);
  EXPECT_NE(out.find("this one"), std::string::npos);
}

}  // namespace
}  // namespace mostar
