// lms200_emulator: a SICK LMS200 on a pseudo-terminal, scanning an empty room.
//
//   lms200_emulator --link /tmp/lms200 --baud 9600 --room-length 8 --room-width 5
// Prints the slave device path; point the driver's `port` at the link (or that path).
#include <CLI/CLI.hpp>
#include <atomic>
#include <iostream>
#include <thread>

#include "common/process/stop_signals.h"
#include "robot_server/sim/lms200_emulator/lms200_pty.h"

namespace {}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"SICK LMS200 emulator on a pseudo-terminal"};
  std::string link = "/tmp/lms200";
  int baud = 9600;
  double length_m = 8.0, width_m = 5.0;
  std::string unit = "mm";
  int angle_deg = 180, resolution_cdeg = 50, measuring_mode = 0;
  bool indices = false;
  double garbage_rate = 0, crc_error_rate = 0, truncate_rate = 0;
  app.add_option("--link", link, "symlink to the slave device ('' for none)");
  app.add_option("--baud", baud, "power-on baud rate")
      ->check(CLI::IsMember({9600, 19200, 38400, 500000}));
  app.add_option("--room-length", length_m, "room length along x, metres");
  app.add_option("--room-width", width_m, "room width along y, metres");
  app.add_option("--unit", unit, "mm or cm")->check(CLI::IsMember({"mm", "cm"}));
  app.add_option("--angle", angle_deg, "field of view, degrees")->check(CLI::IsMember({100, 180}));
  app.add_option("--resolution", resolution_cdeg, "1/100 degree")
      ->check(CLI::IsMember({25, 50, 100}));
  app.add_option("--measuring-mode", measuring_mode, "configuration block D");
  app.add_flag("--indices", indices, "send real-time indices");
  app.add_option("--garbage-rate", garbage_rate, "probability of garbage before a telegram");
  app.add_option("--crc-error-rate", crc_error_rate, "probability of a bad CRC per telegram");
  app.add_option("--truncate-rate", truncate_rate, "probability of a truncated telegram");
  CLI11_PARSE(app, argc, argv);

  mostar::sim::Lms200EmulatorOptions options;
  options.initial_baud = baud;
  options.unit = unit == "mm" ? mostar::laser::Lms200Unit::kMm : mostar::laser::Lms200Unit::kCm;
  options.variant = {angle_deg, resolution_cdeg};
  if (!options.variant.IsValid()) {
    std::cerr << "invalid variant " << angle_deg << " x " << resolution_cdeg << "\n";
    return 2;
  }
  options.measuring_mode = static_cast<uint8_t>(measuring_mode);
  options.real_time_indices = indices;
  options.garbage_rate = garbage_rate;
  options.crc_error_rate = crc_error_rate;
  options.truncate_rate = truncate_rate;
  mostar::sim::RoomRangeSource room(length_m, width_m, length_m / 2, width_m / 2);
  mostar::sim::Lms200Emulator emulator(options, &room, std::chrono::steady_clock::now());
  mostar::sim::Lms200PtyRunner runner(&emulator, link);
  std::string error;
  if (!runner.Start(&error)) {
    std::cerr << "lms200_emulator: " << error << "\n";
    return 1;
  }
  std::cout << runner.slave_path() << (link.empty() ? "" : " (" + link + ")") << std::endl;
  mostar::InstallStopSignals();
  while (!mostar::StopRequested()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  runner.Stop();
  return 0;
}
