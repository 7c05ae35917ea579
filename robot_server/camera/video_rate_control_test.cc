#include "robot_server/camera/video_rate_control.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace mostar::camera {
namespace {

using std::chrono::milliseconds;

const SteadyTime kT0 = SteadyTime{} + std::chrono::seconds(10);

// Frames 1..n written every 33 ms, `bytes` each; a viewer reports them `delay_ms` later plus
// `extra_ms` per frame (a growing queue when > 0).
VideoFeedback Report(const std::string& viewer, uint64_t first, uint64_t last, double delay_ms,
                     double extra_ms) {
  VideoFeedback feedback;
  feedback.sender_id = viewer;
  for (uint64_t n = first; n <= last; ++n) {
    const double ms = 33.0 * static_cast<double>(n) + delay_ms + extra_ms * static_cast<double>(n);
    feedback.arrivals.push_back({n, static_cast<int64_t>(ms * 1e6), 20'000});
  }
  return feedback;
}

TEST(VideoRateControlTest, WithoutReportsTheTargetStartsBelowWhereANewViewersControllerStarts) {
  VideoRateControl control;
  EXPECT_EQ(control.Target(8e6, kT0), 8e6 * VideoRateControlOptions().unreported_fraction);
  EXPECT_LT(VideoRateControlOptions().unreported_fraction, LinkRateOptions().start_fraction);
  EXPECT_EQ(control.Target(0, kT0), 0);
  EXPECT_FALSE(control.ShouldSkipFrame(kT0));
  EXPECT_EQ(control.Stats(kT0).viewers, 0);
}

TEST(VideoRateControlTest, TheSlowestViewerSetsTheTargetUntilItGoesQuiet) {
  VideoRateControl control;
  control.SetClassTarget(8e6);
  for (uint64_t n = 1; n <= 60; ++n) {
    control.OnFrameSent(n, kT0 + milliseconds(33 * n), 20'000);
  }
  const SteadyTime now = kT0 + milliseconds(33 * 60 + 60);
  control.OnFeedback(Report("fast", 1, 60, 50, 0), now);
  control.OnFeedback(Report("slow", 1, 60, 50, 8), now);  // 8 ms more queue per frame
  const VideoRateStats stats = control.Stats(now);
  EXPECT_EQ(stats.viewers, 2);
  EXPECT_GT(stats.queue_ms, 100);  // the slow one's
  const double target = control.Target(8e6, now);
  EXPECT_LT(target, 8e6 * 0.9);
  EXPECT_TRUE(control.ShouldSkipFrame(now));
  // Two seconds later without reports the slow viewer no longer counts: the start's quarter of
  // the class, but for silent_cap no more than the target of the viewers that went quiet.
  const double slow = target;
  EXPECT_EQ(control.Target(8e6, now + std::chrono::seconds(3)),
            std::min(slow, 8e6 * VideoRateControlOptions().unreported_fraction));
  EXPECT_FALSE(control.ShouldSkipFrame(now + std::chrono::seconds(3)));
  EXPECT_EQ(control.Target(8e6, now + std::chrono::seconds(11)),
            8e6 * VideoRateControlOptions().unreported_fraction);
}

// A viewer that stops reporting while frames keep going out gets none of them: its target halves
// (LinkRateController::OnSilence), and the quarter of the class that applies once it no longer
// counts is held below that.
TEST(VideoRateControlTest, FramesSentIntoASilenceLowerTheTarget) {
  VideoRateControl control;
  control.SetClassTarget(16e6);
  for (uint64_t n = 1; n <= 60; ++n) control.OnFrameSent(n, kT0 + milliseconds(33 * n), 20'000);
  const SteadyTime last_report = kT0 + milliseconds(33 * 60 + 60);
  control.OnFeedback(Report("pilot", 1, 60, 50, 0), last_report);
  const double reported = control.Target(16e6, last_report);
  double target = reported;
  for (uint64_t n = 61; n <= 150; ++n) {  // 3 s of frames, no report
    const SteadyTime now = kT0 + milliseconds(33 * n);
    target = control.Target(16e6, now);
    control.OnFrameSent(n, now, 20'000);
    // Twice the report's lag (60 ms) + the repair hold (50) + the margin (50) since frame 61 was
    // sent (27 ms before the report): no decrease for 193 ms.
    if (now - last_report < milliseconds(190)) {
      EXPECT_EQ(target, reported);
    } else if (now - last_report > milliseconds(200)) {
      EXPECT_LT(target, reported);
    }
  }
  EXPECT_EQ(target, LinkRateOptions().min_bits_per_s);
  EXPECT_LT(target, 16e6 * VideoRateControlOptions().unreported_fraction);
}

// A repair takes the repair period and a round trip: a deadline below that is named in the log.
TEST(VideoRateControlTest, ARepairDeadlineShorterThanARepairIsNamed) {
  for (const int deadline_ms : {0, 100, 250}) {
    VideoRateControlOptions options;
    options.link.repair_hold = milliseconds(50);
    options.repair_deadline = milliseconds(deadline_ms);
    VideoRateControl control(options);
    control.SetClassTarget(8e6);
    for (uint64_t n = 1; n <= 60; ++n) control.OnFrameSent(n, kT0 + milliseconds(33 * n), 20'000);
    const SteadyTime now = kT0 + milliseconds(33 * 60 + 120);  // a 120 ms report lag
    control.OnFeedback(Report("hub", 1, 60, 50, 0), now);
    EXPECT_NEAR(control.Stats(now).report_lag_ms, 120, 1);
    const std::string warning = control.RepairDeadlineWarning(now);
    if (deadline_ms == 100) {
      EXPECT_NE(warning.find("shorter than a repair takes on hub's link"), std::string::npos)
          << warning;
      EXPECT_NE(warning.find("above 220 ms"), std::string::npos) << warning;
    } else {
      EXPECT_EQ(warning, "") << "deadline " << deadline_ms << " ms";
    }
  }
}

// The automatic deadline: the repair period + 1.5 round trips + 50 ms, once a lag is measured;
// changed only when 20 % off and an interval (5 s by default) after the last change (each change
// is announced to every participant).
TEST(VideoRateControlTest, TheAutomaticRepairDeadlineFollowsTheSlowestViewersRoundTrip) {
  VideoRateControlOptions options;
  options.link.repair_hold = milliseconds(50);
  options.auto_repair_deadline = true;
  options.auto_deadline_interval = std::chrono::seconds(1);
  VideoRateControl control(options);
  control.SetClassTarget(8e6);
  EXPECT_FALSE(control.RepairDeadlineUpdate(kT0).has_value()) << "no lag measured yet";
  for (uint64_t n = 1; n <= 200; ++n) control.OnFrameSent(n, kT0 + milliseconds(33 * n), 20'000);
  SteadyTime now = kT0 + milliseconds(33 * 60 + 120);  // a 120 ms report lag
  control.OnFeedback(Report("pilot", 1, 60, 50, 0), now);
  std::optional<Duration> deadline = control.RepairDeadlineUpdate(now);
  ASSERT_TRUE(deadline.has_value());
  EXPECT_EQ(*deadline, milliseconds(50 + 180 + 50));
  EXPECT_NEAR(control.Stats(now).repair_deadline_ms, 280, 1e-6);
  EXPECT_FALSE(control.RepairDeadlineUpdate(now + milliseconds(10)).has_value()) << "unchanged";
  // A viewer across the Internet (400 ms report lag): far off, but within a second (this test's
  // interval) of the change.
  const SteadyTime changed = now;
  now = kT0 + milliseconds(33 * 66 + 400);
  control.OnFeedback(Report("observer", 61, 66, 50, 0), now);
  EXPECT_FALSE(control.RepairDeadlineUpdate(now).has_value());
  deadline = control.RepairDeadlineUpdate(changed + milliseconds(1100));
  ASSERT_TRUE(deadline.has_value()) << "a second later";
  EXPECT_EQ(*deadline, milliseconds(50 + 600 + 50));
  // Off by default.
  VideoRateControl fixed;
  fixed.OnFrameSent(1, kT0, 20'000);
  fixed.OnFeedback(Report("pilot", 1, 1, 50, 0), kT0 + milliseconds(120));
  EXPECT_FALSE(fixed.RepairDeadlineUpdate(kT0 + milliseconds(120)).has_value());
}

// Only frames sent measure the link: after an outage the frames that waited it out report
// seconds of queue, and without new frames nothing would correct that. Skipping therefore
// pauses for one frame every max_skip.
TEST(VideoRateControlTest, SkippingPausesForOneFrameEveryMaxSkip) {
  VideoRateControlOptions options;
  options.max_skip = milliseconds(100);
  VideoRateControl control(options);
  control.SetClassTarget(8e6);
  for (uint64_t n = 1; n <= 60; ++n) control.OnFrameSent(n, kT0 + milliseconds(33 * n), 20'000);
  const SteadyTime now = kT0 + milliseconds(33 * 60 + 60);
  control.OnFeedback(Report("slow", 1, 60, 50, 8), now);  // about 480 ms of queue
  EXPECT_TRUE(control.ShouldSkipFrame(now));
  EXPECT_TRUE(control.ShouldSkipFrame(now + milliseconds(50)));
  EXPECT_FALSE(control.ShouldSkipFrame(now + milliseconds(100))) << "one frame goes out";
  EXPECT_TRUE(control.ShouldSkipFrame(now + milliseconds(101))) << "then skipping resumes";
}

TEST(VideoRateControlTest, MalformedReportsAreRefusedAndTheTableIsBounded) {
  VideoRateControlOptions options;
  options.max_viewers = 2;
  VideoRateControl control(options);
  VideoFeedback bad = Report("x", 1, 5, 50, 0);
  std::swap(bad.arrivals[1], bad.arrivals[2]);
  control.OnFeedback(bad, kT0);
  EXPECT_EQ(control.Stats(kT0).reports_refused, 1u);
  for (int i = 0; i < 5; ++i) {
    control.OnFeedback(Report("viewer" + std::to_string(i), 1, 2, 50, 0), kT0 + milliseconds(i));
  }
  EXPECT_EQ(control.Stats(kT0 + milliseconds(10)).viewers, 2);
  EXPECT_EQ(control.Stats(kT0).reports, 5u);
}

}  // namespace
}  // namespace mostar::camera
