// Decode cost per LMS200 scan: framing (CRC included), B0 decoding and conversion to metres.
#include <benchmark/benchmark.h>

#include <vector>

#include "robot_server/laser/lms200_framer.h"
#include "robot_server/laser/lms200_telegrams.h"

namespace mostar::laser {
namespace {

std::vector<uint8_t> ScanTelegram(int count) {
  std::vector<uint8_t> payload{0xB0, static_cast<uint8_t>(count & 0xFF),
                               static_cast<uint8_t>((count >> 8) | 0x40)};
  for (int i = 0; i < count; ++i) {
    const uint16_t v = static_cast<uint16_t>(1000 + 7 * i);
    payload.push_back(static_cast<uint8_t>(v & 0xFF));
    payload.push_back(static_cast<uint8_t>(v >> 8));
  }
  payload.push_back(0x10);
  return BuildReplyTelegram(0x80, payload);
}

void BM_FrameAndDecodeScan(benchmark::State& state) {
  const std::vector<uint8_t> wire = ScanTelegram(static_cast<int>(state.range(0)));
  Lms200Framer framer;
  std::vector<FramerEvent> events;
  Lms200MeasuredValues values;
  LaserScan scan;
  std::string error;
  for (auto _ : state) {
    events.clear();
    framer.Push(wire.data(), wire.size(), &events);
    DecodeScanReply(events[0].frame, {}, &values, &error);
    ToLaserScan(values, 0, &scan, nullptr, &error);
    benchmark::DoNotOptimize(scan.ranges_m.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * wire.size()));
}
BENCHMARK(BM_FrameAndDecodeScan)->Arg(181)->Arg(361)->Arg(401);

void BM_FrameOnlyInSmallChunks(benchmark::State& state) {
  const std::vector<uint8_t> wire = ScanTelegram(361);
  Lms200Framer framer;
  std::vector<FramerEvent> events;
  for (auto _ : state) {
    events.clear();
    for (size_t pos = 0; pos < wire.size(); pos += 32) {
      framer.Push(wire.data() + pos, std::min<size_t>(32, wire.size() - pos), &events);
    }
    benchmark::DoNotOptimize(events.data());
  }
}
BENCHMARK(BM_FrameOnlyInSmallChunks);

}  // namespace
}  // namespace mostar::laser
