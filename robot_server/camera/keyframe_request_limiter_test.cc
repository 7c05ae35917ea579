#include "robot_server/camera/keyframe_request_limiter.h"

#include <gtest/gtest.h>

namespace mostar::camera {
namespace {

using std::chrono::milliseconds;

TEST(KeyframeRequestLimiterTest, NoRequestNoIdr) {
  KeyframeRequestLimiter limiter;
  EXPECT_FALSE(limiter.ShouldSendIdr(SteadyTime{} + milliseconds(1000)));
}

TEST(KeyframeRequestLimiterTest, FirstRequestAnsweredAtOnce) {
  KeyframeRequestLimiter limiter;
  const SteadyTime t0 = SteadyTime{} + milliseconds(1000);
  limiter.Request(t0);
  EXPECT_TRUE(limiter.ShouldSendIdr(t0));
  limiter.OnIdrSent(t0);
  EXPECT_FALSE(limiter.pending());
  EXPECT_FALSE(limiter.ShouldSendIdr(t0 + milliseconds(33)));
  EXPECT_EQ(limiter.counters().answered, 1u);
}

TEST(KeyframeRequestLimiterTest, RequestsInsideTheIntervalAreDeferredNotLost) {
  KeyframeRequestLimiter limiter(milliseconds(300));
  const SteadyTime t0 = SteadyTime{} + milliseconds(1000);
  limiter.Request(t0);
  ASSERT_TRUE(limiter.ShouldSendIdr(t0));
  limiter.OnIdrSent(t0);
  // A storm of requests right after the IDR: one more IDR, at the end of the interval.
  int idrs = 0;
  for (int ms = 10; ms <= 1000; ms += 10) {
    const SteadyTime now = t0 + milliseconds(ms);
    if (ms <= 200) limiter.Request(now);
    if (limiter.ShouldSendIdr(now)) {
      EXPECT_GE(ms, 300);
      limiter.OnIdrSent(now);
      ++idrs;
    }
  }
  EXPECT_EQ(idrs, 1);
  EXPECT_EQ(limiter.counters().requests, 21u);
  EXPECT_EQ(limiter.counters().deferred, 20u);
  EXPECT_EQ(limiter.counters().answered, 2u);
}

TEST(KeyframeRequestLimiterTest, AnIdrSentForAnotherReasonAnswersPendingRequests) {
  KeyframeRequestLimiter limiter;
  const SteadyTime t0 = SteadyTime{} + milliseconds(1000);
  limiter.Request(t0);
  limiter.OnIdrSent(t0);  // e.g. the encoder restarted
  EXPECT_FALSE(limiter.pending());
  EXPECT_FALSE(limiter.ShouldSendIdr(t0 + milliseconds(500)));
  EXPECT_EQ(limiter.counters().answered, 0u);
}

}  // namespace
}  // namespace mostar::camera
