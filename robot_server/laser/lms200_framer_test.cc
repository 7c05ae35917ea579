#include "robot_server/laser/lms200_framer.h"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "robot_server/laser/lms200_telegrams.h"

namespace mostar::laser {
namespace {

using Bytes = std::vector<uint8_t>;

Bytes Cat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const Bytes& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

std::vector<FramerEvent> PushAll(Lms200Framer* framer, const Bytes& bytes) {
  std::vector<FramerEvent> events;
  framer->Push(bytes.data(), bytes.size(), &events);
  return events;
}

// Wire frames from the reference's telegram vectors (Telegram Listing LMS2xx and captures).
struct Vector {
  const char* name;
  Bytes wire;
};

std::vector<Vector> RequestVectors() {
  return {
      {"status", {0x02, 0x00, 0x01, 0x00, 0x31, 0x15, 0x12}},
      {"reset", {0x02, 0x00, 0x01, 0x00, 0x10, 0x34, 0x12}},
      {"type", {0x02, 0x00, 0x01, 0x00, 0x3A, 0x1E, 0x12}},
      {"read_config", {0x02, 0x00, 0x01, 0x00, 0x74, 0x50, 0x12}},
      {"errors", {0x02, 0x00, 0x01, 0x00, 0x32, 0x16, 0x12}},
      {"start_continuous", {0x02, 0x00, 0x02, 0x00, 0x20, 0x24, 0x34, 0x08}},
      {"stop_continuous", {0x02, 0x00, 0x02, 0x00, 0x20, 0x25, 0x35, 0x08}},
      {"baud_38400", {0x02, 0x00, 0x02, 0x00, 0x20, 0x40, 0x50, 0x08}},
      {"baud_19200", {0x02, 0x00, 0x02, 0x00, 0x20, 0x41, 0x51, 0x08}},
      {"baud_9600", {0x02, 0x00, 0x02, 0x00, 0x20, 0x42, 0x52, 0x08}},
      {"baud_500k", {0x02, 0x00, 0x02, 0x00, 0x20, 0x48, 0x58, 0x08}},
      {"poll_scan", {0x02, 0x00, 0x02, 0x00, 0x30, 0x01, 0x31, 0x18}},
      {"installation",
       {0x02, 0x00, 0x0A, 0x00, 0x20, 0x00, 0x53, 0x49, 0x43, 0x4B, 0x5F, 0x4C, 0x4D, 0x53, 0xBE,
        0xC5}},
      {"variant_180_050", {0x02, 0x00, 0x05, 0x00, 0x3B, 0xB4, 0x00, 0x32, 0x00, 0x3B, 0x1F}},
      {"variant_180_100", {0x02, 0x00, 0x05, 0x00, 0x3B, 0xB4, 0x00, 0x64, 0x00, 0x97, 0x49}},
      {"variant_100_025", {0x02, 0x00, 0x05, 0x00, 0x3B, 0x64, 0x00, 0x19, 0x00, 0xE7, 0x72}},
  };
}

Bytes TypeReplyWire() {
  const std::string type = "LMS200;301063;V02.10 ";
  Bytes wire{0x02, 0x80, 0x17, 0x00, 0xBA};
  wire.insert(wire.end(), type.begin(), type.end());
  wire.insert(wire.end(), {0x10, 0x22, 0x61});
  return wire;
}

Bytes ConfigWriteReplyWire() {
  Bytes wire{0x02, 0x80, 0x25, 0x00, 0xF7, 0x01, 0x00, 0x00, 0x70,
             0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x02, 0x02};
  wire.insert(wire.end(), 21, 0x00);
  wire.insert(wire.end(), {0x02, 0x00, 0x10, 0xC5, 0x7A});
  return wire;
}

std::vector<Vector> ReplyVectors() {
  return {
      {"mode_ok", {0x02, 0x80, 0x03, 0x00, 0xA0, 0x00, 0x10, 0x16, 0x0A}},
      {"reset_ack", {0x02, 0x80, 0x02, 0x00, 0x91, 0x10, 0x79, 0x30}},
      {"rejected", {0x02, 0x80, 0x02, 0x00, 0x92, 0x10, 0x7F, 0x33}},
      {"variant", {0x02, 0x80, 0x07, 0x00, 0xBB, 0x01, 0xB4, 0x00, 0x32, 0x00, 0x10, 0x03, 0x9D}},
      {"type", TypeReplyWire()},
      {"config_write", ConfigWriteReplyWire()},
      {"scan_3_values",
       {0x02, 0x80, 0x0A, 0x00, 0xB0, 0x03, 0x40, 0xE8, 0x03, 0xD0, 0x07, 0xFF, 0x1F, 0x10, 0x16,
        0xB1}},
  };
}

TEST(Lms200FramerTest, DecodesEveryRequestVector) {
  for (const Vector& v : RequestVectors()) {
    Lms200Framer framer({Lms200Framer::Direction::kRequests});
    const auto events = PushAll(&framer, v.wire);
    ASSERT_EQ(events.size(), 1u) << v.name;
    EXPECT_EQ(events[0].type, FramerEventType::kFrame) << v.name;
    EXPECT_EQ(events[0].frame.address, 0x00) << v.name;
    EXPECT_EQ(Bytes(v.wire.begin() + 4, v.wire.end() - 2), events[0].frame.payload) << v.name;
    EXPECT_EQ(framer.stats().crc_errors, 0u) << v.name;
  }
}

TEST(Lms200FramerTest, BuildersReproduceEveryRequestVector) {
  const auto v = RequestVectors();
  EXPECT_EQ(StatusRequest(), v[0].wire);
  EXPECT_EQ(ResetRequest(), v[1].wire);
  EXPECT_EQ(TypeRequest(), v[2].wire);
  EXPECT_EQ(ReadConfigRequest(), v[3].wire);
  EXPECT_EQ(ErrorRequest(), v[4].wire);
  EXPECT_EQ(StartContinuousRequest(), v[5].wire);
  EXPECT_EQ(StopContinuousRequest(), v[6].wire);
  EXPECT_EQ(BaudRequest(38400), v[7].wire);
  EXPECT_EQ(BaudRequest(19200), v[8].wire);
  EXPECT_EQ(BaudRequest(9600), v[9].wire);
  EXPECT_EQ(BaudRequest(500000), v[10].wire);
  EXPECT_EQ(PollScanRequest(), v[11].wire);
  EXPECT_EQ(InstallationModeRequest("SICK_LMS"), v[12].wire);
  EXPECT_EQ(VariantRequest({180, 50}), v[13].wire);
  EXPECT_EQ(VariantRequest({180, 100}), v[14].wire);
  EXPECT_EQ(VariantRequest({100, 25}), v[15].wire);
  EXPECT_TRUE(BaudRequest(115200).empty());
}

TEST(Lms200FramerTest, DecodesEveryReplyVector) {
  for (const Vector& v : ReplyVectors()) {
    Lms200Framer framer;
    const auto events = PushAll(&framer, v.wire);
    ASSERT_EQ(events.size(), 1u) << v.name;
    EXPECT_EQ(events[0].type, FramerEventType::kFrame) << v.name;
    EXPECT_EQ(events[0].frame.address, 0x80) << v.name;
    EXPECT_EQ(Bytes(v.wire.begin() + 4, v.wire.end() - 2), events[0].frame.payload) << v.name;
    EXPECT_EQ(framer.stats().bytes_discarded, 0u) << v.name;
  }
}

TEST(Lms200FramerTest, ReportsLoneAckAndNakBetweenFrames) {
  Lms200Framer framer;
  const Bytes mode_ok = ReplyVectors()[0].wire;
  const auto events = PushAll(&framer, Cat({{kLms200Ack}, mode_ok, {kLms200Nak}}));
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].type, FramerEventType::kAck);
  EXPECT_EQ(events[1].type, FramerEventType::kFrame);
  EXPECT_EQ(events[2].type, FramerEventType::kNak);
  EXPECT_EQ(framer.stats().acks, 1u);
  EXPECT_EQ(framer.stats().naks, 1u);
}

TEST(Lms200FramerTest, AcceptsReplyAddress0x81AndRejectsOthers) {
  Bytes reply81 = BuildReplyTelegram(0x81, {0xA0, 0x00, 0x10});
  Bytes reply85 = BuildReplyTelegram(0x85, {0xA0, 0x00, 0x10});
  Lms200Framer framer;
  EXPECT_EQ(PushAll(&framer, reply81).size(), 1u);
  EXPECT_TRUE(PushAll(&framer, reply85).empty());
  Lms200Framer strict({Lms200Framer::Direction::kReplies, 0, /*accept_reply_address_0x81=*/false});
  EXPECT_TRUE(PushAll(&strict, reply81).empty());
}

TEST(Lms200FramerTest, RejectsLengthBeyondMaximumAndRescans) {
  // A false start announcing 0x0FFF bytes must not swallow the frame after it.
  const Bytes good = ReplyVectors()[0].wire;
  Lms200Framer framer;
  const auto events = PushAll(&framer, Cat({{0x02, 0x80, 0xFF, 0x0F}, good}));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].frame.payload, Bytes(good.begin() + 4, good.end() - 2));
  EXPECT_EQ(framer.stats().bytes_discarded, 4u);
}

TEST(Lms200FramerTest, CountsCrcErrorAndFindsFrameHiddenInsideBadCandidate) {
  // A false STX whose LEN spans the following real frame: CRC fails, one byte is skipped,
  // and the rescan finds the real frame.
  const Bytes good = ReplyVectors()[6].wire;  // 16 bytes
  Bytes stream = Cat({{0x02, 0x80, 0x10, 0x00}, good, Bytes(8, 0x33)});
  Lms200Framer framer;
  const auto events = PushAll(&framer, stream);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].frame.command(), 0xB0);
  EXPECT_GE(framer.stats().crc_errors, 1u);
  EXPECT_GE(framer.stats().resyncs, 1u);
}

TEST(Lms200FramerTest, TruncatedFrameFollowedByGoodFrameYieldsGoodFrame) {
  const Bytes scan = ReplyVectors()[6].wire;
  const Bytes mode_ok = ReplyVectors()[0].wire;
  // The B0 was cut after 9 bytes because the host sent a command; then ACK and A0 follow.
  const Bytes stream = Cat({Bytes(scan.begin(), scan.begin() + 9), {kLms200Ack}, mode_ok});
  Lms200Framer framer;
  std::vector<FramerEvent> events = PushAll(&framer, stream);
  // The held candidate (LEN 10) now spans the ACK and part of A0; the line goes quiet.
  framer.AbandonPartial(&events);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].type, FramerEventType::kAck);
  EXPECT_EQ(events[1].frame.command(), 0xA0);
  EXPECT_EQ(framer.buffered_bytes(), 0u);
  EXPECT_EQ(framer.stats().partials_abandoned + framer.stats().crc_errors, 1u);
}

TEST(Lms200FramerTest, TruncatedFrameInsideStreamIsSkippedWithoutAbandon) {
  const Bytes scan = ReplyVectors()[6].wire;
  const Bytes stream = Cat({Bytes(scan.begin(), scan.begin() + 7), scan, scan});
  Lms200Framer framer;
  const auto events = PushAll(&framer, stream);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(framer.stats().frames, 2u);
}

TEST(Lms200FramerTest, RequestDirectionIgnoresReplyAddresses) {
  Lms200Framer framer({Lms200Framer::Direction::kRequests});
  EXPECT_TRUE(PushAll(&framer, ReplyVectors()[0].wire).empty());
  EXPECT_EQ(PushAll(&framer, StatusRequest(0x05)).size(), 1u);
}

TEST(Lms200FramerTest, ResetDropsBufferedBytes) {
  Lms200Framer framer;
  const Bytes scan = ReplyVectors()[6].wire;
  PushAll(&framer, Bytes(scan.begin(), scan.begin() + 5));
  EXPECT_EQ(framer.buffered_bytes(), 5u);
  framer.Reset();
  EXPECT_EQ(framer.buffered_bytes(), 0u);
  EXPECT_EQ(PushAll(&framer, scan).size(), 1u);
}

// Property: any stream of valid frames, with random garbage between them, false STX starts
// inserted and arbitrary read boundaries, decodes to exactly the original frames in order.
TEST(Lms200FramerTest, PropertyRandomGarbageSplitsAndFalseStartsNeverLoseFrames) {
  std::mt19937 rng(20240611);
  auto uniform = [&rng](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  for (int iteration = 0; iteration < 400; ++iteration) {
    std::vector<Bytes> payloads;
    Bytes stream;
    const int frame_count = uniform(1, 12);
    for (int f = 0; f < frame_count; ++f) {
      // Garbage: random bytes (may contain 02, 06, 15, 80), sometimes a false start.
      const int garbage = uniform(0, 20);
      for (int g = 0; g < garbage; ++g) stream.push_back(static_cast<uint8_t>(uniform(0, 255)));
      if (uniform(0, 2) == 0) {
        const int false_len = uniform(0, 900);
        stream.insert(stream.end(), {0x02, 0x80, static_cast<uint8_t>(false_len & 0xFF),
                                     static_cast<uint8_t>(false_len >> 8)});
      }
      Bytes payload;
      const int size = uniform(2, 300);
      payload.push_back(static_cast<uint8_t>(uniform(0x80, 0xFF)));
      for (int b = 1; b < size; ++b) payload.push_back(static_cast<uint8_t>(uniform(0, 255)));
      const Bytes wire = BuildReplyTelegram(0x80, payload);
      stream.insert(stream.end(), wire.begin(), wire.end());
      payloads.push_back(payload);
    }
    Lms200Framer framer;
    std::vector<FramerEvent> events;
    size_t pos = 0;
    while (pos < stream.size()) {
      const size_t chunk = std::min<size_t>(stream.size() - pos, uniform(1, 64));
      framer.Push(stream.data() + pos, chunk, &events);
      pos += chunk;
    }
    framer.AbandonPartial(&events);
    std::vector<Bytes> decoded;
    for (const FramerEvent& e : events) {
      if (e.type == FramerEventType::kFrame) decoded.push_back(e.frame.payload);
    }
    ASSERT_EQ(decoded, payloads) << "iteration " << iteration;
  }
}

}  // namespace
}  // namespace mostar::laser
