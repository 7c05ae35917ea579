#include "common/process/stop_signals.h"

#include <gtest/gtest.h>

#include <csignal>

namespace mostar {
namespace {

// Each test runs in its own process (gtest_discover_tests): the flag starts clear.
TEST(StopSignalsTest, SigtermRequestsAStopInsteadOfEndingTheProcess) {
  InstallStopSignals();
  EXPECT_FALSE(StopRequested());
  ASSERT_EQ(std::raise(SIGTERM), 0);
  EXPECT_TRUE(StopRequested());
}

TEST(StopSignalsTest, SigintRequestsAStop) {
  InstallStopSignals();
  InstallStopSignals();  // idempotent
  ASSERT_EQ(std::raise(SIGINT), 0);
  EXPECT_TRUE(StopRequested());
}

TEST(StopSignalsTest, CodeCanRequestAStop) {
  EXPECT_FALSE(StopRequested());
  RequestStop();
  EXPECT_TRUE(StopRequested());
}

}  // namespace
}  // namespace mostar
