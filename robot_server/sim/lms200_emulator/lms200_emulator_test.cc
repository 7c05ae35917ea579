#include "robot_server/sim/lms200_emulator/lms200_emulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace mostar::sim {
namespace {

using Bytes = std::vector<uint8_t>;
using laser::FramerEvent;
using laser::FramerEventType;
using std::chrono::milliseconds;

// Drives an emulator with a synthetic clock and decodes what it sends.
struct Harness {
  explicit Harness(Lms200EmulatorOptions options = {})
      : room(10.0, 6.0, 5.0, 3.0), emulator(options, &room, t) {}
  void Send(const Bytes& bytes, int host_baud) {
    emulator.Receive(bytes.data(), bytes.size(), host_baud, t);
  }
  std::vector<FramerEvent> Run(Duration d, int host_baud) {
    std::vector<FramerEvent> events;
    const SteadyTime end = t + d;
    while (t < end) {
      t += milliseconds(1);
      Bytes out;
      emulator.Transmit(t, host_baud, &out);
      framer.Push(out.data(), out.size(), &events);
    }
    return events;
  }
  static std::vector<laser::Lms200Frame> Frames(const std::vector<FramerEvent>& events) {
    std::vector<laser::Lms200Frame> frames;
    for (const auto& e : events) {
      if (e.type == FramerEventType::kFrame) frames.push_back(e.frame);
    }
    return frames;
  }
  SteadyTime t = SteadyTime(std::chrono::seconds(100));
  RoomRangeSource room;
  Lms200Emulator emulator;
  laser::Lms200Framer framer;
};

TEST(Lms200EmulatorTest, AcksAndAnswersStatusAtItsBaudOnly) {
  Harness h;
  h.Send(laser::StatusRequest(), 38400);  // wrong rate: lost
  EXPECT_TRUE(h.Run(milliseconds(300), 38400).empty());
  h.Send(laser::StatusRequest(), 9600);
  const auto events = h.Run(milliseconds(300), 9600);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].type, FramerEventType::kAck);
  laser::Lms200DeviceStatus status;
  std::string error;
  ASSERT_TRUE(laser::DecodeStatusReply(events[1].frame, &status, &error)) << error;
  EXPECT_EQ(status.baud, 9600);
  EXPECT_EQ(status.variant, (laser::Lms200Variant{180, 50}));
}

TEST(Lms200EmulatorTest, NaksBadChecksumAndRejectsUnknownCommand) {
  Harness h;
  Bytes bad = laser::StatusRequest();
  bad.back() ^= 1;
  h.Send(bad, 9600);
  auto events = h.Run(milliseconds(50), 9600);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, FramerEventType::kNak);
  h.Send(laser::BuildTelegram(0, {0x55}), 9600);
  const auto frames = Harness::Frames(h.Run(milliseconds(50), 9600));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_TRUE(laser::IsRejection(frames[0]));
  // Another address: silence.
  h.Send(laser::StatusRequest(0x05), 9600);
  EXPECT_TRUE(h.Run(milliseconds(300), 9600).empty());
}

TEST(Lms200EmulatorTest, SwitchesBaudAfterReplyAtOldRate) {
  Harness h;
  h.Send(laser::BaudRequest(38400), 9600);
  const auto frames = Harness::Frames(h.Run(milliseconds(50), 9600));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].command(), laser::kReplyMode);
  EXPECT_EQ(h.emulator.baud(), 38400);
  h.Send(laser::StatusRequest(), 38400);
  EXPECT_EQ(Harness::Frames(h.Run(milliseconds(100), 38400)).size(), 1u);
}

// Frames a 180 x 1 deg scanner at `baud` sends in 2 s of continuous output; `scans` counts them.
std::vector<laser::Lms200Frame> StreamFor2s(int baud, size_t* scans) {
  Lms200EmulatorOptions options;
  options.initial_baud = baud;
  options.variant = {180, 100};
  Harness h(options);
  h.Send(laser::StartContinuousRequest(), baud);
  const auto frames = Harness::Frames(h.Run(std::chrono::seconds(2), baud));
  *scans = 0;
  for (const auto& f : frames) *scans += f.command() == laser::kReplyScan;
  return frames;
}

TEST(Lms200EmulatorTest, StreamsAsFastAsTheLineAllows) {
  size_t scans = 0;
  const auto frames = StreamFor2s(38400, &scans);
  // 372 bytes take 96.9 ms; the next free mirror turn is the 8th: 106.6 ms per scan.
  EXPECT_NEAR(static_cast<double>(scans), 2.0 / 0.10656, 1.0);
  laser::Lms200MeasuredValues values;
  std::string error;
  ASSERT_TRUE(laser::DecodeScanReply(frames.back(), {}, &values, &error)) << error;
  EXPECT_EQ(values.count, 181);
  EXPECT_EQ(values.unit, laser::Lms200Unit::kMm);
  EXPECT_EQ(values.words[90], 5000);  // wall 5 m ahead
  EXPECT_EQ(values.words[0], 3000);   // wall 3 m to the right
}

TEST(Lms200EmulatorTest, StreamsEveryMirrorTurnAt500kBd) {
  size_t scans = 0;
  StreamFor2s(500000, &scans);
  // 372 bytes take 7.44 ms, less than a mirror turn (13.32 ms): one scan per turn, 75 Hz
  // (150.2 turns in 2 s; the first turn's phase and the telegram in flight at the end).
  EXPECT_NEAR(static_cast<double>(scans), 2.0 / laser::kLms200MirrorPeriodS, 2.0);
}

TEST(Lms200EmulatorTest, LogsOnlyScansThatLeftIntactAtTheHostsRate) {
  Lms200EmulatorOptions options;
  options.initial_baud = 500000;
  options.variant = {180, 100};
  Harness h(options);
  h.Send(laser::StartContinuousRequest(), 500000);
  h.Run(milliseconds(5), 500000);  // the ACK and A0 leave
  h.emulator.CorruptNextTelegrams(2);
  auto frames = Harness::Frames(h.Run(milliseconds(500), 500000));
  h.Run(milliseconds(100), 38400);  // the host at another rate: garbage
  const auto more = Harness::Frames(h.Run(milliseconds(500), 500000));
  frames.insert(frames.end(), more.begin(), more.end());
  size_t valid_scans = 0;
  for (const auto& f : frames) valid_scans += f.command() == laser::kReplyScan;
  const auto intact = h.emulator.IntactScans();
  EXPECT_EQ(intact.size(), valid_scans);
  ASSERT_GE(intact.size(), 60u);
  EXPECT_EQ(intact.front().id, 2u);  // 0 and 1 left with a bad CRC
  EXPECT_EQ(intact.front().stream_starts, 1u);
  EXPECT_EQ(h.emulator.scans_sent(), intact.size() + 2 + 8);  // 7-8 turns in 100 ms garbled
}

// A pause of the emulator's own thread inside a telegram (a real UART never pauses) takes that
// telegram out of the intact log: a driver that gives up on a partial after a quiet line
// may rightly drop it.
TEST(Lms200EmulatorTest, ATelegramTheLinePausedInsideIsStalledNotIntact) {
  Lms200EmulatorOptions options;
  options.initial_baud = 500000;
  options.variant = {180, 100};
  Harness h(options);
  h.Send(laser::StartContinuousRequest(), 500000);
  h.Run(milliseconds(100), 500000);
  const size_t intact_before = h.emulator.IntactScans().size();
  ASSERT_GE(intact_before, 5u);
  EXPECT_TRUE(h.emulator.StalledScans().empty());
  // Find a moment inside a telegram: bytes are still due after this millisecond's batch.
  Bytes out;
  for (int i = 0; i < 20; ++i) {
    h.t += milliseconds(1);
    out.clear();
    const size_t logged = h.emulator.IntactScans().size();
    h.emulator.Transmit(h.t, 500000, &out);
    if (!out.empty() && h.emulator.IntactScans().size() == logged) break;
  }
  ASSERT_FALSE(out.empty());
  h.t += milliseconds(120);  // the emulator's thread is not scheduled for 120 ms
  h.Run(milliseconds(1), 500000);
  const auto stalled = h.emulator.StalledScans();
  ASSERT_EQ(stalled.size(), 1u);
  // Telegrams that were merely late as a whole (queued during the pause) stay intact.
  h.Run(milliseconds(200), 500000);
  EXPECT_EQ(h.emulator.StalledScans().size(), 1u);
  const auto intact = h.emulator.IntactScans();
  EXPECT_GE(intact.size(), intact_before + 10);
  for (const auto& scan : intact) EXPECT_NE(scan.id, stalled.front());
}

TEST(Lms200EmulatorTest, EncodesNoEchoBeyondRangeErrorsAndForcedCodes) {
  Lms200EmulatorOptions options;
  options.initial_baud = 38400;
  options.variant = {180, 100};
  FunctionRangeSource source([](SteadyTime, float a) {
    if (a > 0.5f) return INFINITY;    // nothing echoes
    if (a > 0.3f) return NAN;         // no measurement
    return a < -0.5f ? 20.0f : 2.0f;  // beyond the maximum, in range
  });
  Lms200Emulator emulator(options, &source, SteadyTime{});
  emulator.SetBeamCode(90, 0x1FFE);
  const Bytes poll = laser::PollScanRequest();
  emulator.Receive(poll.data(), poll.size(), 38400, SteadyTime{});
  Bytes out;
  emulator.Transmit(SteadyTime(std::chrono::seconds(1)), 38400, &out);
  laser::Lms200Framer framer;
  std::vector<FramerEvent> events;
  framer.Push(out.data(), out.size(), &events);
  ASSERT_EQ(events.size(), 2u);
  laser::Lms200MeasuredValues values;
  std::string error;
  ASSERT_TRUE(laser::DecodeScanReply(events[1].frame, {}, &values, &error)) << error;
  EXPECT_EQ(values.words[0], 0x1FF7);    // 20 m > 8.183 m in mm mode
  EXPECT_EQ(values.words[180], 0x1FFF);  // no echo
  EXPECT_EQ(values.words[110], 0x1FFE);  // NaN: dazzle
  EXPECT_EQ(values.words[90], 0x1FFE);   // forced dazzle
  EXPECT_EQ(values.words[80], 2000);
}

TEST(Lms200EmulatorTest, WritesConfigOnlyInInstallationMode) {
  Harness h;
  laser::Lms200ConfigBlock block = h.emulator.config();
  block.set_measuring_mode(3);
  h.Send(laser::WriteConfigRequest(block), 9600);
  auto frames = Harness::Frames(h.Run(milliseconds(200), 9600));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_TRUE(laser::IsRejection(frames[0]));
  h.Send(laser::InstallationModeRequest("WRONG_PW"), 9600);
  frames = Harness::Frames(h.Run(milliseconds(200), 9600));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].payload[1], 0x01);  // refused
  h.Send(laser::InstallationModeRequest("SICK_LMS"), 9600);
  h.Run(milliseconds(200), 9600);
  h.Send(laser::WriteConfigRequest(block), 9600);
  frames = Harness::Frames(h.Run(milliseconds(200), 9600));
  ASSERT_EQ(frames.size(), 1u);
  bool accepted = false;
  laser::Lms200ConfigBlock echoed;
  std::string error;
  ASSERT_TRUE(laser::DecodeConfigWriteReply(frames[0], &accepted, &echoed, &error)) << error;
  EXPECT_TRUE(accepted);
  EXPECT_EQ(echoed.measuring_mode(), 3);
  EXPECT_EQ(h.emulator.eeprom_writes(), 1);
}

TEST(Lms200EmulatorTest, HostRequestTruncatesTelegramInFlight) {
  Lms200EmulatorOptions options;
  options.initial_baud = 9600;
  Harness h(options);
  h.Send(laser::StartContinuousRequest(), 9600);
  h.Run(milliseconds(100), 9600);  // A0 done, first B0 (732 bytes, 0.76 s) under way
  h.Send(laser::StopContinuousRequest(), 9600);
  auto events = h.Run(milliseconds(100), 9600);
  h.framer.AbandonPartial(&events);
  const auto frames = Harness::Frames(events);
  ASSERT_FALSE(frames.empty());
  EXPECT_EQ(frames.back().command(), laser::kReplyMode);
  EXPECT_EQ(h.framer.stats().frames, 2u);  // the first A0 and the last; the B0 was cut
}

}  // namespace
}  // namespace mostar::sim
