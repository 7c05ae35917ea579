#include "robot_server/replay/replay_laser_scanner.h"

#include <utility>

namespace mostar::replay {

ReplayLaserScanner::ReplayLaserScanner(const Options& options)
    : pump_(options, {options.name, "scans", "scans_replayed"}) {}

ReplayLaserScanner::~ReplayLaserScanner() { Stop(); }

bool ReplayLaserScanner::Start(ScanCallback on_scan, std::string* error) {
  sequence_ = 0;
  return pump_.Start(
      [this, on_scan = std::move(on_scan)](LaserScan& scan, uint64_t pass) {
        scan.stamp = pump_.options().timeline->Restamp(scan.stamp, pass);
        scan.sequence = ++sequence_;
        on_scan(scan);
      },
      error);
}

void ReplayLaserScanner::Stop() { pump_.Stop(); }

}  // namespace mostar::replay
