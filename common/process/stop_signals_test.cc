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

TEST(StopSignalsTest, ARequestSignalIsTakenOnceAndStopsNothing) {
  ASSERT_TRUE(InstallSignalRequest(SIGUSR2));
  EXPECT_FALSE(TakeSignalRequest(SIGUSR2));
  ASSERT_EQ(std::raise(SIGUSR2), 0);
  ASSERT_EQ(std::raise(SIGUSR2), 0);  // two before a take are one request
  EXPECT_TRUE(TakeSignalRequest(SIGUSR2));
  EXPECT_FALSE(TakeSignalRequest(SIGUSR2));
  EXPECT_FALSE(StopRequested());
}

TEST(StopSignalsTest, StopSignalsAndBadNumbersAreNoRequestSignals) {
  EXPECT_FALSE(InstallSignalRequest(SIGTERM));
  EXPECT_FALSE(InstallSignalRequest(SIGINT));
  EXPECT_FALSE(InstallSignalRequest(0));
  EXPECT_FALSE(InstallSignalRequest(65));
  EXPECT_FALSE(TakeSignalRequest(-1));
}

}  // namespace
}  // namespace mostar
