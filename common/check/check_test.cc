#include "common/check/check.h"

#include <gtest/gtest.h>

namespace mostar {
namespace {

int CountingTrue(int* calls) {
  ++*calls;
  return 1;
}

TEST(CheckTest, PassingCheckEvaluatesItsConditionOnceAndNotItsMessage) {
  int condition_calls = 0;
  int message_calls = 0;
  MOSTAR_CHECK(CountingTrue(&condition_calls)) << CountingTrue(&message_calls);
  EXPECT_EQ(condition_calls, 1);
  EXPECT_EQ(message_calls, 0);
}

TEST(CheckDeathTest, FailingCheckAbortsWithConditionAndMessage) {
  const int width = -3;
  EXPECT_DEATH(MOSTAR_CHECK(width > 0) << "width " << width << " px",
               "check_test.cc:[0-9]+: check failed: width > 0: width -3 px");
}

TEST(CheckDeathTest, SurvivesNdebug) {
#ifndef NDEBUG
  GTEST_SKIP() << "this build keeps assert(); the check matters when NDEBUG is defined";
#endif
  EXPECT_DEATH(MOSTAR_CHECK(1 + 1 == 3), "check failed: 1 \\+ 1 == 3");
}

TEST(CheckTest, UsableAsAStatementInUnbracedIfElse) {
  bool reached_else = false;
  if (false)
    MOSTAR_CHECK(false) << "never evaluated";
  else
    reached_else = true;
  EXPECT_TRUE(reached_else);
}

}  // namespace
}  // namespace mostar
