// The sonar and bumper replays on a small recording written with the real writer, on a
// FakeClock that the replays' sleeps advance up to a limit the test moves.
#include "robot_server/replay/replay_sonar.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <mutex>
#include <thread>
#include <vector>

#include "common/record/recording_writer.h"
#include "common/record/test_records.h"
#include "common/time/fake_clock.h"

namespace mostar::replay {
namespace {

using record::testing::T0;
using std::chrono::milliseconds;

constexpr int kCycles = 5;
const Duration kCyclePeriod = milliseconds(200);
Time CycleLogTime(int k) { return T0() + k * kCyclePeriod + milliseconds(130); }

// Bumper states: open, then segment 2 pressed, then unreadable, then open again.
struct RecordedBumpers {
  Duration at;
  uint32_t pressed;
  bool readable;
};
const RecordedBumpers kBumpers[] = {{milliseconds(100), 0, true},
                                    {milliseconds(400), 1u << 2, true},
                                    {milliseconds(600), 0, false},
                                    {milliseconds(800), 0, true}};

void WriteRecording(const std::string& path) {
  std::vector<record::RecordedMessage> messages;
  for (int k = 0; k < kCycles; ++k) {
    messages.push_back(
        record::testing::At(CycleLogTime(k), record::testing::MakeSonar(T0() + k * kCyclePeriod)));
  }
  for (const RecordedBumpers& b : kBumpers) {
    BumperState state = record::testing::MakeBumpers(T0() + b.at);
    state.pressed = b.pressed;
    state.latched = 0;
    state.readable = b.readable;
    messages.push_back(record::testing::At(T0() + b.at, state));
  }
  messages.push_back(record::testing::At(T0() + milliseconds(1000),
                                         record::testing::MakeScan(T0() + milliseconds(990), 1)));
  std::stable_sort(messages.begin(), messages.end(),
                   [](const auto& a, const auto& b) { return a.log_time < b.log_time; });
  FakeClock clock(T0());
  std::string error;
  auto writer = record::RecordingWriter::Open(path, {}, record::testing::MakeInfo(), clock, &error);
  ASSERT_NE(writer, nullptr) << error;
  for (const auto& m : messages) EXPECT_TRUE(writer->Write(m));
  EXPECT_TRUE(writer->Close(&error)) << error;
}

class ReplaySonarTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = record::testing::TempPath("replay_sonar.mostar");
    WriteRecording(path_);
  }
  void TearDown() override { std::remove(path_.c_str()); }

  // Options on the fake clock; a replay's sleep advances it, but not beyond the limit.
  template <typename Options>
  Options DeviceOptions(ReplayTimelineOptions timeline_options = {}) {
    std::string error;
    Options options;
    options.path = path_;
    options.timeline = ReplayTimeline::ForRecording(path_, clock_, timeline_options, &error);
    EXPECT_NE(options.timeline, nullptr) << error;
    options.clock = &clock_;
    options.sleep = [this](Duration d) {
      if (clock_.SteadyNow() + d <= limit_.load()) {
        clock_.Advance(d);
      } else {
        std::this_thread::sleep_for(milliseconds(1));
      }
    };
    return options;
  }
  // Lets the replays run until `offset` after the timeline's start, and waits (bounded) until
  // `done` holds.
  template <typename Done>
  bool RunUntil(Duration offset, Done done) {
    limit_ = start_ + offset;
    for (int i = 0; i < 2000 && !done(); ++i) std::this_thread::sleep_for(milliseconds(1));
    return done();
  }

  std::string path_;
  FakeClock clock_{T0()};
  const SteadyTime start_ = clock_.SteadyNow();
  std::atomic<SteadyTime> limit_{start_};
};

TEST_F(ReplaySonarTest, SonarDeliversEveryCycleRestampedAndRenumberedThenEnds) {
  ReplaySonarRing sonar(DeviceOptions<ReplaySonarRing::Options>());
  std::mutex mutex;
  std::vector<SonarRanges> received;
  std::string error;
  ASSERT_TRUE(sonar.Start(
      [&](const SonarRanges& ranges) {
        std::lock_guard<std::mutex> lock(mutex);
        received.push_back(ranges);
      },
      &error))
      << error;
  const Time w0 = clock_.Now();
  ASSERT_TRUE(RunUntil(milliseconds(2000), [&] { return sonar.finished(); }));
  sonar.Stop();
  ASSERT_EQ(received.size(), static_cast<size_t>(kCycles));
  const Time begin = T0() + milliseconds(100);  // the recording's first record
  for (int k = 0; k < kCycles; ++k) {
    EXPECT_EQ(received[k].cycle, static_cast<uint64_t>(k + 1));
    ASSERT_EQ(received[k].ranges.size(), 3u);
    EXPECT_EQ(received[k].ranges[0].stamp, w0 + (T0() + k * kCyclePeriod - begin));
    EXPECT_EQ(received[k].ranges[0].range_m, 1.25f);
  }
  const DeviceHealth health = sonar.Health();
  EXPECT_EQ(health.state, DeviceState::kOff);
  EXPECT_NE(health.message.find("end of recording"), std::string::npos) << health.message;
  EXPECT_EQ(health.counters.front(), (std::pair<std::string, uint64_t>{"cycles_replayed", 5}));
}

TEST_F(ReplaySonarTest, LoopingKeepsCycleNumbersIncreasing) {
  ReplayTimelineOptions looping;
  looping.loop = true;
  ReplaySonarRing sonar(DeviceOptions<ReplaySonarRing::Options>(looping));
  std::atomic<uint64_t> last_cycle{0};
  std::atomic<bool> increasing{true};
  std::atomic<int> count{0};
  std::string error;
  ASSERT_TRUE(sonar.Start(
      [&](const SonarRanges& ranges) {
        if (ranges.cycle <= last_cycle) increasing = false;
        last_cycle = ranges.cycle;
        ++count;
      },
      &error))
      << error;
  ASSERT_TRUE(RunUntil(milliseconds(5000), [&] { return count.load() >= 2 * kCycles + 1; }));
  sonar.Stop();
  EXPECT_TRUE(increasing.load());
  EXPECT_GE(last_cycle.load(), static_cast<uint64_t>(2 * kCycles + 1));
}

TEST_F(ReplaySonarTest, BumpersFollowTheRecordedStatesAndFailWhenUnknownOrUnreadable) {
  std::string error;
  ReplayBumperBelt::Options options = DeviceOptions<ReplayBumperBelt::Options>();
  options.segments = 16;
  ReplayBumperBelt bumpers(options, &error);
  ASSERT_TRUE(error.empty()) << error;
  EXPECT_EQ(bumpers.segments(), 16);
  uint32_t pressed = 99;
  std::string why;
  EXPECT_FALSE(bumpers.Read(&pressed, &why));  // nothing due yet: unknown
  EXPECT_NE(why.find("no recorded bumper state"), std::string::npos) << why;
  auto reads = [&](uint32_t expected) {
    uint32_t p = 0;
    std::string e;
    return bumpers.Read(&p, &e) && p == expected;
  };
  // Log times from the recording's first record (T0 + 100 ms).
  EXPECT_TRUE(RunUntil(milliseconds(150), [&] { return reads(0); }));
  EXPECT_TRUE(RunUntil(milliseconds(350), [&] { return reads(1u << 2); }));
  ASSERT_TRUE(RunUntil(milliseconds(550), [&] {
    std::string e;
    return !bumpers.Read(&pressed, &e) && e.find("unreadable") != std::string::npos;
  }));
  EXPECT_TRUE(RunUntil(milliseconds(2000), [&] { return bumpers.finished() && reads(0); }));
  EXPECT_EQ(bumpers.Health().counters.front(),
            (std::pair<std::string, uint64_t>{"states_replayed", 4}));
}

TEST_F(ReplaySonarTest, ABeltOfAnotherSizeWarnsAndAMissingFileIsAnError) {
  std::string error;
  ReplayBumperBelt::Options options = DeviceOptions<ReplayBumperBelt::Options>();
  options.segments = 8;
  ReplayBumperBelt bumpers(options, &error);
  ASSERT_TRUE(RunUntil(milliseconds(150), [&] {
    uint32_t p = 0;
    std::string e;
    return bumpers.Read(&p, &e);
  }));
  const DeviceHealth health = bumpers.Health();
  EXPECT_EQ(health.state, DeviceState::kWarn);
  EXPECT_NE(health.message.find("16 segments"), std::string::npos) << health.message;

  ReplaySonarRing::Options missing = DeviceOptions<ReplaySonarRing::Options>();
  missing.path = path_ + ".missing";
  ReplaySonarRing sonar(missing);
  EXPECT_FALSE(sonar.Start([](const SonarRanges&) {}, &error));
  EXPECT_NE(error.find(".missing"), std::string::npos) << error;
}

}  // namespace
}  // namespace mostar::replay
