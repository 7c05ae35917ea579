#include "common/time/time.h"

#include <gtest/gtest.h>

#include "common/time/fake_clock.h"
#include "common/time/rate_meter.h"

namespace mostar {
namespace {

TEST(TimeTest, SecNanosecRoundTrip) {
  const Time t = FromUnixNanos(1'763'769'599'123'456'789);
  const SecNanosec s = ToSecNanosec(t);
  EXPECT_EQ(s.sec, 1'763'769'599);
  EXPECT_EQ(s.nanosec, 123'456'789u);
  EXPECT_EQ(FromSecNanosec(s.sec, s.nanosec), t);
}

TEST(TimeTest, NegativeTimesClampToEpoch) {
  const SecNanosec s = ToSecNanosec(FromUnixNanos(-5));
  EXPECT_EQ(s.sec, 0);
  EXPECT_EQ(s.nanosec, 0u);
}

TEST(TimeTest, Iso8601) {
  EXPECT_EQ(ToIso8601(FromUnixNanos(1'000'000'000'000'000'001)), "2001-09-09T01:46:40.000000001Z");
}

TEST(TimeTest, SecondsConversions) {
  EXPECT_DOUBLE_EQ(ToSeconds(FromSeconds(0.25)), 0.25);
  EXPECT_EQ(FromMilliseconds(250), std::chrono::milliseconds(250));
}

TEST(FakeClockTest, AdvancesBothClocks) {
  FakeClock clock;
  const Time t0 = clock.Now();
  const SteadyTime s0 = clock.SteadyNow();
  clock.Advance(std::chrono::milliseconds(40));
  EXPECT_EQ(clock.Now() - t0, std::chrono::milliseconds(40));
  EXPECT_EQ(clock.SteadyNow() - s0, std::chrono::milliseconds(40));
}

TEST(RateMeterTest, MeasuresTenHertz) {
  FakeClock clock;
  RateMeter meter(std::chrono::seconds(1));
  for (int i = 0; i < 30; ++i) {
    meter.Tick(clock.SteadyNow());
    clock.Advance(std::chrono::milliseconds(100));
  }
  EXPECT_NEAR(meter.RateHz(clock.SteadyNow() - std::chrono::milliseconds(100)), 10.0, 0.01);
  clock.Advance(std::chrono::seconds(5));
  EXPECT_EQ(meter.RateHz(clock.SteadyNow()), 0.0);
}

}  // namespace
}  // namespace mostar
