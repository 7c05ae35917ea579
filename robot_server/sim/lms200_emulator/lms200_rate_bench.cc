// lms200_rate_bench: achieved scan rate of the driver against the pty emulator, compared with
// the wire ceiling (10 bits per byte) and the mirror-quantised ceiling (a scan leaves only at
// the end of a mirror turn when the line is free).
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <thread>

#include "robot_server/laser/lms200_scanner.h"
#include "robot_server/laser/serial_byte_stream.h"
#include "robot_server/sim/lms200_emulator/lms200_pty.h"

namespace {

struct Row {
  int baud;
  mostar::laser::Lms200Variant variant;
};

double MeasureHz(const Row& row, double seconds_to_measure) {
  using namespace mostar;
  sim::Lms200EmulatorOptions options;
  options.initial_baud = row.baud;
  options.variant = row.variant;
  sim::RoomRangeSource room(10, 6, 5, 3);
  sim::Lms200Emulator emulator(options, &room, std::chrono::steady_clock::now());
  char dir[] = "/tmp/lms200_bench_XXXXXX";
  const std::string link = std::string(mkdtemp(dir)) + "/lms200";
  sim::Lms200PtyRunner runner(&emulator, link);
  std::string error;
  if (!runner.Start(&error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 0;
  }
  laser::Lms200Config config;
  config.set_port(link);
  config.set_baud(row.baud);
  config.set_rs422(row.baud == 500000);
  config.set_angle_deg(row.variant.angle_deg);
  config.set_resolution_cdeg(row.variant.resolution_cdeg);
  std::atomic<int> scans{0};
  laser::Lms200Scanner scanner(std::make_unique<laser::SerialByteStream>(link, row.baud),
                               &SystemClock::Instance(), config);
  scanner.Start([&](const LaserScan&) { ++scans; }, &error);
  // Wait for streaming, then count.
  for (int i = 0; i < 100 && scans.load() == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const int start = scans.load();
  const auto t0 = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds_to_measure));
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const int counted = scans.load() - start;
  scanner.Stop();
  runner.Stop();
  ::rmdir(dir);
  return counted / elapsed;
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 3.0;
  const Row rows[] = {
      {38400, {180, 100}}, {38400, {180, 50}}, {500000, {180, 100}}, {500000, {180, 50}}};
  std::printf("%8s %9s %7s %12s %14s %10s %8s %8s\n", "baud", "variant", "bytes", "wire_hz",
              "mirror_cap_hz", "achieved", "%wire", "%cap");
  for (const Row& row : rows) {
    const int bytes = 2 * row.variant.values() + 10;
    const double wire_s = bytes * 10.0 / row.baud;
    const double mirror_s = mostar::laser::kLms200MirrorPeriodS * row.variant.revolutions();
    const double wire_hz = std::min(1.0 / wire_s, 1.0 / mirror_s);
    const double turns = std::max(1.0, std::ceil(wire_s / mirror_s));
    const double cap_hz = 1.0 / (turns * mirror_s);
    const double achieved = MeasureHz(row, seconds);
    std::printf("%8d %5dx%-3d %7d %12.2f %14.2f %10.2f %7.1f%% %7.1f%%\n", row.baud,
                row.variant.angle_deg, row.variant.resolution_cdeg, bytes, wire_hz, cap_hz,
                achieved, 100 * achieved / wire_hz, 100 * achieved / cap_hz);
  }
  return 0;
}
