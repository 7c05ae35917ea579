#include "common/record/recording_writer.h"

#include <gtest/gtest.h>

#include <condition_variable>
#include <mutex>

#include "common/record/recording_reader.h"
#include "common/record/test_records.h"
#include "common/time/fake_clock.h"

namespace mostar::record {
namespace {

using testing::T0;

// Keeps the bytes in memory; fails with "no space left" once `capacity` bytes are exceeded, and
// can hold Append() until released (to fill the writer's queue).
class MemorySink final : public ByteSink {
 public:
  struct State {
    std::mutex mutex;
    std::condition_variable released_cv;
    std::string bytes;
    size_t capacity = SIZE_MAX;
    bool hold = false;
    int syncs = 0;
    bool closed = false;
  };
  explicit MemorySink(State* state) : state_(state) {}

  bool Append(const char* data, size_t size, std::string* error) override {
    std::unique_lock<std::mutex> lock(state_->mutex);
    state_->released_cv.wait(lock, [this] { return !state_->hold; });
    const size_t room = state_->capacity - std::min(state_->capacity, state_->bytes.size());
    state_->bytes.append(data, std::min(size, room));  // a partial write, like a full disk
    if (size > room) {
      *error = "cannot write memory: no space left on device (disk full)";
      return false;
    }
    return true;
  }
  bool Sync(std::string*) override {
    std::lock_guard<std::mutex> lock(state_->mutex);
    ++state_->syncs;
    return true;
  }
  bool Truncate(uint64_t size_bytes, std::string*) override {
    std::lock_guard<std::mutex> lock(state_->mutex);
    state_->bytes.resize(static_cast<size_t>(size_bytes));
    return true;
  }
  bool Close(std::string*) override {
    std::lock_guard<std::mutex> lock(state_->mutex);
    state_->closed = true;
    return true;
  }

 private:
  State* state_;
};

std::unique_ptr<RecordingReader> ReopenBytes(const std::string& bytes, const std::string& name) {
  const std::string path = testing::TempPath(name);
  testing::WriteFileBytes(path, bytes);
  std::string error;
  auto reader = RecordingReader::Open(path, &error);
  EXPECT_NE(reader, nullptr) << error;
  return reader;
}

TEST(RecordingWriterTest, WritesEveryTypeAndReadsItBack) {
  FakeClock clock(T0());
  const std::string path = testing::TempPath("every_type.mrec");
  std::string error;
  auto writer = RecordingWriter::Open(path, {}, testing::MakeInfo(), clock, &error);
  ASSERT_NE(writer, nullptr) << error;

  CompressedStereoPair pair;
  pair.sequence = 5;
  pair.left = testing::MakeImage(Eye::kLeft, T0(), 5).image;
  pair.right = testing::MakeImage(Eye::kRight, T0(), 5).image;
  EXPECT_TRUE(writer->Write(pair));
  clock.Advance(std::chrono::milliseconds(10));
  EXPECT_TRUE(writer->Write(testing::MakeImage(Eye::kLeft, T0(), 0).image, Eye::kLeft));
  EXPECT_TRUE(writer->Write(testing::MakeScan(T0(), 1)));
  EXPECT_TRUE(writer->Write(testing::MakeOdometry(T0())));
  EXPECT_TRUE(writer->Write(testing::MakeCommand(T0(), 2)));
  EXPECT_TRUE(writer->Write(testing::MakeStop(T0())));
  EXPECT_TRUE(writer->Write(testing::MakeRequest(T0())));
  clock.Advance(std::chrono::milliseconds(10));
  EXPECT_TRUE(writer->Write(testing::MakeLease(T0())));
  EXPECT_TRUE(writer->Write(testing::MakeHealth(T0())));
  ASSERT_TRUE(writer->Close(&error)) << error;
  EXPECT_EQ(writer->stats().records_written, 10u);
  EXPECT_EQ(writer->stats().frames_dropped, 0u);

  auto reader = RecordingReader::Open(path, &error);
  ASSERT_NE(reader, nullptr) << error;
  EXPECT_TRUE(reader->has_footer());
  EXPECT_EQ(reader->info().robot_id, "morduc");
  EXPECT_EQ(reader->info().calibration_text, testing::MakeInfo().calibration_text);
  EXPECT_EQ(reader->info().metadata, testing::MakeInfo().metadata);
  std::vector<RecordedMessage> got;
  RecordedMessage message;
  while (reader->Next(&message)) got.push_back(message);
  EXPECT_FALSE(reader->damage().has_value());
  ASSERT_EQ(got.size(), 10u);
  const RecordedImage& left = std::get<RecordedImage>(got[0].payload);
  EXPECT_EQ(left.eye, Eye::kLeft);
  EXPECT_EQ(left.pair_sequence, 5u);
  EXPECT_EQ(left.image.data, pair.left.data);
  EXPECT_EQ(std::get<RecordedImage>(got[1].payload).eye, Eye::kRight);
  EXPECT_EQ(got[0].log_time, T0());
  EXPECT_EQ(got[2].log_time, T0() + std::chrono::milliseconds(10));
  EXPECT_EQ(got[9].log_time, T0() + std::chrono::milliseconds(20));
  EXPECT_EQ(testing::Serialized(got[3]),
            testing::Serialized(testing::At(got[3].log_time, testing::MakeScan(T0(), 1))));
  EXPECT_EQ(testing::Serialized(got[9]),
            testing::Serialized(testing::At(got[9].log_time, testing::MakeHealth(T0()))));
  // Offsets and sizes tile the data region.
  for (size_t i = 1; i < got.size(); ++i) {
    EXPECT_GE(got[i].offset, got[i - 1].offset + got[i - 1].size_bytes);
  }
}

TEST(RecordingWriterTest, FillsInTheCreationTimeFromTheClock) {
  FakeClock clock(T0() + std::chrono::seconds(7));
  RecordingInfo info = testing::MakeInfo();
  info.creation_time = Time{};
  const std::string path = testing::TempPath("creation.mrec");
  std::string error;
  ASSERT_NE(RecordingWriter::Open(path, {}, info, clock, &error), nullptr) << error;
  auto reader = RecordingReader::Open(path, &error);
  ASSERT_NE(reader, nullptr) << error;
  EXPECT_EQ(reader->info().creation_time, T0() + std::chrono::seconds(7));
}

TEST(RecordingWriterTest, RefusesInvalidOptions) {
  FakeClock clock;
  RecordingWriterOptions options;
  options.sync_period = Duration::zero();
  std::string error;
  EXPECT_EQ(RecordingWriter::Open(testing::TempPath("bad.mrec"), options, {}, clock, &error),
            nullptr);
  EXPECT_NE(error.find("sync_period"), std::string::npos) << error;
}

TEST(RecordingWriterTest, ReportsAFullDeviceAtOpenWithoutCrashing) {
  FakeClock clock;
  std::string error;
  auto writer = RecordingWriter::Open("/dev/full", {}, testing::MakeInfo(), clock, &error);
  EXPECT_EQ(writer, nullptr);
  EXPECT_NE(error.find("/dev/full"), std::string::npos) << error;
  EXPECT_NE(error.find("no space left"), std::string::npos) << error;
}

TEST(RecordingWriterTest, ReportsAMissingDirectory) {
  FakeClock clock;
  std::string error;
  EXPECT_EQ(RecordingWriter::Open("/nonexistent-dir/x.mrec", {}, {}, clock, &error), nullptr);
  EXPECT_NE(error.find("/nonexistent-dir/x.mrec"), std::string::npos) << error;
}

TEST(RecordingWriterTest, DiskFullMidwayKeepsEveryCompleteRecordReadable) {
  FakeClock clock(T0());
  MemorySink::State state;
  state.capacity = 4000;  // header + some records
  std::string error;
  auto writer = RecordingWriter::OpenSink(std::make_unique<MemorySink>(&state), "memory", {},
                                          testing::MakeInfo(), clock, &error);
  ASSERT_NE(writer, nullptr) << error;
  for (int i = 0; i < 50; ++i) {
    writer->Write(testing::MakeScan(T0(), static_cast<uint64_t>(i)));
    clock.Advance(std::chrono::milliseconds(27));
  }
  EXPECT_FALSE(writer->Close(&error));
  EXPECT_NE(error.find("no space left"), std::string::npos) << error;
  EXPECT_NE(error.find("readable up to byte"), std::string::npos) << error;
  const RecordingWriterStats stats = writer->stats();
  EXPECT_TRUE(stats.failed);
  EXPECT_GT(stats.records_written, 0u);
  EXPECT_LT(stats.records_written, 50u);
  EXPECT_EQ(stats.records_written + stats.records_dropped, 50u);
  EXPECT_FALSE(writer->Write(testing::MakeScan(T0(), 99)));  // after the failure: dropped

  // The partial record was cut off: the file ends on a record boundary, without damage.
  EXPECT_EQ(state.bytes.size(), stats.bytes_written);
  auto reader = ReopenBytes(state.bytes, "disk_full.mrec");
  ASSERT_NE(reader, nullptr);
  EXPECT_FALSE(reader->has_footer());
  uint64_t count = 0;
  RecordedMessage message;
  while (reader->Next(&message)) {
    EXPECT_EQ(std::get<LaserScan>(message.payload).sequence, count);
    ++count;
  }
  EXPECT_FALSE(reader->damage().has_value());
  EXPECT_EQ(count, stats.records_written);
}

TEST(RecordingWriterTest, SlowDiskDropsFramesButKeepsScansAndCommands) {
  FakeClock clock(T0());
  MemorySink::State state;
  RecordingWriterOptions options;
  options.max_queue_bytes = 1u << 20;
  std::string error;
  auto writer = RecordingWriter::OpenSink(std::make_unique<MemorySink>(&state), "memory", options,
                                          testing::MakeInfo(), clock, &error);
  ASSERT_NE(writer, nullptr) << error;
  {
    std::lock_guard<std::mutex> lock(state.mutex);
    state.hold = true;  // the disk stalls
  }
  int frames_accepted = 0;
  const int kFrames = 40;  // 40 x 200 KB = 8 MB, far above the 1 MiB queue
  for (int i = 0; i < kFrames; ++i) {
    const Time stamp = T0() + std::chrono::milliseconds(66 * i);
    if (writer->Write(testing::MakeImage(Eye::kLeft, stamp, static_cast<uint64_t>(i), 200000).image,
                      Eye::kLeft)) {
      ++frames_accepted;
    }
    EXPECT_TRUE(writer->Write(testing::MakeScan(stamp, static_cast<uint64_t>(i))));
    EXPECT_TRUE(writer->Write(testing::MakeCommand(stamp, static_cast<uint64_t>(i))));
    clock.Advance(std::chrono::milliseconds(66));
  }
  EXPECT_LE(writer->stats().queued_bytes, options.max_queue_bytes);
  {
    std::lock_guard<std::mutex> lock(state.mutex);
    state.hold = false;
  }
  state.released_cv.notify_all();
  ASSERT_TRUE(writer->Close(&error)) << error;
  const RecordingWriterStats stats = writer->stats();
  EXPECT_GT(stats.frames_dropped, 0u);
  EXPECT_EQ(stats.records_dropped, 0u);
  EXPECT_EQ(stats.records_written + stats.frames_dropped, 3u * kFrames);

  auto reader = ReopenBytes(state.bytes, "slow_disk.mrec");
  ASSERT_NE(reader, nullptr);
  EXPECT_TRUE(reader->has_footer());
  uint64_t scans = 0, commands = 0, frames = 0;
  RecordedMessage message;
  while (reader->Next(&message)) {
    switch (message.kind()) {
      case RecordKind::kScan:
        EXPECT_EQ(std::get<LaserScan>(message.payload).sequence, scans++);
        break;
      case RecordKind::kVelocityCommand:
        EXPECT_EQ(std::get<VelocityCommand>(message.payload).sequence, commands++);
        break;
      case RecordKind::kImage:
        ++frames;
        break;
      default:
        ADD_FAILURE() << "unexpected record";
    }
  }
  EXPECT_EQ(scans, static_cast<uint64_t>(kFrames));
  EXPECT_EQ(commands, static_cast<uint64_t>(kFrames));
  EXPECT_EQ(frames + stats.frames_dropped, static_cast<uint64_t>(kFrames));
  EXPECT_LE(frames, static_cast<uint64_t>(frames_accepted));
}

TEST(RecordingWriterTest, WritesPeriodicIndexRecordsAndSyncsOnClose) {
  FakeClock clock(T0());
  MemorySink::State state;
  RecordingWriterOptions options;
  options.index_period = std::chrono::seconds(1);
  options.index_record_period = std::chrono::seconds(5);
  std::string error;
  auto writer = RecordingWriter::OpenSink(std::make_unique<MemorySink>(&state), "memory", options,
                                          testing::MakeInfo(), clock, &error);
  ASSERT_NE(writer, nullptr) << error;
  for (int i = 0; i < 300; ++i) {  // 30 s at 10 Hz
    writer->Write(testing::MakeOdometry(clock.Now()));
    clock.Advance(std::chrono::milliseconds(100));
  }
  ASSERT_TRUE(writer->Close(&error)) << error;
  EXPECT_TRUE(state.closed);
  EXPECT_GE(state.syncs, 2);  // header and close

  auto reader = ReopenBytes(state.bytes, "periodic_index.mrec");
  ASSERT_NE(reader, nullptr);
  ASSERT_TRUE(reader->has_footer());
  EXPECT_EQ(reader->index().size(), 30u);
  RecordedMessage message;
  uint64_t count = 0;
  while (reader->Next(&message)) ++count;
  EXPECT_EQ(count, 300u);
  EXPECT_GE(reader->index_records_seen(), 5u);
}

TEST(RecordingWriterTest, CloseIsIdempotentAndLaterWritesAreDropped) {
  FakeClock clock(T0());
  const std::string path = testing::TempPath("close_twice.mrec");
  std::string error;
  auto writer = RecordingWriter::Open(path, {}, testing::MakeInfo(), clock, &error);
  ASSERT_NE(writer, nullptr) << error;
  EXPECT_TRUE(writer->Write(testing::MakeScan(T0(), 1)));
  EXPECT_TRUE(writer->Close());
  EXPECT_TRUE(writer->Close());
  EXPECT_FALSE(writer->Write(testing::MakeScan(T0(), 2)));
  EXPECT_EQ(writer->stats().records_dropped, 1u);
}

}  // namespace
}  // namespace mostar::record
