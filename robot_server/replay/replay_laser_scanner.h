// A recording as the LaserScanner: the scans of a recording, each handed to the scan callback
// on the scanner's thread when its log time is due on a ReplayTimeline, so the live scan path
// (safety governor, publication, recording) runs on recorded scans.
//
// Scans are delivered unchanged except for the stamp (ReplayTimeline::Restamp) and the
// sequence (+1 per delivered scan, so it keeps increasing across loops). At the end of the
// recording the thread logs it and Health() says "end of recording <file> after N scans"
// (state kOff); with the timeline's loop it starts the next pass. Damage in the file ends a pass
// early and shows in Health() as a warning.
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "common/record/recording_reader.h"
#include "common/record/replay_sources.h"
#include "common/time/rate_meter.h"
#include "robot_server/laser/laser_scanner.h"
#include "robot_server/replay/replay_timeline.h"

namespace mostar::replay {

class ReplayLaserScanner final : public laser::LaserScanner {
 public:
  struct Options : ReplayDeviceOptions {
    std::string name = "laser_replay";  // DeviceHealth name
  };

  explicit ReplayLaserScanner(Options options);
  ~ReplayLaserScanner() override;  // Stop()

  // Opens the recording (false with the reason when it cannot be read) and starts the thread.
  bool Start(ScanCallback on_scan, std::string* error) override;
  void Stop() override;
  // Counters: scans_replayed, replay_loops (passes completed).
  DeviceHealth Health() const override;

  // True once a non-looping replay has delivered its last scan (or met damage).
  bool finished() const { return finished_; }
  uint64_t scans_replayed() const { return scans_replayed_; }

 private:
  void Run(ScanCallback on_scan);
  // Sleeps until `t`; false when stopping.
  bool SleepUntil(SteadyTime t);
  void SetState(DeviceState state, const std::string& message);

  const Options options_;
  std::unique_ptr<record::RecordingReader> reader_;  // handed to the thread's source
  std::atomic<bool> stop_{false};
  std::atomic<bool> finished_{false};
  std::atomic<uint64_t> scans_replayed_{0};
  std::atomic<uint64_t> passes_{0};
  std::thread thread_;

  mutable std::mutex mutex_;  // guards the health fields below
  DeviceState state_ = DeviceState::kOff;
  std::string message_ = "not started";
  mutable RateMeter rate_;
};

}  // namespace mostar::replay
