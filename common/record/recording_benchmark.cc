// Throughput of the recording path: serializing + framing records, and reading them back.
#include <benchmark/benchmark.h>

#include "common/record/record_conversions.h"
#include "common/record/recording_reader.h"
#include "common/record/recording_writer.h"
#include "common/record/test_records.h"
#include "common/time/fake_clock.h"

namespace mostar::record {
namespace {

void BM_FrameJpegEye(benchmark::State& state) {
  const RecordedMessage message = testing::At(
      testing::T0(),
      testing::MakeImage(Eye::kLeft, testing::T0(), 1, static_cast<size_t>(state.range(0))));
  std::string frame;
  for (auto _ : state) {
    proto::Record record;
    ToProto(message, &record);
    frame.clear();
    AppendFrame(record.SerializeAsString(), &frame);
    benchmark::DoNotOptimize(frame.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * state.range(0));
}
BENCHMARK(BM_FrameJpegEye)->Arg(30000)->Arg(120000);

void BM_ReadScans(benchmark::State& state) {
  FakeClock clock(testing::T0());
  const std::string path = testing::TempPath("benchmark.mrec");
  std::string error;
  {
    auto writer = RecordingWriter::Open(path, {}, testing::MakeInfo(), clock, &error);
    for (int i = 0; i < 1000; ++i) {
      writer->Write(testing::MakeScan(clock.Now(), static_cast<uint64_t>(i)));
      clock.Advance(std::chrono::milliseconds(27));
    }
  }
  for (auto _ : state) {
    auto reader = RecordingReader::Open(path, &error);
    RecordedMessage message;
    int64_t count = 0;
    while (reader->Next(&message)) ++count;
    benchmark::DoNotOptimize(count);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * 1000);
}
BENCHMARK(BM_ReadScans);

}  // namespace
}  // namespace mostar::record
