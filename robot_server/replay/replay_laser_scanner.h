// A recording as the LaserScanner: the scans of a recording, each handed to the scan callback
// on the scanner's thread when its log time is due on a ReplayTimeline (ReplayPump), so the
// live scan path (safety governor, publication, recording) runs on recorded scans.
//
// Scans are delivered unchanged except for the stamp (ReplayTimeline::Restamp) and the
// sequence (+1 per delivered scan, so it keeps increasing across loops). End of recording,
// loops and damage: see ReplayPump.
#pragma once

#include <cstdint>
#include <string>

#include "robot_server/laser/laser_scanner.h"
#include "robot_server/replay/replay_pump.h"
#include "robot_server/replay/replay_timeline.h"

namespace mostar::replay {

class ReplayLaserScanner final : public laser::LaserScanner {
 public:
  struct Options : ReplayDeviceOptions {
    std::string name = "laser_replay";  // DeviceHealth name
  };

  explicit ReplayLaserScanner(const Options& options);
  ~ReplayLaserScanner() override;  // Stop()

  // Opens the recording (false with the reason when it cannot be read) and starts the thread.
  bool Start(ScanCallback on_scan, std::string* error) override;
  void Stop() override;
  // Counters: scans_replayed, replay_loops (passes completed).
  DeviceHealth Health() const override { return pump_.Health(); }

  // True once a non-looping replay has delivered its last scan (or met damage).
  bool finished() const { return pump_.finished(); }
  uint64_t scans_replayed() const { return pump_.delivered(); }

 private:
  ReplayPump<LaserScan> pump_;
  uint64_t sequence_ = 0;  // pump thread only
};

}  // namespace mostar::replay
