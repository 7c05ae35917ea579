#include "robot_server/drive/motor_protocol.h"

#include <gtest/gtest.h>

#include <random>

namespace mostar::drive {
namespace {

std::vector<MotorMessage> DecodeAll(MotorFrameDecoder* decoder) {
  std::vector<MotorMessage> out;
  while (auto frame = decoder->Next()) {
    MotorMessage message;
    std::string error;
    if (DecodeMessage(*frame, &message, &error)) out.push_back(message);
  }
  return out;
}

bool SameMessage(const MotorMessage& a, const MotorMessage& b) {
  return EncodeMessage(a) == EncodeMessage(b);
}

TEST(Crc16CcittFalseTest, MatchesTheStandardCheckValue) {
  const std::string check = "123456789";
  EXPECT_EQ(Crc16CcittFalse(reinterpret_cast<const uint8_t*>(check.data()), check.size()), 0x29B1);
}

TEST(MotorProtocolTest, EncodesSetVelocityLikeTheDocumentedVector) {
  SetVelocityMsg m;
  m.sequence = 0x0102;
  m.left_ticks_per_s = 1000;
  m.right_ticks_per_s = -1000;
  const std::vector<uint8_t> expected = {0xAA, 0x55, 0x01, 0x0A, 0x02, 0x01, 0xE8, 0x03,
                                         0x00, 0x00, 0x18, 0xFC, 0xFF, 0xFF, 0x21, 0x13};
  EXPECT_EQ(EncodeMessage(m), expected);
}

TEST(MotorProtocolTest, DecodesTheDocumentedEncoderReportVector) {
  const std::vector<uint8_t> bytes = {0xAA, 0x55, 0x10, 0x0C, 0x04, 0x03, 0x02, 0x01, 0xFF,
                                      0xFF, 0xFF, 0xFF, 0x07, 0x00, 0x00, 0x00, 0xEE, 0x4F};
  MotorFrameDecoder decoder;
  decoder.Push(bytes);
  const std::vector<MotorMessage> messages = DecodeAll(&decoder);
  ASSERT_EQ(messages.size(), 1u);
  const auto* report = std::get_if<EncoderReportMsg>(&messages[0]);
  ASSERT_NE(report, nullptr);
  EXPECT_EQ(report->board_time_us, 0x01020304u);
  EXPECT_EQ(report->left_count, 0xFFFFFFFFu);
  EXPECT_EQ(report->right_count, 7u);
  EXPECT_EQ(decoder.stats().frames, 1u);
  EXPECT_EQ(decoder.stats().crc_errors, 0u);
}

TEST(MotorProtocolTest, RoundTripsEveryMessageType) {
  StatusMsg status;
  status.state = BoardState::kFault;
  status.fault_flags = kFaultOvercurrentLeft | kFaultUndervoltage;
  status.battery_mv = 23950;
  status.last_sequence = 65535;
  const std::vector<MotorMessage> messages = {SetVelocityMsg{7, -123456, 654321}, StopMsg{8, true},
                                              HeartbeatMsg{9}, EncoderReportMsg{1, 2, 3}, status};
  MotorFrameDecoder decoder;
  for (const auto& m : messages) decoder.Push(EncodeMessage(m));
  const std::vector<MotorMessage> decoded = DecodeAll(&decoder);
  ASSERT_EQ(decoded.size(), messages.size());
  for (size_t i = 0; i < messages.size(); ++i) {
    EXPECT_EQ(decoded[i].index(), messages[i].index());
    EXPECT_TRUE(SameMessage(decoded[i], messages[i])) << i;
  }
}

TEST(MotorProtocolTest, ResyncsAfterGarbageAndCountsIt) {
  MotorFrameDecoder decoder;
  const std::vector<uint8_t> garbage = {0x00, 0x13, 0xAA, 0x00, 0x55, 0xAA};
  decoder.Push(garbage);
  decoder.Push(EncodeMessage(HeartbeatMsg{42}));
  const std::vector<MotorMessage> decoded = DecodeAll(&decoder);
  ASSERT_EQ(decoded.size(), 1u);
  EXPECT_EQ(std::get<HeartbeatMsg>(decoded[0]).sequence, 42);
  EXPECT_EQ(decoder.stats().discarded_bytes, garbage.size());
}

TEST(MotorProtocolTest, DropsACorruptedFrameAndKeepsTheNextOne) {
  std::vector<uint8_t> bad = EncodeMessage(SetVelocityMsg{1, 10, 10});
  bad[6] ^= 0x40;  // flip a payload bit
  MotorFrameDecoder decoder;
  decoder.Push(bad);
  decoder.Push(EncodeMessage(StopMsg{2, false}));
  const std::vector<MotorMessage> decoded = DecodeAll(&decoder);
  ASSERT_EQ(decoded.size(), 1u);
  EXPECT_EQ(std::get<StopMsg>(decoded[0]).sequence, 2);
  EXPECT_EQ(decoder.stats().crc_errors, 1u);
}

TEST(MotorProtocolTest, ImpossibleLengthDoesNotSwallowTheFollowingFrame) {
  MotorFrameDecoder decoder;
  decoder.Push(std::vector<uint8_t>{0xAA, 0x55, 0x01, 0xFF});
  decoder.Push(EncodeMessage(HeartbeatMsg{5}));
  const std::vector<MotorMessage> decoded = DecodeAll(&decoder);
  ASSERT_EQ(decoded.size(), 1u);
  EXPECT_EQ(decoder.stats().bad_lengths, 1u);
}

TEST(MotorProtocolTest, WaitsForAFrameSplitAcrossPushes) {
  const std::vector<uint8_t> frame = EncodeMessage(EncoderReportMsg{100, 200, 300});
  MotorFrameDecoder decoder;
  for (size_t i = 0; i + 1 < frame.size(); ++i) {
    decoder.Push(&frame[i], 1);
    EXPECT_FALSE(decoder.Next().has_value()) << "byte " << i;
  }
  decoder.Push(&frame.back(), 1);
  EXPECT_TRUE(decoder.Next().has_value());
  EXPECT_EQ(decoder.buffered_bytes(), 0u);
}

TEST(MotorProtocolTest, RejectsUnknownTypeAndWrongPayloadLength) {
  MotorMessage message;
  std::string error;
  EXPECT_FALSE(DecodeMessage(RawFrame{0x7F, {}}, &message, &error));
  EXPECT_NE(error.find("unknown"), std::string::npos);
  EXPECT_FALSE(DecodeMessage(RawFrame{0x03, {1, 2, 3}}, &message, &error));
  EXPECT_NE(error.find("expected 2"), std::string::npos);
  EXPECT_FALSE(DecodeMessage(RawFrame{0x11, {9, 0, 0, 0, 0, 0, 0}}, &message, &error));
}

// Property: valid frames separated by random garbage all come out, in order, whatever the
// garbage and however the stream is cut into reads.
TEST(MotorProtocolTest, PropertyResyncNeverLosesAValidFrame) {
  std::mt19937 rng(1234);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> garbage_size(0, 40);
  std::uniform_int_distribution<int> chunk(1, 64);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<MotorMessage> sent;
    std::vector<uint8_t> stream;
    for (int i = 0; i < 100; ++i) {
      const int n = garbage_size(rng);
      for (int g = 0; g < n; ++g) {
        // Bias towards sync bytes so that fake headers are common.
        const int b = byte(rng);
        stream.push_back(b < 40 ? kSync0 : (b < 80 ? kSync1 : static_cast<uint8_t>(b)));
      }
      MotorMessage m = EncoderReportMsg{static_cast<uint32_t>(i), static_cast<uint32_t>(byte(rng)),
                                        static_cast<uint32_t>(trial)};
      if (i % 3 == 1) m = SetVelocityMsg{static_cast<uint16_t>(i), byte(rng) - 128, byte(rng)};
      sent.push_back(m);
      const std::vector<uint8_t> frame = EncodeMessage(m);
      stream.insert(stream.end(), frame.begin(), frame.end());
    }
    // Trailing bytes flush a fake header that may still wait for its payload.
    stream.insert(stream.end(), kMaxPayloadBytes + kFrameOverheadBytes, 0x00);

    MotorFrameDecoder decoder;
    std::vector<MotorMessage> received;
    for (size_t pos = 0; pos < stream.size();) {
      const size_t n = std::min(stream.size() - pos, static_cast<size_t>(chunk(rng)));
      decoder.Push(stream.data() + pos, n);
      pos += n;
      for (auto& m : DecodeAll(&decoder)) received.push_back(m);
    }
    // Every sent message appears in order (garbage may rarely form an extra valid frame).
    size_t next = 0;
    for (const auto& m : received) {
      if (next < sent.size() && SameMessage(m, sent[next])) ++next;
    }
    EXPECT_EQ(next, sent.size()) << "trial " << trial;
    EXPECT_LE(received.size(), sent.size() + 2);
  }
}

}  // namespace
}  // namespace mostar::drive
