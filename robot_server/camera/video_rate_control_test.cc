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
    if (now - last_report < milliseconds(450)) {
      EXPECT_EQ(target, reported);
    }
  }
  EXPECT_EQ(target, LinkRateOptions().min_bits_per_s);
  EXPECT_LT(target, 16e6 * VideoRateControlOptions().unreported_fraction);
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
