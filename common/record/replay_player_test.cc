#include "common/record/replay_player.h"

#include <gtest/gtest.h>

#include "common/record/recording_reader.h"
#include "common/record/recording_writer.h"
#include "common/record/replay_sources.h"
#include "common/record/test_records.h"
#include "common/time/fake_clock.h"

namespace mostar::record {
namespace {

using std::chrono::milliseconds;
using testing::T0;
using testing::VectorRecordStream;

// Odometry records at the given log times (ms after T0).
std::vector<RecordedMessage> AtMs(const std::vector<int>& times_ms) {
  std::vector<RecordedMessage> out;
  for (int ms : times_ms) {
    const Time t = T0() + milliseconds(ms);
    out.push_back(testing::At(t, testing::MakeOdometry(t)));
  }
  return out;
}

std::vector<int> DueMs(ReplayPlayer* player) {
  std::vector<int> out;
  for (const RecordedMessage& m : player->PollDue()) {
    out.push_back(
        static_cast<int>(std::chrono::duration_cast<milliseconds>(m.log_time - T0()).count()));
  }
  return out;
}

TEST(ReplayClockTest, MapsRecordingTimeAtTheRateAndFreezesWhenPaused) {
  FakeClock clock;
  ReplayClock replay(clock, 2.0);
  replay.JumpTo(T0());
  const SteadyTime start = clock.SteadyNow();
  EXPECT_EQ(replay.DueTime(T0() + milliseconds(1000)), start + milliseconds(500));
  clock.Advance(milliseconds(100));
  EXPECT_EQ(replay.RecordingNow(), T0() + milliseconds(200));
  replay.Pause();
  clock.Advance(milliseconds(1000));
  EXPECT_EQ(replay.RecordingNow(), T0() + milliseconds(200));
  EXPECT_EQ(replay.DueTime(T0() + milliseconds(300)), SteadyTime::max());
  replay.Resume();
  replay.SetRate(0.5);
  clock.Advance(milliseconds(200));
  EXPECT_EQ(replay.RecordingNow(), T0() + milliseconds(300));
  replay.SetRate(-1);  // ignored
  EXPECT_EQ(replay.rate(), 0.5);
}

TEST(ReplayPlayerTest, DeliversAtRealSpeed) {
  FakeClock clock;
  VectorRecordStream stream(AtMs({0, 100, 250, 1000}));
  ReplayPlayer player(&stream, clock, {});
  EXPECT_EQ(DueMs(&player), std::vector<int>({0}));
  EXPECT_EQ(player.NextDueTime(), clock.SteadyNow() + milliseconds(100));
  clock.Advance(milliseconds(99));
  EXPECT_TRUE(DueMs(&player).empty());
  clock.Advance(milliseconds(1));
  EXPECT_EQ(DueMs(&player), std::vector<int>({100}));
  clock.Advance(milliseconds(500));  // late poll: everything overdue at once
  EXPECT_EQ(DueMs(&player), std::vector<int>({250}));
  clock.Advance(milliseconds(400));
  EXPECT_EQ(DueMs(&player), std::vector<int>({1000}));
  EXPECT_TRUE(player.finished());
  EXPECT_FALSE(player.NextDueTime().has_value());
  EXPECT_EQ(player.records_delivered(), 4u);
  EXPECT_EQ(player.position(), T0() + milliseconds(1000));
}

TEST(ReplayPlayerTest, TwiceAsFastHalvesTheWaits) {
  FakeClock clock;
  VectorRecordStream stream(AtMs({0, 100, 200, 400}));
  ReplayOptions options;
  options.rate = 2.0;
  ReplayPlayer player(&stream, clock, options);
  EXPECT_EQ(DueMs(&player), std::vector<int>({0}));
  clock.Advance(milliseconds(50));
  EXPECT_EQ(DueMs(&player), std::vector<int>({100}));
  clock.Advance(milliseconds(50));
  EXPECT_EQ(DueMs(&player), std::vector<int>({200}));
  EXPECT_EQ(player.NextDueTime(), clock.SteadyNow() + milliseconds(100));
  player.SetRate(0.5);  // from here on, half speed
  EXPECT_EQ(player.NextDueTime(), clock.SteadyNow() + milliseconds(400));
}

TEST(ReplayPlayerTest, PauseHoldsAndResumeContinuesFromThePosition) {
  FakeClock clock;
  VectorRecordStream stream(AtMs({0, 100, 200}));
  ReplayPlayer player(&stream, clock, {});
  EXPECT_EQ(DueMs(&player), std::vector<int>({0}));
  clock.Advance(milliseconds(50));
  player.Pause();
  EXPECT_TRUE(player.paused());
  EXPECT_FALSE(player.NextDueTime().has_value());
  clock.Advance(milliseconds(10000));
  EXPECT_TRUE(DueMs(&player).empty());
  player.Resume();
  EXPECT_EQ(player.NextDueTime(), clock.SteadyNow() + milliseconds(50));
  clock.Advance(milliseconds(50));
  EXPECT_EQ(DueMs(&player), std::vector<int>({100}));
}

TEST(ReplayPlayerTest, StepDeliversOneRecordAtATimeWhilePaused) {
  FakeClock clock;
  VectorRecordStream stream(AtMs({0, 100, 5000, 5100}));
  ReplayOptions options;
  options.start_paused = true;
  ReplayPlayer player(&stream, clock, options);
  EXPECT_TRUE(DueMs(&player).empty());
  player.Step();
  EXPECT_EQ(player.NextDueTime(), clock.SteadyNow());
  EXPECT_EQ(DueMs(&player), std::vector<int>({0}));
  EXPECT_TRUE(DueMs(&player).empty());
  player.Step(2);
  EXPECT_EQ(DueMs(&player), std::vector<int>({100, 5000}));  // no waiting for the gap
  EXPECT_EQ(player.position(), T0() + milliseconds(5000));
  player.Resume();  // continues from the stepped position
  EXPECT_EQ(player.NextDueTime(), clock.SteadyNow() + milliseconds(100));
  player.Step();  // stepping while running pauses
  EXPECT_TRUE(player.paused());
  EXPECT_EQ(DueMs(&player), std::vector<int>({5100}));
}

TEST(ReplayPlayerTest, LoopsBackToTheStart) {
  FakeClock clock;
  VectorRecordStream stream(AtMs({0, 100}));
  ReplayOptions options;
  options.loop = true;
  ReplayPlayer player(&stream, clock, options);
  EXPECT_EQ(DueMs(&player), std::vector<int>({0}));
  clock.Advance(milliseconds(100));
  EXPECT_EQ(DueMs(&player), std::vector<int>({100}));
  EXPECT_EQ(player.loops_completed(), 1u);
  EXPECT_FALSE(player.finished());
  const std::optional<SteadyTime> due = player.NextDueTime();
  ASSERT_TRUE(due.has_value());
  EXPECT_GT(*due, clock.SteadyNow());  // a short gap between loops
  clock.Advance(*due - clock.SteadyNow());
  EXPECT_EQ(DueMs(&player), std::vector<int>({0}));
  clock.Advance(milliseconds(100));
  EXPECT_EQ(DueMs(&player), std::vector<int>({100}));
  EXPECT_EQ(player.loops_completed(), 2u);
}

TEST(ReplayPlayerTest, LoopingASingleInstantNeverSpinsWithinOnePoll) {
  FakeClock clock;
  VectorRecordStream stream(AtMs({0, 0, 0}));
  ReplayOptions options;
  options.loop = true;
  ReplayPlayer player(&stream, clock, options);
  EXPECT_EQ(DueMs(&player).size(), 3u);  // one pass, then the next loop waits
  clock.Advance(milliseconds(1000));
  EXPECT_EQ(DueMs(&player).size(), 3u);
}

TEST(ReplayPlayerTest, EmptyStreamIsFinishedEvenWhenLooping) {
  FakeClock clock;
  VectorRecordStream stream({});
  ReplayOptions options;
  options.loop = true;
  ReplayPlayer player(&stream, clock, options);
  EXPECT_TRUE(player.finished());
  EXPECT_TRUE(player.PollDue().empty());
  EXPECT_FALSE(player.NextDueTime().has_value());
}

TEST(ReplayPlayerTest, SeekJumpsAndDeliversFromThere) {
  FakeClock clock;
  VectorRecordStream stream(AtMs({0, 100, 200, 300}));
  ReplayPlayer player(&stream, clock, {});
  ASSERT_TRUE(player.SeekToTime(T0() + milliseconds(150)));
  EXPECT_EQ(DueMs(&player), std::vector<int>({200}));
  EXPECT_FALSE(player.SeekToTime(T0() + milliseconds(400)));
  EXPECT_TRUE(player.finished());
}

TEST(ReplayOptionsTest, RefusesANonPositiveRate) {
  ReplayOptions options;
  options.rate = 0;
  std::string error;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("rate"), std::string::npos);
}

TEST(ReplayScanSourceTest, GivesScansInOrderAndOnlyWhenDue) {
  std::vector<RecordedMessage> messages;
  for (int i = 0; i < 4; ++i) {
    const Time t = T0() + milliseconds(100 * i);
    messages.push_back(testing::At(t, testing::MakeScan(t, static_cast<uint64_t>(i))));
    messages.push_back(testing::At(t, testing::MakeOdometry(t)));
  }
  ReplayScanSource source(std::make_unique<VectorRecordStream>(messages));
  EXPECT_EQ(source.PeekTime(), T0());
  TimedScan scan;
  ASSERT_TRUE(source.NextUntil(T0() + milliseconds(150), &scan));
  EXPECT_EQ(scan.value.sequence, 0u);
  ASSERT_TRUE(source.NextUntil(T0() + milliseconds(150), &scan));
  EXPECT_EQ(scan.value.sequence, 1u);
  EXPECT_FALSE(source.NextUntil(T0() + milliseconds(150), &scan));
  ASSERT_TRUE(source.Next(&scan));
  EXPECT_EQ(scan.value.sequence, 2u);
  EXPECT_EQ(scan.log_time, T0() + milliseconds(200));
  ASSERT_TRUE(source.SeekToTime(T0() + milliseconds(50)));
  ASSERT_TRUE(source.Next(&scan));
  EXPECT_EQ(scan.value.sequence, 1u);
}

TEST(ReplayFrameSourceTest, PairsEyesByStampInEitherOrderAndDropsOrphans) {
  std::vector<RecordedMessage> messages;
  auto eye = [&](Eye e, int stamp_ms, int log_ms, uint64_t sequence) {
    messages.push_back(testing::At(T0() + milliseconds(log_ms),
                                   testing::MakeImage(e, T0() + milliseconds(stamp_ms), sequence)));
  };
  eye(Eye::kLeft, 0, 10, 1);
  messages.push_back(testing::At(T0() + milliseconds(11), testing::MakeScan(T0(), 0)));
  eye(Eye::kRight, 0, 12, 1);
  eye(Eye::kRight, 66, 70, 2);  // right first
  eye(Eye::kLeft, 66, 75, 2);
  eye(Eye::kLeft, 133, 140, 3);  // its right eye was dropped by the recorder
  eye(Eye::kLeft, 200, 205, 4);
  eye(Eye::kRight, 200, 207, 4);
  ReplayFrameSource source(std::make_unique<VectorRecordStream>(messages));
  TimedStereoPair pair;
  ASSERT_TRUE(source.Next(&pair));
  EXPECT_EQ(pair.pair.sequence, 1u);
  EXPECT_EQ(pair.log_time, T0() + milliseconds(12));
  EXPECT_EQ(pair.pair.left.frame_id, "camera_left");
  EXPECT_EQ(pair.pair.right.frame_id, "camera_right");
  EXPECT_EQ(pair.pair.left.stamp, pair.pair.right.stamp);
  ASSERT_TRUE(source.Next(&pair));
  EXPECT_EQ(pair.pair.sequence, 2u);
  EXPECT_EQ(pair.pair.left.frame_id, "camera_left");
  EXPECT_EQ(pair.log_time, T0() + milliseconds(75));
  EXPECT_FALSE(source.NextUntil(T0() + milliseconds(206), &pair));
  ASSERT_TRUE(source.NextUntil(T0() + milliseconds(207), &pair));
  EXPECT_EQ(pair.pair.sequence, 4u);
  EXPECT_EQ(source.orphan_eyes(), 1u);
  EXPECT_FALSE(source.Next(&pair));
}

TEST(ReplayPlayerTest, ReplaysARecordingFile) {
  FakeClock clock(T0());
  const std::string path = testing::TempPath("replay.mrec");
  std::string error;
  {
    auto writer = RecordingWriter::Open(path, {}, testing::MakeInfo(), clock, &error);
    ASSERT_NE(writer, nullptr) << error;
    for (int i = 0; i < 5; ++i) {
      writer->Write(testing::MakeScan(clock.Now(), static_cast<uint64_t>(i)));
      clock.Advance(milliseconds(200));
    }
  }
  auto reader = RecordingReader::Open(path, &error);
  ASSERT_NE(reader, nullptr) << error;
  ReplayOptions options;
  options.rate = 4.0;
  ReplayPlayer player(reader.get(), clock, options);
  EXPECT_EQ(player.PollDue().size(), 1u);
  clock.Advance(milliseconds(100));  // 400 ms of recording
  EXPECT_EQ(player.PollDue().size(), 2u);
  clock.Advance(milliseconds(100));
  EXPECT_EQ(player.PollDue().size(), 2u);
  EXPECT_TRUE(player.finished());
}

}  // namespace
}  // namespace mostar::record
