#include "common/record/recording_summary.h"

#include <gtest/gtest.h>

#include "common/record/recording_writer.h"
#include "common/record/test_records.h"
#include "common/time/fake_clock.h"

namespace mostar::record {
namespace {

using std::chrono::milliseconds;
using testing::T0;

// 10 s of scans at 10 Hz with a 3 s hole from 4 s to 7 s, and commands at 2 Hz.
std::string WriteSample(const std::string& name) {
  FakeClock clock(T0());
  const std::string path = testing::TempPath(name);
  std::string error;
  auto writer = RecordingWriter::Open(path, {}, testing::MakeInfo(), clock, &error);
  EXPECT_NE(writer, nullptr) << error;
  for (int i = 0; i <= 100; ++i) {
    const Time t = T0() + milliseconds(100 * i);
    if (i <= 40 || i >= 70) writer->Write(testing::At(t, testing::MakeScan(t, 0)));
    if (i % 5 == 0) writer->Write(testing::At(t, testing::MakeCommand(t, 0)));
  }
  EXPECT_TRUE(writer->Close(&error)) << error;
  return path;
}

TEST(RecordingSummaryTest, CountsRatesSizesAndGapsPerTopic) {
  const std::string path = WriteSample("summary.mrec");
  std::string error;
  auto reader = RecordingReader::Open(path, &error);
  ASSERT_NE(reader, nullptr) << error;
  const RecordingSummary summary = SummarizeRecording(reader.get());
  EXPECT_TRUE(summary.has_footer);
  EXPECT_EQ(summary.start, T0());
  EXPECT_EQ(summary.end, T0() + milliseconds(10000));
  EXPECT_EQ(summary.duration(), milliseconds(10000));
  ASSERT_EQ(summary.topics.size(), 2u);
  const TopicSummary& scans = summary.topics.at("scan");
  EXPECT_EQ(scans.count, 72u);
  EXPECT_EQ(scans.largest_gap, milliseconds(3000));
  ASSERT_EQ(scans.long_gaps.size(), 1u);
  EXPECT_EQ(scans.long_gaps[0].from, T0() + milliseconds(4000));
  EXPECT_EQ(scans.long_gaps[0].to, T0() + milliseconds(7000));
  EXPECT_NEAR(scans.rate_hz(), 7.1, 1e-9);
  EXPECT_GT(scans.mean_bytes(), 1400.0);
  const TopicSummary& commands = summary.topics.at("cmd_vel");
  EXPECT_EQ(commands.count, 21u);
  EXPECT_NEAR(commands.rate_hz(), 2.0, 1e-9);
  EXPECT_TRUE(commands.long_gaps.empty());
  EXPECT_FALSE(summary.damage.has_value());

  const std::string text = FormatSummary(summary);
  EXPECT_NE(text.find("robot:           morduc"), std::string::npos) << text;
  EXPECT_NE(text.find("duration:        10.000 s"), std::string::npos) << text;
  EXPECT_NE(text.find("gaps in scan (1)"), std::string::npos) << text;
  EXPECT_NE(text.find("damage:          none"), std::string::npos) << text;
}

TEST(RecordingSummaryTest, ReportsDamageWithItsOffset) {
  const std::string path = WriteSample("summary_damaged.mrec");
  std::string bytes = testing::ReadFileBytes(path);
  bytes.resize(bytes.size() / 2);
  testing::WriteFileBytes(path, bytes);
  std::string error;
  auto reader = RecordingReader::Open(path, &error);
  ASSERT_NE(reader, nullptr) << error;
  const RecordingSummary summary = SummarizeRecording(reader.get());
  EXPECT_FALSE(summary.has_footer);
  ASSERT_TRUE(summary.damage.has_value());
  EXPECT_GT(summary.record_count, 0u);
  const std::string text = FormatSummary(summary);
  EXPECT_NE(text.find("at byte " + std::to_string(summary.damage->offset)), std::string::npos)
      << text;
  EXPECT_NE(text.find("closed cleanly:  no"), std::string::npos) << text;
}

}  // namespace
}  // namespace mostar::record
