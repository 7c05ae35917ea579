// lms200_rate_bench: achieved scan rate of the driver against the pty emulator, compared with
// the wire ceiling (10 bits per byte) and the mirror-quantised ceiling (a scan leaves only at
// the end of a mirror turn when the line is free), times the share of telegrams sent intact
// when line faults are injected. The emulator powers up at 9600 Bd; the driver switches it.
// `valid` counts the scan telegrams the emulator sent intact in the measured window,
// `delivered` the scans the driver handed over in it, `lost` the valid ones of the window the
// driver never handed over (scans are numbered by the range source; a second of grace after
// the window lets a driver that lags behind catch up).
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <set>
#include <thread>

#include "robot_server/laser/lms200_scanner.h"
#include "robot_server/laser/serial_byte_stream.h"
#include "robot_server/sim/lms200_emulator/lms200_pty.h"

namespace {

struct Row {
  int baud;
  mostar::laser::Lms200Variant variant;
  double garbage_rate = 0, crc_error_rate = 0, truncate_rate = 0;
};

struct Measured {
  double hz = 0;
  long valid = 0, delivered = 0, lost = 0;
};

Measured Measure(const Row& row, double seconds_to_measure) {
  using namespace mostar;
  sim::Lms200EmulatorOptions options;  // powers up at 9600 Bd
  options.variant = row.variant;
  options.garbage_rate = row.garbage_rate;
  options.crc_error_rate = row.crc_error_rate;
  options.truncate_rate = row.truncate_rate;
  sim::NumberedRangeSource numbered;
  sim::Lms200Emulator emulator(options, &numbered, std::chrono::steady_clock::now());
  char dir[] = "/tmp/lms200_bench_XXXXXX";
  const std::string link = std::string(mkdtemp(dir)) + "/lms200";
  sim::Lms200PtyRunner runner(&emulator, link);
  std::string error;
  if (!runner.Start(&error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return {};
  }
  laser::Lms200Config config;
  config.set_port(link);
  config.set_baud(row.baud);
  config.set_rs422(row.baud == 500000);
  config.set_angle_deg(row.variant.angle_deg);
  config.set_resolution_cdeg(row.variant.resolution_cdeg);
  std::atomic<int> scans{0};
  std::mutex mutex;
  std::set<uint64_t> numbers;  // of the scans delivered
  laser::Lms200Scanner scanner(std::make_unique<laser::SerialByteStream>(link, row.baud),
                               &SystemClock::Instance(), config);
  scanner.Start(
      [&](const LaserScan& scan) {
        std::lock_guard<std::mutex> lock(mutex);
        numbers.insert(sim::NumberedRangeSource::Number(scan.ranges_m));
        ++scans;
      },
      &error);
  // Wait for streaming, then count.
  for (int i = 0; i < 200 && scans.load() == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const int start = scans.load();
  const auto t0 = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds_to_measure));
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const int counted = scans.load() - start;
  const auto t1 = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::seconds(1));
  Measured m;
  m.hz = counted / elapsed;
  m.delivered = counted;
  std::lock_guard<std::mutex> lock(mutex);
  for (const auto& scan : emulator.IntactScans()) {
    if (scan.done < t0 || scan.done >= t1) continue;
    ++m.valid;
    m.lost += numbers.count(scan.id % sim::NumberedRangeSource::kModulus) == 0;
  }
  scanner.Stop();
  runner.Stop();
  ::rmdir(dir);
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 3.0;
  const Row rows[] = {{38400, {180, 100}},
                      {38400, {180, 50}},
                      {500000, {180, 100}},
                      {500000, {180, 50}},
                      {500000, {180, 100}, 0.05, 0.02, 0.01},
                      {500000, {180, 100}, 0.1, 0.1, 0.05}};
  std::printf("%8s %9s %17s %7s %9s %9s %9s %7s %9s %7s %5s\n", "baud", "variant", "faults g/c/t",
              "bytes", "wire_hz", "cap_hz", "achieved", "%cap", "delivered", "valid", "lost");
  for (const Row& row : rows) {
    const int bytes = 2 * row.variant.values() + 10;
    const double wire_s = bytes * 10.0 / row.baud;
    const double mirror_s = mostar::laser::kLms200MirrorPeriodS * row.variant.revolutions();
    const double wire_hz = std::min(1.0 / wire_s, 1.0 / mirror_s);
    const double turns = std::max(1.0, std::ceil(wire_s / mirror_s));
    const double intact = (1 - row.crc_error_rate) * (1 - row.truncate_rate);
    const double cap_hz = intact / (turns * mirror_s);
    const Measured m = Measure(row, seconds);
    std::printf("%8d %5dx%-3d %5.2f/%4.2f/%4.2f %7d %9.2f %9.2f %9.2f %6.1f%% %9ld %7ld %5ld\n",
                row.baud, row.variant.angle_deg, row.variant.resolution_cdeg, row.garbage_rate,
                row.crc_error_rate, row.truncate_rate, bytes, wire_hz, cap_hz, m.hz,
                100 * m.hz / cap_hz, m.delivered, m.valid, m.lost);
  }
  return 0;
}
