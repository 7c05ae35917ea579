// The sonar belt and the bumper belt of a recording (robot_server --replay-sensors), paced by
// the same ReplayTimeline as the camera and laser replays (ReplayPump), so that the safety
// governor, publication and recording run on the recorded belts.
//
// ReplaySonarRing hands each recorded belt cycle to the ranges callback, restamped
// (ReplayTimeline::Restamp) and renumbered (cycle +1 per delivered cycle, increasing across
// loops). ReplayBumperBelt's Read() gives the pressed segments of the newest recorded state
// that is due; before the first one, and while that state says the contacts were unreadable,
// Read() fails, so the robot stops as with a real belt that cannot be read.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "robot_server/bumper/bumper_belt.h"
#include "robot_server/replay/replay_pump.h"
#include "robot_server/replay/replay_timeline.h"
#include "robot_server/sonar/sonar_ring.h"

namespace mostar::replay {

class ReplaySonarRing final : public sonar::SonarRing {
 public:
  struct Options : ReplayDeviceOptions {
    std::string name = "sonar_replay";  // DeviceHealth name
  };

  explicit ReplaySonarRing(const Options& options);
  ~ReplaySonarRing() override;  // Stop()

  // Opens the recording (false with the reason when it cannot be read) and starts the thread.
  bool Start(RangesCallback on_ranges, std::string* error) override;
  void Stop() override;
  // Counters: cycles_replayed, replay_loops.
  DeviceHealth Health() const override { return pump_.Health(); }
  bool finished() const { return pump_.finished(); }

 private:
  ReplayPump<SonarRanges> pump_;
  uint64_t cycle_ = 0;  // pump thread only
};

class ReplayBumperBelt final : public bumper::BumperBelt {
 public:
  struct Options : ReplayDeviceOptions {
    std::string name = "bumpers_replay";  // DeviceHealth name
    int segments = 16;                    // the configured belt, 1..bumper::kMaxSegments
  };

  // Starts reading the recording at once (the belt has no Start); `error` says why when the
  // recording cannot be read, and Read() then fails.
  ReplayBumperBelt(const Options& options, std::string* error);
  ~ReplayBumperBelt() override;

  bool Read(uint32_t* pressed, std::string* error) override;
  int segments() const override { return segments_; }
  // The pump's health; a recorded belt of another size than the configured one is a warning.
  DeviceHealth Health() const override;
  bool finished() const { return pump_.finished(); }

 private:
  const int segments_;
  ReplayPump<BumperState> pump_;
  std::string start_error_;  // why the recording could not be read; empty when it could
  mutable std::mutex mutex_;
  std::optional<BumperState> newest_;  // the newest due recorded state
};

}  // namespace mostar::replay
