#include "common/record/recording_reader.h"

#include <gtest/gtest.h>

#include "common/record/recording_writer.h"
#include "common/record/test_records.h"
#include "common/time/fake_clock.h"

namespace mostar::record {
namespace {

using std::chrono::milliseconds;
using testing::T0;

// Writes `messages` with the writer and returns the file's bytes.
std::string WriteRecording(const std::vector<RecordedMessage>& messages, const std::string& name,
                           RecordingWriterOptions options = {}) {
  FakeClock clock(T0());
  const std::string path = testing::TempPath(name);
  std::string error;
  auto writer = RecordingWriter::Open(path, options, testing::MakeInfo(), clock, &error);
  EXPECT_NE(writer, nullptr) << error;
  if (writer == nullptr) return "";
  for (const RecordedMessage& m : messages) EXPECT_TRUE(writer->Write(m));
  EXPECT_TRUE(writer->Close(&error)) << error;
  return testing::ReadFileBytes(path);
}

std::unique_ptr<RecordingReader> OpenBytes(const std::string& bytes, const std::string& name,
                                           std::string* error) {
  const std::string path = testing::TempPath(name);
  testing::WriteFileBytes(path, bytes);
  return RecordingReader::Open(path, error);
}

std::vector<RecordedMessage> ReadAll(RecordingReader* reader) {
  std::vector<RecordedMessage> out;
  RecordedMessage message;
  while (reader->Next(&message)) out.push_back(message);
  return out;
}

// Start offsets of every frame after the header, plus the trailer and the end of the file.
std::vector<uint64_t> UnitBoundaries(const std::string& bytes, uint64_t data_begin) {
  std::vector<uint64_t> starts;
  uint64_t offset = data_begin;
  const uint64_t frames_end = bytes.size() - kTrailerSize;
  while (offset < frames_end) {
    starts.push_back(offset);
    uint64_t length = 0;
    const int used = ParseVarint(reinterpret_cast<const uint8_t*>(bytes.data()) + offset,
                                 bytes.size() - offset, &length);
    offset += static_cast<uint64_t>(used) + length + 4;
  }
  EXPECT_EQ(offset, frames_end);
  starts.push_back(frames_end);    // the trailer
  starts.push_back(bytes.size());  // the end
  return starts;
}

// A sequence of small records of several kinds, 100 ms apart.
std::vector<RecordedMessage> SmallRecording(int count) {
  std::vector<RecordedMessage> messages;
  for (int i = 0; i < count; ++i) {
    const Time t = T0() + milliseconds(100 * i);
    switch (i % 4) {
      case 0:
        messages.push_back(testing::At(t, testing::MakeOdometry(t)));
        break;
      case 1:
        messages.push_back(testing::At(t, testing::MakeCommand(t, static_cast<uint64_t>(i))));
        break;
      case 2:
        messages.push_back(testing::At(t, testing::MakeImage(Eye::kLeft, t, 1, 16)));
        break;
      default:
        messages.push_back(testing::At(t, testing::MakeLease(t)));
        break;
    }
  }
  return messages;
}

TEST(RecordingReaderTest, RefusesAMissingFile) {
  std::string error;
  EXPECT_EQ(RecordingReader::Open(testing::TempPath("does_not_exist.mrec"), &error), nullptr);
  EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
}

TEST(RecordingReaderTest, RefusesAnEmptyFile) {
  std::string error;
  EXPECT_EQ(OpenBytes("", "empty.mrec", &error), nullptr);
  EXPECT_NE(error.find("empty"), std::string::npos) << error;
}

TEST(RecordingReaderTest, RefusesWrongMagic) {
  std::string bytes = WriteRecording(SmallRecording(3), "magic_src.mrec");
  bytes[0] = 'X';
  std::string error;
  EXPECT_EQ(OpenBytes(bytes, "magic.mrec", &error), nullptr);
  EXPECT_NE(error.find("not a mostar recording"), std::string::npos) << error;
  EXPECT_EQ(OpenBytes("hello world, this is text", "text.mrec", &error), nullptr);
  EXPECT_NE(error.find("not a mostar recording"), std::string::npos) << error;
}

TEST(RecordingReaderTest, RefusesANewerFormatVersionNamingBoth) {
  std::string bytes = WriteRecording(SmallRecording(3), "version_src.mrec");
  bytes[kMagicSize] = static_cast<char>(kFormatVersion + 1);
  std::string error;
  EXPECT_EQ(OpenBytes(bytes, "version.mrec", &error), nullptr);
  EXPECT_NE(error.find("format version " + std::to_string(kFormatVersion + 1)), std::string::npos)
      << error;
  EXPECT_NE(error.find("version " + std::to_string(kFormatVersion) + ")"), std::string::npos)
      << error;
  EXPECT_NE(error.find("newer"), std::string::npos) << error;
}

TEST(RecordingReaderTest, DeliversAPrefixAndTheRightOffsetWhenTruncatedAnywhere) {
  const std::vector<RecordedMessage> originals = SmallRecording(12);
  RecordingWriterOptions options;
  options.index_record_period = std::chrono::seconds(1);  // include periodic index records
  const std::string bytes = WriteRecording(originals, "truncate_src.mrec", options);
  std::string error;
  auto full = OpenBytes(bytes, "truncate_full.mrec", &error);
  ASSERT_NE(full, nullptr) << error;
  const uint64_t data_begin = full->data_begin();
  const std::vector<RecordedMessage> all = ReadAll(full.get());
  ASSERT_EQ(all.size(), originals.size());
  const std::vector<uint64_t> units = UnitBoundaries(bytes, data_begin);

  for (size_t cut = 0; cut <= bytes.size(); ++cut) {
    SCOPED_TRACE("cut at " + std::to_string(cut));
    auto reader = OpenBytes(bytes.substr(0, cut), "truncated.mrec", &error);
    if (cut < data_begin) {
      EXPECT_EQ(reader, nullptr);
      EXPECT_FALSE(error.empty());
      continue;
    }
    ASSERT_NE(reader, nullptr) << error;
    EXPECT_EQ(reader->has_footer(), cut == bytes.size());
    const std::vector<RecordedMessage> got = ReadAll(reader.get());
    // Delivered: exactly the records that end at or before the cut, unchanged.
    size_t expected = 0;
    while (expected < all.size() && all[expected].offset + all[expected].size_bytes <= cut) {
      ++expected;
    }
    ASSERT_EQ(got.size(), expected);
    for (size_t i = 0; i < got.size(); ++i) {
      EXPECT_EQ(testing::Serialized(got[i]), testing::Serialized(originals[i]));
    }
    // Damage: at the start of the unit the cut falls into, none on a boundary.
    auto after = std::upper_bound(units.begin(), units.end(), cut);
    const uint64_t unit_start = *std::prev(after);
    if (unit_start == cut) {
      EXPECT_FALSE(reader->damage().has_value()) << reader->damage()->reason;
    } else {
      ASSERT_TRUE(reader->damage().has_value());
      EXPECT_EQ(reader->damage()->offset, unit_start) << reader->damage()->reason;
    }
  }
}

TEST(RecordingReaderTest, CatchesEveryFlippedBitAfterTheHeader) {
  const std::vector<RecordedMessage> originals = SmallRecording(6);
  const std::string bytes = WriteRecording(originals, "flip_src.mrec");
  std::string error;
  auto full = OpenBytes(bytes, "flip_full.mrec", &error);
  ASSERT_NE(full, nullptr) << error;
  const uint64_t data_begin = full->data_begin();
  const std::vector<RecordedMessage> all = ReadAll(full.get());
  const std::vector<uint64_t> units = UnitBoundaries(bytes, data_begin);

  for (size_t i = 0; i < bytes.size(); ++i) {
    SCOPED_TRACE("flip in byte " + std::to_string(i));
    std::string damaged = bytes;
    damaged[i] = static_cast<char>(damaged[i] ^ (1 << (i % 8)));
    auto reader = OpenBytes(damaged, "flipped.mrec", &error);
    if (i < data_begin) {
      EXPECT_EQ(reader, nullptr);  // prelude and header: refused with a message
      EXPECT_FALSE(error.empty());
      continue;
    }
    ASSERT_NE(reader, nullptr) << error;
    const std::vector<RecordedMessage> got = ReadAll(reader.get());
    ASSERT_TRUE(reader->damage().has_value());
    const uint64_t unit_start = *std::prev(std::upper_bound(units.begin(), units.end(), i));
    EXPECT_EQ(reader->damage()->offset, unit_start) << reader->damage()->reason;
    ASSERT_LE(got.size(), all.size());
    for (size_t k = 0; k < got.size(); ++k) {
      EXPECT_EQ(testing::Serialized(got[k]), testing::Serialized(originals[k]));
      EXPECT_LT(got[k].offset, unit_start);
    }
  }
}

TEST(RecordingReaderTest, ReportsCrcMismatchAsTheReason) {
  const std::vector<RecordedMessage> originals = SmallRecording(4);
  std::string bytes = WriteRecording(originals, "crc_src.mrec");
  std::string error;
  auto full = OpenBytes(bytes, "crc_full.mrec", &error);
  ASSERT_NE(full, nullptr);
  const std::vector<RecordedMessage> all = ReadAll(full.get());
  bytes[all[2].offset + all[2].size_bytes / 2] ^= 0x10;
  auto reader = OpenBytes(bytes, "crc.mrec", &error);
  ASSERT_NE(reader, nullptr) << error;
  EXPECT_EQ(ReadAll(reader.get()).size(), 2u);
  ASSERT_TRUE(reader->damage().has_value());
  EXPECT_EQ(reader->damage()->offset, all[2].offset);
  EXPECT_NE(reader->damage()->reason.find("CRC mismatch"), std::string::npos);
}

TEST(RecordingReaderTest, StopsAtAZeroedTail) {
  const std::vector<RecordedMessage> originals = SmallRecording(4);
  std::string bytes = WriteRecording(originals, "zero_src.mrec");
  std::string error;
  auto full = OpenBytes(bytes, "zero_full.mrec", &error);
  ASSERT_NE(full, nullptr);
  const std::vector<RecordedMessage> all = ReadAll(full.get());
  // A crash on some file systems leaves zeros where the last writes were.
  const uint64_t end = all[3].offset;
  bytes = bytes.substr(0, end) + std::string(4096, '\0');
  auto reader = OpenBytes(bytes, "zero.mrec", &error);
  ASSERT_NE(reader, nullptr) << error;
  EXPECT_EQ(ReadAll(reader.get()).size(), 3u);
  ASSERT_TRUE(reader->damage().has_value());
  EXPECT_EQ(reader->damage()->offset, end);
  EXPECT_NE(reader->damage()->reason.find("length 0"), std::string::npos);
}

// Seeking: every record 100 ms apart over 30 s; index entries every second.
class RecordingSeekTest : public ::testing::TestWithParam<bool> {};

TEST_P(RecordingSeekTest, FindsTheFirstRecordAtOrAfterATime) {
  const bool with_footer = GetParam();
  const std::vector<RecordedMessage> originals = SmallRecording(300);
  std::string bytes = WriteRecording(originals, "seek_src.mrec");
  std::string error;
  if (!with_footer) {
    auto full = OpenBytes(bytes, "seek_full.mrec", &error);
    ASSERT_NE(full, nullptr);
    const std::vector<RecordedMessage> all = ReadAll(full.get());
    bytes.resize(all.back().offset + all.back().size_bytes);  // crashed before Close()
  }
  auto reader = OpenBytes(bytes, "seek.mrec", &error);
  ASSERT_NE(reader, nullptr) << error;
  EXPECT_EQ(reader->has_footer(), with_footer);
  EXPECT_GE(reader->index().size(), 29u);

  for (int64_t ms : {-5000, 0, 1, 99, 100, 2550, 9999, 10000, 17321, 29800, 29900}) {
    SCOPED_TRACE(ms);
    ASSERT_TRUE(reader->SeekToTime(T0() + milliseconds(ms)));
    RecordedMessage message;
    ASSERT_TRUE(reader->Next(&message));
    const int64_t expected_ms = ms <= 0 ? 0 : (ms + 99) / 100 * 100;
    EXPECT_EQ(message.log_time, T0() + milliseconds(expected_ms));
    EXPECT_EQ(testing::Serialized(message), testing::Serialized(originals[expected_ms / 100]));
    // Reading continues in order from there.
    RecordedMessage following;
    if (expected_ms < 29900) {
      ASSERT_TRUE(reader->Next(&following));
      EXPECT_EQ(following.log_time, message.log_time + milliseconds(100));
    }
  }
  EXPECT_FALSE(reader->SeekToTime(T0() + std::chrono::seconds(31)));
  RecordedMessage message;
  EXPECT_FALSE(reader->Next(&message));
  ASSERT_TRUE(reader->SeekToTime(Time::min()));  // rewinds
  ASSERT_TRUE(reader->Next(&message));
  EXPECT_EQ(message.log_time, T0());
}

INSTANTIATE_TEST_SUITE_P(WithAndWithoutFooter, RecordingSeekTest, ::testing::Bool());

TEST(RecordingReaderTest, SeeksBeforeDamageInAFileWithoutFooter) {
  const std::vector<RecordedMessage> originals = SmallRecording(100);
  std::string bytes = WriteRecording(originals, "seek_damage_src.mrec");
  std::string error;
  auto full = OpenBytes(bytes, "seek_damage_full.mrec", &error);
  ASSERT_NE(full, nullptr);
  const std::vector<RecordedMessage> all = ReadAll(full.get());
  bytes.resize(all.back().offset + all.back().size_bytes);  // no footer
  bytes[all[60].offset + 3] ^= 0x01;
  auto reader = OpenBytes(bytes, "seek_damage.mrec", &error);
  ASSERT_NE(reader, nullptr) << error;
  EXPECT_FALSE(reader->has_footer());
  ASSERT_TRUE(reader->SeekToTime(T0() + milliseconds(2000)));
  RecordedMessage message;
  int count = 0;
  while (reader->Next(&message)) ++count;
  EXPECT_EQ(count, 40);  // records 20..59
  ASSERT_TRUE(reader->damage().has_value());
  EXPECT_EQ(reader->damage()->offset, all[60].offset);
  EXPECT_FALSE(reader->SeekToTime(T0() + milliseconds(7000)));  // beyond the damage
  reader->Rewind();
  EXPECT_FALSE(reader->damage().has_value());
}

}  // namespace
}  // namespace mostar::record
