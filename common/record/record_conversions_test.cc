#include "common/record/record_conversions.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/record/test_records.h"

namespace mostar::record {
namespace {

using testing::OneOfEach;
using testing::T0;

TEST(Crc32Test, MatchesTheStandardCheckValue) {
  const std::string text = "123456789";
  EXPECT_EQ(Crc32(text.data(), text.size()), 0xCBF43926u);
  EXPECT_EQ(Crc32(nullptr, 0), 0u);
}

TEST(Crc32Test, ContinuesAcrossChunks) {
  const std::string text = "mostar recording";
  EXPECT_EQ(Crc32(text.data() + 6, text.size() - 6, Crc32(text.data(), 6)),
            Crc32(text.data(), text.size()));
}

TEST(FrameTest, VarintRoundTripsAndRejectsOverlongPrefixes) {
  for (uint64_t length : {0ull, 1ull, 127ull, 128ull, 300ull, 16383ull, 16384ull, 100000ull}) {
    std::string frame;
    AppendFrame(std::string(length, 'x'), &frame);
    uint64_t parsed = 0;
    const int used =
        ParseVarint(reinterpret_cast<const uint8_t*>(frame.data()), frame.size(), &parsed);
    ASSERT_GT(used, 0);
    EXPECT_EQ(parsed, length);
    EXPECT_EQ(frame.size(), static_cast<size_t>(used) + length + 4);
  }
  const uint8_t large[6] = {0x80, 0x80, 0x80, 0x80, 0x80, 0x20};
  uint64_t large_value = 0;
  EXPECT_EQ(ParseVarint(large, sizeof(large), &large_value), 6);
  EXPECT_EQ(large_value, 1ull << 40);
  const uint8_t overlong[11] = {0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x01};
  uint64_t value = 0;
  EXPECT_EQ(ParseVarint(overlong, sizeof(overlong), &value), -1);
  const uint8_t cut[2] = {0x80, 0x80};
  EXPECT_EQ(ParseVarint(cut, sizeof(cut), &value), 0);
}

TEST(FrameTest, EndsWithTheCrcOfTheRecordBytes) {
  std::string frame;
  AppendFrame("abc", &frame);
  ASSERT_EQ(frame.size(), 1u + 3u + 4u);
  EXPECT_EQ(frame[0], 3);
  const uint32_t crc = Crc32("abc", 3);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(static_cast<uint8_t>(frame[4 + static_cast<size_t>(i)]), (crc >> (8 * i)) & 0xFFu);
  }
}

TEST(RecordConversionsTest, EveryRecordKindRoundTrips) {
  const std::vector<RecordedMessage> messages = OneOfEach(T0(), std::chrono::milliseconds(10));
  ASSERT_EQ(messages.size(), kRecordKindCount + 1);  // both eyes
  for (const RecordedMessage& original : messages) {
    proto::Record record;
    ToProto(original, &record);
    proto::Record parsed;
    ASSERT_TRUE(parsed.ParseFromString(record.SerializeAsString()));
    RecordedMessage back;
    ASSERT_EQ(FromProto(parsed, &back), FromProtoResult::kOk) << TopicName(original);
    EXPECT_EQ(back.log_time, original.log_time);
    EXPECT_EQ(back.kind(), original.kind());
    EXPECT_EQ(testing::Serialized(back), testing::Serialized(original)) << TopicName(original);
  }
}

TEST(RecordConversionsTest, ScanKeepsInvalidBeamsBitForBit) {
  const LaserScan scan = testing::MakeScan(T0(), 4);
  proto::Record record;
  ToProto(testing::At(T0(), scan), &record);
  RecordedMessage back;
  ASSERT_EQ(FromProto(record, &back), FromProtoResult::kOk);
  const LaserScan& got = std::get<LaserScan>(back.payload);
  ASSERT_EQ(got.ranges_m.size(), scan.ranges_m.size());
  EXPECT_TRUE(std::isnan(got.ranges_m[3]));
  EXPECT_TRUE(std::isinf(got.ranges_m[4]));
  EXPECT_EQ(got.ranges_m[10], scan.ranges_m[10]);
  EXPECT_EQ(got.stamp, scan.stamp);
  EXPECT_EQ(got.intensities, scan.intensities);
}

TEST(RecordConversionsTest, HealthFieldsSurvive) {
  const RobotHealth health = testing::MakeHealth(T0());
  proto::Record record;
  ToProto(testing::At(T0(), health), &record);
  RecordedMessage back;
  ASSERT_EQ(FromProto(record, &back), FromProtoResult::kOk);
  const RobotHealth& got = std::get<RobotHealth>(back.payload);
  ASSERT_EQ(got.devices.size(), 1u);
  EXPECT_EQ(got.devices[0].state, DeviceState::kWarn);
  EXPECT_EQ(got.devices[0].counters, health.devices[0].counters);
  EXPECT_EQ(got.watchdog_state, WatchdogState::kDriving);
  EXPECT_EQ(got.last_command_sequence, 77u);
}

TEST(RecordConversionsTest, UnknownHealthStatesMapToSafeValues) {
  proto::Record record;
  record.set_log_time_unix_ns(1);
  record.mutable_health()->add_devices()->set_state(99);
  record.mutable_health()->set_watchdog_state(42);
  RecordedMessage back;
  ASSERT_EQ(FromProto(record, &back), FromProtoResult::kOk);
  const RobotHealth& got = std::get<RobotHealth>(back.payload);
  EXPECT_EQ(got.devices[0].state, DeviceState::kError);
  EXPECT_EQ(got.watchdog_state, WatchdogState::kIdle);
}

TEST(RecordConversionsTest, IndexAndEmptyRecordsAreNotData) {
  proto::Record index;
  index.mutable_index()->set_footer(true);
  RecordedMessage message;
  EXPECT_EQ(FromProto(index, &message), FromProtoResult::kIndex);
  proto::Record empty;
  empty.set_log_time_unix_ns(5);
  EXPECT_EQ(FromProto(empty, &message), FromProtoResult::kUnknown);
}

TEST(RecordConversionsTest, HeaderRoundTrips) {
  const RecordingInfo info = testing::MakeInfo();
  proto::Header header;
  ToProto(info, &header);
  EXPECT_EQ(header.format_version(), kFormatVersion);
  RecordingInfo back;
  FromProto(header, &back);
  EXPECT_EQ(back.creation_time, info.creation_time);
  EXPECT_EQ(back.robot_id, info.robot_id);
  EXPECT_EQ(back.calibration_text, info.calibration_text);
  EXPECT_EQ(back.metadata, info.metadata);
  EXPECT_EQ(back.sensors.laser_beam_count, 181u);
  EXPECT_EQ(back.sensors.camera_width_px, 640u);
  EXPECT_EQ(back.sensors.camera_format, "jpeg");
}

TEST(RecordConversionsTest, SonarKeepsNoEchoAndFailedReadingsBitForBit) {
  const SonarRanges sonar = testing::MakeSonar(T0());
  proto::Record record;
  ToProto(testing::At(T0(), sonar), &record);
  RecordedMessage back;
  ASSERT_EQ(FromProto(record, &back), FromProtoResult::kOk);
  const SonarRanges& got = std::get<SonarRanges>(back.payload);
  ASSERT_EQ(got.ranges.size(), 3u);
  EXPECT_EQ(got.ranges[0].range_m, 1.25f);
  EXPECT_TRUE(std::isinf(got.ranges[1].range_m));
  EXPECT_TRUE(std::isnan(got.ranges[2].range_m));
  EXPECT_EQ(got.ranges[2].mount.frame_id, "sonar_2");
  EXPECT_EQ(got.ranges[1].stamp, T0() + std::chrono::milliseconds(65));
}

TEST(RecordConversionsTest, TopicNamesFollowTheDdsTopics) {
  const std::vector<RecordedMessage> messages = OneOfEach(T0(), std::chrono::milliseconds(10));
  std::vector<std::string> names;
  for (const RecordedMessage& m : messages) names.push_back(TopicName(m));
  EXPECT_EQ(names, (std::vector<std::string>{"camera/left", "camera/right", "scan", "odom",
                                             "cmd_vel", "estop", "control/request", "control/lease",
                                             "health", "sonar", "bumpers"}));
}

}  // namespace
}  // namespace mostar::record
