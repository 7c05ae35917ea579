#include "robot_server/laser/lms200_telegrams.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace mostar::laser {
namespace {

using Bytes = std::vector<uint8_t>;

Lms200Frame FrameOf(const Bytes& wire) {
  Lms200Framer framer;
  std::vector<FramerEvent> events;
  framer.Push(wire.data(), wire.size(), &events);
  EXPECT_EQ(events.size(), 1u);
  return events.empty() ? Lms200Frame{} : events[0].frame;
}

// A B0 payload with `words` values; unit bits and optional indices.
Lms200Frame ScanFrame(const std::vector<uint16_t>& words, Lms200Unit unit, bool indices = false,
                      uint8_t status = 0x10) {
  Lms200Frame frame;
  frame.address = 0x80;
  const uint16_t count = static_cast<uint16_t>(words.size() | (static_cast<int>(unit) << 14));
  frame.payload = {0xB0, static_cast<uint8_t>(count & 0xFF), static_cast<uint8_t>(count >> 8)};
  for (uint16_t w : words) {
    frame.payload.push_back(static_cast<uint8_t>(w & 0xFF));
    frame.payload.push_back(static_cast<uint8_t>(w >> 8));
  }
  if (indices) frame.payload.insert(frame.payload.end(), {0x07, 0x2A});
  frame.payload.push_back(status);
  return frame;
}

std::vector<uint16_t> Words181(uint16_t fill) { return std::vector<uint16_t>(181, fill); }

TEST(Lms200TelegramsTest, DecodesSyntheticScanVector) {
  const Lms200Frame frame = FrameOf({0x02, 0x80, 0x0A, 0x00, 0xB0, 0x03, 0x40, 0xE8, 0x03, 0xD0,
                                     0x07, 0xFF, 0x1F, 0x10, 0x16, 0xB1});
  Lms200MeasuredValues values;
  std::string error;
  ASSERT_TRUE(DecodeScanReply(frame, {}, &values, &error)) << error;
  EXPECT_EQ(values.count, 3);
  EXPECT_EQ(values.unit, Lms200Unit::kMm);
  EXPECT_FALSE(values.partial);
  EXPECT_EQ(values.words, (std::vector<uint16_t>{1000, 2000, 0x1FFF}));
  EXPECT_EQ(values.status.raw, 0x10);
  // 3 values are no known variant: conversion refuses with a message.
  LaserScan scan;
  EXPECT_FALSE(ToLaserScan(values, 0x00, &scan, nullptr, &error));
  EXPECT_NE(error.find("3 values"), std::string::npos);
}

TEST(Lms200TelegramsTest, CountWordSeparatesCountPartialAndUnitBits) {
  // 361 values, mm, as in the listing's example "69 41".
  Lms200Frame frame = ScanFrame(std::vector<uint16_t>(361, 500), Lms200Unit::kMm);
  EXPECT_EQ(frame.payload[1], 0x69);
  EXPECT_EQ(frame.payload[2], 0x41);
  Lms200MeasuredValues values;
  std::string error;
  ASSERT_TRUE(DecodeScanReply(frame, {}, &values, &error)) << error;
  EXPECT_EQ(values.count, 361);
  // Partial-scan bits set: the count must not change.
  frame.payload[2] |= 0x38;  // bit 13 partial, raster 3
  ASSERT_TRUE(DecodeScanReply(frame, {}, &values, &error)) << error;
  EXPECT_EQ(values.count, 361);
  EXPECT_TRUE(values.partial);
  EXPECT_EQ(values.partial_raster, 3);
  LaserScan scan;
  EXPECT_FALSE(ToLaserScan(values, 0, &scan, nullptr, &error));
}

TEST(Lms200TelegramsTest, ScanGeometryIsRep103WithFirstBeamOnTheRight) {
  std::vector<uint16_t> words = Words181(1234);
  Lms200MeasuredValues values;
  std::string error;
  ASSERT_TRUE(DecodeScanReply(ScanFrame(words, Lms200Unit::kMm), {}, &values, &error));
  LaserScan scan;
  ASSERT_TRUE(ToLaserScan(values, 0, &scan, nullptr, &error)) << error;
  ASSERT_EQ(scan.ranges_m.size(), 181u);
  EXPECT_NEAR(scan.angle_min_rad, -M_PI / 2, 1e-6);
  EXPECT_NEAR(scan.angle_max_rad(), M_PI / 2, 1e-5);
  EXPECT_NEAR(scan.AngleOf(90), 0.0, 1e-6);
  EXPECT_FLOAT_EQ(scan.ranges_m[0], 1.234f);
  EXPECT_NEAR(scan.range_max_m, 8.182, 1e-6);

  // 100 deg x 0.25 deg: 401 values from -50 to +50 deg.
  ASSERT_TRUE(DecodeScanReply(ScanFrame(std::vector<uint16_t>(401, 50), Lms200Unit::kCm), {},
                              &values, &error));
  ASSERT_TRUE(ToLaserScan(values, 0, &scan, nullptr, &error)) << error;
  EXPECT_NEAR(scan.angle_min_rad, -50 * M_PI / 180, 1e-6);
  EXPECT_NEAR(scan.angle_increment_rad, 0.25 * M_PI / 180, 1e-7);
  EXPECT_FLOAT_EQ(scan.ranges_m[0], 0.5f);
}

TEST(Lms200TelegramsTest, MasksDistanceByMeasuringMode) {
  struct Case {
    uint8_t mode;
    uint16_t word;
    float expected_m;
    float intensity;  // -1: no intensities
  };
  const Case cases[] = {
      {0x00, 0x8000 | 1500, 1.5f, -1},    // dazzle flag bit 15 is not part of the range
      {0x00, 0x2000 | 1500, 1.5f, -1},    // field A flag
      {0x01, 0xE000 | 1500, 1.5f, 7},     // reflector level 7 in bits 13..15
      {0x02, 0x6000 | 2500, 2.5f, -1},    // fields A and B
      {0x03, 0xC000 | 12000, 12.0f, 3},   // 16 m mode, level in bits 14..15
      {0x04, 0x4000 | 15000, 15.0f, -1},  // 16 m mode, field A
      {0x05, 0x8000 | 30000, 30.0f, 1},   // 32 m mode, 1-bit level
      {0x06, 0x8000 | 20000, 20.0f, -1},  // 32 m mode, field A
      {0x0F, 40000, 40.0f, -1},           // 16 bits, no flags
  };
  for (const Case& c : cases) {
    Lms200MeasuredValues values;
    std::string error;
    ASSERT_TRUE(DecodeScanReply(ScanFrame(Words181(c.word), Lms200Unit::kMm), {c.mode, false},
                                &values, &error));
    LaserScan scan;
    ASSERT_TRUE(ToLaserScan(values, c.mode, &scan, nullptr, &error)) << error;
    EXPECT_FLOAT_EQ(scan.ranges_m[7], c.expected_m) << "mode " << int(c.mode);
    if (c.intensity < 0) {
      EXPECT_TRUE(scan.intensities.empty()) << "mode " << int(c.mode);
    } else {
      ASSERT_EQ(scan.intensities.size(), 181u);
      EXPECT_FLOAT_EQ(scan.intensities[7], c.intensity) << "mode " << int(c.mode);
    }
  }
  Lms200MeasuredValues values;
  std::string error;
  ASSERT_TRUE(DecodeScanReply(ScanFrame(Words181(100), Lms200Unit::kMm), {}, &values, &error));
  LaserScan scan;
  EXPECT_FALSE(ToLaserScan(values, 0x3F, &scan, nullptr, &error));  // reflectivity mode
}

// Each code of TL 10.8.1 with what a scan must carry: +Inf (nothing hit up to the maximum range:
// free space) only for "no echo" and "beyond range"; NaN (unknown space) for every error code.
TEST(Lms200TelegramsTest, EachCodeDecodesToFreeOrUnknownSpace) {
  enum class Space { kFree, kUnknown };
  struct Case {
    uint16_t code_13bit;
    Lms200BeamCode expected;
    Space space;
  };
  const Case cases[] = {
      {0x1FFF, Lms200BeamCode::kNoEcho, Space::kFree},
      {0x1FFE, Lms200BeamCode::kDazzle, Space::kUnknown},
      {0x1FFD, Lms200BeamCode::kOverflow, Space::kUnknown},
      {0x1FFC, Lms200BeamCode::kOtherError, Space::kUnknown},
      {0x1FFB, Lms200BeamCode::kLowSignal, Space::kUnknown},
      {0x1FFA, Lms200BeamCode::kChannelError, Space::kUnknown},
      {0x1FF9, Lms200BeamCode::kOtherError, Space::kUnknown},
      {0x1FF8, Lms200BeamCode::kOtherError, Space::kUnknown},
      {0x1FF7, Lms200BeamCode::kBeyondRange, Space::kFree},
  };
  for (const uint8_t mode : {0x00, 0x03, 0x05, 0x0F}) {
    const uint16_t mask = DistanceMask(mode);
    for (const Case& c : cases) {
      const uint16_t code = static_cast<uint16_t>(mask - (0x1FFF - c.code_13bit));
      std::vector<uint16_t> words = Words181(1000);
      words[10] = code;
      Lms200MeasuredValues values;
      std::string error;
      ASSERT_TRUE(
          DecodeScanReply(ScanFrame(words, Lms200Unit::kMm), {mode, false}, &values, &error));
      LaserScan scan;
      Lms200BeamCounts counts;
      ASSERT_TRUE(ToLaserScan(values, mode, &scan, &counts, &error)) << error;
      const std::string what =
          std::string(BeamCodeName(c.expected)) + " in mode " + std::to_string(int(mode));
      EXPECT_EQ(ClassifyValue(code, mask), c.expected) << what;
      EXPECT_EQ(counts.by_code[static_cast<int>(c.expected)], 1u) << what;
      EXPECT_EQ(counts.by_code[static_cast<int>(Lms200BeamCode::kRange)], 180u) << what;
      EXPECT_FALSE(LaserScan::IsValidRange(scan.ranges_m[10])) << what;
      if (c.space == Space::kFree) {
        EXPECT_TRUE(std::isinf(scan.ranges_m[10]) && scan.ranges_m[10] > 0) << what;
        EXPECT_EQ(counts.invalid(), 0u) << what;
      } else {
        EXPECT_TRUE(std::isnan(scan.ranges_m[10])) << what;
        EXPECT_EQ(counts.invalid(), 1u) << what;
      }
      EXPECT_FLOAT_EQ(scan.ranges_m[9], 1.0f) << what;
      EXPECT_FLOAT_EQ(scan.ranges_m[11], 1.0f) << what;
    }
  }
  // Largest valid 13-bit value.
  EXPECT_EQ(ClassifyValue(0x1FF6, 0x1FFF), Lms200BeamCode::kRange);
}

TEST(Lms200TelegramsTest, ReadsRealTimeIndicesOnlyWhenConfigured) {
  Lms200MeasuredValues values;
  std::string error;
  const Lms200Frame with = ScanFrame(Words181(100), Lms200Unit::kCm, true);
  ASSERT_TRUE(DecodeScanReply(with, {0, true}, &values, &error)) << error;
  EXPECT_EQ(values.scan_index, 0x07);
  EXPECT_EQ(values.telegram_index, 0x2A);
  // The same telegram decoded without indices has the wrong length: an error, not garbage.
  EXPECT_FALSE(DecodeScanReply(with, {0, false}, &values, &error));
  const Lms200Frame without = ScanFrame(Words181(100), Lms200Unit::kCm);
  ASSERT_TRUE(DecodeScanReply(without, {}, &values, &error));
  EXPECT_FALSE(values.scan_index.has_value());
}

TEST(Lms200TelegramsTest, StatusByteSeverityAndPollution) {
  Lms200MeasuredValues values;
  std::string error;
  ASSERT_TRUE(
      DecodeScanReply(ScanFrame(Words181(1), Lms200Unit::kMm, false, 0x93), {}, &values, &error));
  EXPECT_EQ(values.status.severity(), 3);
  EXPECT_TRUE(values.status.is_error());
  EXPECT_TRUE(values.status.pollution());
  EXPECT_FALSE(values.status.implausible());
  Lms200StatusByte normal;
  EXPECT_FALSE(normal.is_error());
  EXPECT_FALSE(normal.implausible());
}

TEST(Lms200TelegramsTest, DecodesModeVariantTypeAndRejection) {
  std::string error;
  Lms200ModeReply mode;
  ASSERT_TRUE(DecodeModeReply(FrameOf({0x02, 0x80, 0x03, 0x00, 0xA0, 0x00, 0x10, 0x16, 0x0A}),
                              &mode, &error));
  EXPECT_TRUE(mode.ok());

  Lms200VariantReply variant;
  ASSERT_TRUE(DecodeVariantReply(
      FrameOf({0x02, 0x80, 0x07, 0x00, 0xBB, 0x01, 0xB4, 0x00, 0x32, 0x00, 0x10, 0x03, 0x9D}),
      &variant, &error));
  EXPECT_TRUE(variant.accepted);
  EXPECT_EQ(variant.variant, (Lms200Variant{180, 50}));

  const std::string type_text = "LMS200;301063;V02.10 ";
  Bytes type_wire{0x02, 0x80, 0x17, 0x00, 0xBA};
  type_wire.insert(type_wire.end(), type_text.begin(), type_text.end());
  type_wire.insert(type_wire.end(), {0x10, 0x22, 0x61});
  std::string type;
  ASSERT_TRUE(DecodeTypeReply(FrameOf(type_wire), &type, &error));
  EXPECT_EQ(type, type_text);

  const Lms200Frame rejected = FrameOf({0x02, 0x80, 0x02, 0x00, 0x92, 0x10, 0x7F, 0x33});
  EXPECT_TRUE(IsRejection(rejected));
  EXPECT_FALSE(DecodeModeReply(rejected, &mode, &error));
  EXPECT_NE(error.find("0x92"), std::string::npos);
}

TEST(Lms200TelegramsTest, DecodesConfigReadAndWriteReplies) {
  Bytes f7{0x02, 0x80, 0x25, 0x00, 0xF7, 0x01, 0x00, 0x00, 0x70,
           0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x02, 0x02};
  f7.insert(f7.end(), 21, 0x00);
  f7.insert(f7.end(), {0x02, 0x00, 0x10, 0xC5, 0x7A});
  bool accepted = false;
  Lms200ConfigBlock block;
  std::string error;
  ASSERT_TRUE(DecodeConfigWriteReply(FrameOf(f7), &accepted, &block, &error)) << error;
  EXPECT_TRUE(accepted);
  ASSERT_EQ(block.bytes.size(), 34u);
  EXPECT_EQ(block.measuring_mode(), 0x00);
  EXPECT_EQ(block.unit_code(), 0x01);  // mm in the listing's example
  EXPECT_EQ(block.bytes[2], 0x70);

  Lms200ConfigBlock wanted = block;
  wanted.set_unit(Lms200Unit::kMm);
  wanted.set_measuring_mode(0x03);
  wanted.set_real_time_indices(true);
  Bytes f4_payload = wanted.bytes;
  f4_payload.insert(f4_payload.begin(), 0xF4);
  f4_payload.push_back(0x10);
  Lms200ConfigBlock read;
  ASSERT_TRUE(DecodeConfigReply(FrameOf(BuildReplyTelegram(0x80, f4_payload)), &read, &error));
  EXPECT_EQ(read, wanted);
  EXPECT_TRUE(read.real_time_indices());
  EXPECT_EQ(read.measuring_mode(), 0x03);

  // A 33-byte block is neither firmware's layout.
  f4_payload.erase(f4_payload.begin() + 5);
  EXPECT_FALSE(DecodeConfigReply(FrameOf(BuildReplyTelegram(0x80, f4_payload)), &read, &error));

  // The write request carries the block verbatim.
  const Bytes request = WriteConfigRequest(wanted);
  ASSERT_EQ(request.size(), 1u + 34u + 6u);
  EXPECT_EQ(request[4], 0x77);
  EXPECT_EQ(Bytes(request.begin() + 5, request.end() - 2), wanted.bytes);
}

TEST(Lms200TelegramsTest, DecodesStatusReplyFields) {
  Bytes payload(1 + kLms200StatusDataBytes + 1, 0);
  payload[0] = 0xB1;
  const std::string version = "V02.10 ";
  for (size_t i = 0; i < 7; ++i) payload[1 + i] = static_cast<uint8_t>(version[i]);
  payload[8] = 0x24;
  payload[102] = 0x03;
  payload[107] = 100;
  payload[109] = 25;
  payload[116] = 0x19;
  payload[117] = 0x80;
  payload[120] = 0x00;
  payload[122] = 0x01;
  payload.back() = 0x10;
  Lms200DeviceStatus status;
  std::string error;
  ASSERT_TRUE(DecodeStatusReply(FrameOf(BuildReplyTelegram(0x80, payload)), &status, &error))
      << error;
  EXPECT_EQ(status.software_version, version);
  EXPECT_EQ(status.operating_mode, 0x24);
  EXPECT_EQ(status.measuring_mode, 0x03);
  EXPECT_EQ(status.variant, (Lms200Variant{100, 25}));
  EXPECT_EQ(status.baud, 38400);
  EXPECT_EQ(status.unit_code, 1);
  payload.resize(50);
  payload.back() = 0x10;
  EXPECT_FALSE(DecodeStatusReply(FrameOf(BuildReplyTelegram(0x80, payload)), &status, &error));
}

}  // namespace
}  // namespace mostar::laser
