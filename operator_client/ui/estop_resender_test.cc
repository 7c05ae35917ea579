#include "operator_client/ui/estop_resender.h"

#include <gtest/gtest.h>

namespace mostar::ui {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

const SteadyTime kT0 = SteadyTime(seconds(100));

// Calls Due() every 50 ms from `from` for `span`; the number of samples it handed out.
int SendsOver(EstopResender* resender, SteadyTime from, Duration span) {
  int sends = 0;
  for (SteadyTime t = from; t < from + span; t += milliseconds(50)) {
    if (resender->Due(t)) ++sends;
  }
  return sends;
}

TEST(EstopResenderTest, EngageIsSentAtOnceAndResentUntilARobotReportShowsIt) {
  EstopResender resender;
  EXPECT_FALSE(resender.Due(kT0).has_value()) << "nothing asked";
  resender.Request(true, kT0);
  EXPECT_EQ(resender.Due(kT0), std::optional<bool>(true));
  EXPECT_FALSE(resender.Due(kT0 + milliseconds(100)).has_value());
  EXPECT_EQ(resender.Due(kT0 + milliseconds(250)), std::optional<bool>(true));
  // Reports that do not confirm: still released, or received before the request.
  resender.OnRobotReport({false, kT0 + milliseconds(300)});
  resender.OnRobotReport({true, kT0 - milliseconds(1)});
  EXPECT_EQ(resender.pending(), std::optional<bool>(true));
  EXPECT_EQ(resender.Due(kT0 + milliseconds(500)), std::optional<bool>(true));
  resender.OnRobotReport({true, kT0 + milliseconds(600)});
  EXPECT_FALSE(resender.pending().has_value());
  EXPECT_EQ(SendsOver(&resender, kT0 + milliseconds(600), seconds(5)), 0);
  EXPECT_EQ(resender.stats().sent, 3u);
  EXPECT_EQ(resender.stats().resent, 2u);
  EXPECT_EQ(resender.stats().confirmed, 1u);
}

TEST(EstopResenderTest, AnUnconfirmedEngagementIsNeverGivenUp) {
  EstopResender resender;
  resender.Request(true, kT0);
  // A robot that never answers (restarting, link down): 4 samples a second, for a minute.
  EXPECT_EQ(SendsOver(&resender, kT0, seconds(60)), 240);
  EXPECT_EQ(resender.pending(), std::optional<bool>(true));
}

TEST(EstopResenderTest, AnUnconfirmedReleaseStopsAfterItsTimeout) {
  EstopResenderOptions options;
  options.release_timeout = seconds(3);
  EstopResender resender(options);
  resender.Request(false, kT0);
  EXPECT_EQ(SendsOver(&resender, kT0, seconds(10)), 12);  // 0 .. 2.75 s
  EXPECT_FALSE(resender.pending().has_value());
  EXPECT_EQ(resender.stats().releases_unconfirmed, 1u);
  // A confirmed release is not counted as given up.
  resender.Request(false, kT0 + seconds(20));
  resender.OnRobotReport({false, kT0 + seconds(20) + milliseconds(400)});
  EXPECT_EQ(SendsOver(&resender, kT0 + seconds(21), seconds(5)), 0);
  EXPECT_EQ(resender.stats().releases_unconfirmed, 1u);
}

TEST(EstopResenderTest, ANewRequestReplacesThePendingOneAndIsSentAtOnce) {
  EstopResender resender;
  resender.Request(true, kT0);
  EXPECT_EQ(resender.Due(kT0), std::optional<bool>(true));
  resender.Request(false, kT0 + milliseconds(100));
  EXPECT_EQ(resender.Due(kT0 + milliseconds(100)), std::optional<bool>(false));
  // A report of the engagement no longer confirms anything.
  resender.OnRobotReport({true, kT0 + milliseconds(200)});
  EXPECT_EQ(resender.pending(), std::optional<bool>(false));
}

TEST(EstopResenderTest, InvalidOptionsAreNamed) {
  EstopResenderOptions options;
  std::string error;
  EXPECT_TRUE(options.IsValid(&error));
  options.resend_period = Duration::zero();
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("resend_period"), std::string::npos);
}

}  // namespace
}  // namespace mostar::ui
