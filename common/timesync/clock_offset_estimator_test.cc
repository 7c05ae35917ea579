#include "common/timesync/clock_offset_estimator.h"

#include <gtest/gtest.h>

#include <random>

namespace mostar::timesync {
namespace {

using std::chrono::milliseconds;

const Time kStart = FromUnixNanos(1'700'000'000'000'000'000);

// One exchange starting at requester time `t0`; the responder clock runs `offset` ahead.
ClockSample MakeSample(Time t0, Duration offset, Duration up_delay, Duration down_delay,
                       Duration processing = milliseconds(1)) {
  ClockSample s;
  s.t0 = t0;
  s.t1 = t0 + up_delay + offset;
  s.t2 = s.t1 + processing;
  s.t3 = s.t2 - offset + down_delay;
  return s;
}

TEST(ClockOffsetEstimatorTest, SymmetricDelaysGiveExactOffset) {
  ClockOffsetEstimator estimator;
  const Duration offset = milliseconds(1234);
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(estimator.AddSample(
        MakeSample(kStart + milliseconds(100 * i), offset, milliseconds(20), milliseconds(20))));
  }
  const ClockOffsetEstimate e = estimator.Estimate();
  ASSERT_TRUE(e.known);
  EXPECT_EQ(e.responder_minus_requester, offset);
  EXPECT_EQ(e.round_trip, milliseconds(40));
  EXPECT_EQ(e.uncertainty, milliseconds(20));
  EXPECT_EQ(e.ToResponderTime(kStart), kStart + offset);
  EXPECT_EQ(e.ToRequesterTime(kStart + offset), kStart);
}

TEST(ClockOffsetEstimatorTest, NotKnownBeforeMinSamples) {
  ClockOffsetEstimator estimator;
  EXPECT_FALSE(estimator.Estimate().known);
  estimator.AddSample(MakeSample(kStart, milliseconds(5), milliseconds(3), milliseconds(3)));
  estimator.AddSample(MakeSample(kStart, milliseconds(5), milliseconds(3), milliseconds(3)));
  EXPECT_FALSE(estimator.Estimate().known);
  EXPECT_EQ(estimator.Estimate().samples, 2u);
  estimator.AddSample(MakeSample(kStart, milliseconds(5), milliseconds(3), milliseconds(3)));
  EXPECT_TRUE(estimator.Estimate().known);
}

TEST(ClockOffsetEstimatorTest, NegativeOffsetWhenResponderIsBehind) {
  ClockOffsetEstimator estimator;
  for (int i = 0; i < 3; ++i) {
    estimator.AddSample(MakeSample(kStart, -milliseconds(5000), milliseconds(8), milliseconds(8)));
  }
  EXPECT_EQ(estimator.Estimate().responder_minus_requester, -milliseconds(5000));
}

TEST(ClockOffsetEstimatorTest, AsymmetricDelayErrorStaysWithinUncertainty) {
  ClockOffsetEstimator estimator;
  const Duration offset = -milliseconds(777);
  for (int i = 0; i < 5; ++i) {
    estimator.AddSample(
        MakeSample(kStart + milliseconds(i), offset, milliseconds(5), milliseconds(45)));
  }
  const ClockOffsetEstimate e = estimator.Estimate();
  const Duration error = e.responder_minus_requester - offset;
  EXPECT_EQ(error, -milliseconds(20));  // (up - down) / 2
  EXPECT_LE(std::chrono::abs(error), e.uncertainty);
}

TEST(ClockOffsetEstimatorTest, MinimumRoundTripFilterRejectsJitter) {
  // Jittery queueing delays on both legs; a few exchanges see a quiet network. The estimate
  // must be as good as the best exchange, far better than the mean.
  std::mt19937 rng(42);
  std::exponential_distribution<double> queueing_ms(1.0 / 30.0);
  ClockOffsetEstimatorOptions options;
  options.window_size = 32;
  ClockOffsetEstimator estimator(options);
  const Duration offset = milliseconds(250);
  for (int i = 0; i < 32; ++i) {
    const Duration up = milliseconds(10) + FromMilliseconds(queueing_ms(rng));
    const Duration down = milliseconds(10) + FromMilliseconds(queueing_ms(rng));
    estimator.AddSample(MakeSample(kStart + milliseconds(200 * i), offset, up, down));
  }
  // One quiet exchange.
  estimator.AddSample(
      MakeSample(kStart + milliseconds(7000), offset, milliseconds(10), milliseconds(11)));
  const ClockOffsetEstimate e = estimator.Estimate();
  ASSERT_TRUE(e.known);
  EXPECT_LE(std::chrono::abs(e.responder_minus_requester - offset), FromMilliseconds(0.5));
  EXPECT_EQ(e.round_trip, milliseconds(21));
}

TEST(ClockOffsetEstimatorTest, PropertyTrueOffsetAlwaysWithinUncertainty) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> delay_ms(0.5, 200.0);
  std::uniform_real_distribution<double> offset_s(-1000.0, 1000.0);
  for (int trial = 0; trial < 200; ++trial) {
    ClockOffsetEstimatorOptions options;
    options.window_size = 8;
    ClockOffsetEstimator estimator(options);
    const Duration offset = FromSeconds(offset_s(rng));
    for (int i = 0; i < 10; ++i) {
      estimator.AddSample(MakeSample(kStart + milliseconds(100 * i), offset,
                                     FromMilliseconds(delay_ms(rng)),
                                     FromMilliseconds(delay_ms(rng))));
    }
    const ClockOffsetEstimate e = estimator.Estimate();
    ASSERT_TRUE(e.known);
    EXPECT_LE(std::chrono::abs(e.responder_minus_requester - offset), e.uncertainty)
        << "trial " << trial;
  }
}

TEST(ClockOffsetEstimatorTest, RejectsInconsistentAndSlowSamples) {
  ClockOffsetEstimator estimator;
  ClockSample backwards = MakeSample(kStart, milliseconds(0), milliseconds(5), milliseconds(5));
  backwards.t3 = backwards.t0 - milliseconds(1);
  EXPECT_FALSE(estimator.AddSample(backwards));
  ClockSample responder_backwards =
      MakeSample(kStart, milliseconds(0), milliseconds(5), milliseconds(5));
  responder_backwards.t2 = responder_backwards.t1 - milliseconds(1);
  EXPECT_FALSE(estimator.AddSample(responder_backwards));
  // Responder claims to have held the probe longer than the whole round trip.
  ClockSample negative_rtt = MakeSample(kStart, milliseconds(0), milliseconds(5), milliseconds(5));
  negative_rtt.t2 = negative_rtt.t1 + milliseconds(50);
  EXPECT_FALSE(estimator.AddSample(negative_rtt));
  EXPECT_FALSE(estimator.AddSample(
      MakeSample(kStart, milliseconds(0), milliseconds(900), milliseconds(900))));
  EXPECT_EQ(estimator.rejected(), 4u);
  EXPECT_EQ(estimator.accepted(), 0u);
  EXPECT_EQ(estimator.Estimate().samples, 0u);
}

TEST(ClockOffsetEstimatorTest, FollowsAClockStepOnceOldSamplesLeaveTheWindow) {
  ClockOffsetEstimatorOptions options;
  options.window_size = 4;
  options.min_samples = 2;
  ClockOffsetEstimator estimator(options);
  for (int i = 0; i < 4; ++i) {
    // Very good samples with the old offset.
    estimator.AddSample(MakeSample(kStart + milliseconds(100 * i), milliseconds(100),
                                   milliseconds(1), milliseconds(1)));
  }
  for (int i = 0; i < 4; ++i) {
    estimator.AddSample(MakeSample(kStart + milliseconds(1000 + 100 * i), milliseconds(900),
                                   milliseconds(10), milliseconds(10)));
  }
  EXPECT_EQ(estimator.Estimate().responder_minus_requester, milliseconds(900));
}

TEST(ClockOffsetEstimatorTest, OldSamplesExpireByAge) {
  ClockOffsetEstimatorOptions options;
  options.min_samples = 1;
  options.max_sample_age = std::chrono::seconds(10);
  ClockOffsetEstimator estimator(options);
  estimator.AddSample(MakeSample(kStart, milliseconds(100), milliseconds(1), milliseconds(1)));
  estimator.AddSample(MakeSample(kStart + std::chrono::seconds(11), milliseconds(300),
                                 milliseconds(20), milliseconds(20)));
  const ClockOffsetEstimate e = estimator.Estimate();
  EXPECT_EQ(e.samples, 1u);
  EXPECT_EQ(e.responder_minus_requester, milliseconds(300));
}

TEST(ClockOffsetEstimatorTest, OptionsValidationNamesTheConstraint) {
  ClockOffsetEstimatorOptions options;
  std::string error;
  EXPECT_TRUE(options.IsValid(&error));
  options.min_samples = 100;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("min_samples"), std::string::npos);
}

}  // namespace
}  // namespace mostar::timesync
