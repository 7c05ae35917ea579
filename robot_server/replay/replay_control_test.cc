#include "robot_server/replay/replay_control.h"

#include <gtest/gtest.h>

#include "common/record/test_records.h"
#include "common/time/fake_clock.h"
#include "robot_server/node/fake_robot_link.h"
#include "robot_server/replay/replay_publisher.h"

namespace mostar::replay {
namespace {

using Kind = ReplayControl::Kind;
using std::chrono::milliseconds;

ReplayControl Parsed(const std::string& line) {
  ReplayControl control;
  std::string error;
  EXPECT_TRUE(ParseReplayControl(line, &control, &error)) << line << ": " << error;
  return control;
}

std::string Refusal(const std::string& line) {
  ReplayControl control;
  std::string error;
  EXPECT_FALSE(ParseReplayControl(line, &control, &error)) << line;
  return error;
}

TEST(ReplayControlTest, ParsesEveryCommand) {
  EXPECT_EQ(Parsed("p").kind, Kind::kTogglePause);
  EXPECT_EQ(Parsed("q").kind, Kind::kQuit);
  EXPECT_EQ(Parsed("  s  ").kind, Kind::kStep);
  EXPECT_EQ(Parsed("s").steps, 1);
  EXPECT_EQ(Parsed("s 25").steps, 25);
  EXPECT_EQ(Parsed("r 0.25").kind, Kind::kSetRate);
  EXPECT_DOUBLE_EQ(Parsed("r 0.25").rate, 0.25);
  EXPECT_DOUBLE_EQ(Parsed("r 4").rate, 4.0);
}

TEST(ReplayControlTest, BlankLinesAreNothing) {
  EXPECT_EQ(Parsed("").kind, Kind::kNone);
  EXPECT_EQ(Parsed(" \t ").kind, Kind::kNone);
}

TEST(ReplayControlTest, RefusesMalformedLinesWithTheLineAndTheUsage) {
  const std::string unknown = Refusal("x");
  EXPECT_NE(unknown.find("'x'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("unknown command"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("p pause/resume, s [N] step, r RATE, q quit"), std::string::npos);
  EXPECT_NE(Refusal("r").find("positive rate"), std::string::npos);
  EXPECT_NE(Refusal("r 0").find("positive rate"), std::string::npos);
  EXPECT_NE(Refusal("r -2").find("positive rate"), std::string::npos);
  EXPECT_NE(Refusal("r fast").find("positive rate"), std::string::npos);
  EXPECT_NE(Refusal("r 2x").find("positive rate"), std::string::npos);
  EXPECT_NE(Refusal("r nan").find("positive rate"), std::string::npos);
  EXPECT_NE(Refusal("s 0").find("whole number"), std::string::npos);
  EXPECT_NE(Refusal("s -3").find("whole number"), std::string::npos);
  EXPECT_NE(Refusal("s 1.5").find("whole number"), std::string::npos);
  EXPECT_NE(Refusal("s 99999999999999999999").find("whole number"), std::string::npos);
  EXPECT_NE(Refusal("p now").find("takes no argument"), std::string::npos);
  EXPECT_NE(Refusal("s 1 2").find("too many arguments"), std::string::npos);
}

// Odometry records at 0, 100, ..., (n-1)*100 ms.
std::vector<record::RecordedMessage> Odometries(int n) {
  std::vector<record::RecordedMessage> out;
  for (int i = 0; i < n; ++i) {
    const Time t = record::testing::T0() + milliseconds(100 * i);
    out.push_back(record::testing::At(t, record::testing::MakeOdometry(t)));
  }
  return out;
}

TEST(ReplayControlTest, AppliesToThePlayer) {
  FakeClock clock;
  record::testing::VectorRecordStream stream(Odometries(10));
  record::ReplayPlayer player(&stream, clock, {});
  EXPECT_TRUE(ApplyReplayControl(Parsed("p"), &player));
  EXPECT_TRUE(player.paused());
  EXPECT_TRUE(ApplyReplayControl(Parsed("s 3"), &player));
  EXPECT_EQ(player.PollDue().size(), 3u);
  EXPECT_TRUE(ApplyReplayControl(Parsed("p"), &player));
  EXPECT_FALSE(player.paused());
  EXPECT_TRUE(ApplyReplayControl(Parsed("r 2"), &player));
  clock.Advance(milliseconds(100));  // 200 ms of recording at 2x
  EXPECT_EQ(player.PollDue().size(), 2u);
  EXPECT_TRUE(ApplyReplayControl(Parsed(""), &player));
  EXPECT_FALSE(ApplyReplayControl(Parsed("q"), &player)) << "q asks to stop";
}

TEST(ReplayPublisherTest, PublishesEachRecordKindWhenDueAndActsOnNoCommand) {
  FakeClock clock;
  record::testing::VectorRecordStream stream(
      record::testing::OneOfEach(record::testing::T0(), milliseconds(10)));
  record::ReplayPlayer player(&stream, clock, {});
  server::FakeRobotLink link;
  ReplayPublisher publisher(&player, &link, nullptr);
  EXPECT_EQ(publisher.PublishDue(), 1u) << "the first record is due at once";
  ASSERT_EQ(link.images.size(), 1u);
  EXPECT_EQ(link.images[0].first, Eye::kLeft);
  clock.Advance(milliseconds(100));
  EXPECT_EQ(publisher.PublishDue(), 10u);
  EXPECT_EQ(publisher.published(), 11u);
  ASSERT_EQ(link.images.size(), 2u);
  EXPECT_EQ(link.images[1].first, Eye::kRight);
  ASSERT_EQ(link.scans.size(), 1u);
  EXPECT_EQ(link.scans[0].sequence, 9u);
  EXPECT_EQ(link.odometries.size(), 1u);
  EXPECT_EQ(link.leases.size(), 1u);
  EXPECT_EQ(link.healths.size(), 1u);
  ASSERT_EQ(link.sonars.size(), 1u);
  EXPECT_EQ(link.sonars[0].cycle, 41u);
  EXPECT_EQ(link.sonars[0].ranges.size(), 3u);
  ASSERT_EQ(link.bumpers.size(), 1u);
  EXPECT_EQ(link.bumpers[0].latched, 1u);
  EXPECT_TRUE(player.finished());
}

}  // namespace
}  // namespace mostar::replay
