// When the records of a recording are due in a replay backend, and which stamps they carry.
//
// Pass k (0 = first) of a recording spanning log times [begin, end] puts log time r at the
// timeline position u = k * loop_period + (r - begin), loop_period = end - begin + loop_gap.
// Started at steady time S0 and wall time W0, u is due at S0 + u / rate, and a recorded stamp s
// of pass k is published as W0 + (k * loop_period + s - begin) / rate (or s unchanged with
// keep_stamps). The camera and the laser of one recording share one timeline, so their data
// stays as aligned as it was recorded, across loops too, and fits odometry stamped live.
// Pure arithmetic over an injected Clock (never sleeps). Thread-safe.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "common/record/replay_player.h"
#include "common/time/time.h"

namespace mostar::replay {

// How replay backends wait: sleeps for the given duration, after which the backend's clock
// must have advanced by it. Tests inject one that advances a FakeClock instead.
using SleepFn = std::function<void(Duration)>;
void RealSleep(Duration d);

class ReplayTimeline;

// What every replay device (camera, laser) is built from.
struct ReplayDeviceOptions {
  std::string path;                               // the recording
  std::shared_ptr<ReplayTimeline> timeline;       // shared by the devices of one recording
  const Clock* clock = &SystemClock::Instance();  // the timeline's clock; not owned
  // Waits in slices of at most 20 ms, so stopping is prompt.
  SleepFn sleep = RealSleep;
  // Camera only: a pair is due at its capture stamp, not at its log time.
  bool due_at_stamp = false;
};

struct ReplayTimelineOptions {
  double rate = 1.0;                                   // speed factor, > 0 (2 = twice as fast)
  bool loop = false;                                   // start again after the end
  Duration loop_gap = std::chrono::milliseconds(100);  // between the end and the next pass, >= 0
  // True: publish the recorded stamps (they repeat when looping). False: move them to the
  // replay's wall clock as above, so that they are fresh and strictly increase across loops.
  bool keep_stamps = false;

  bool IsValid(std::string* error) const;
};

class ReplayTimeline {
 public:
  // `clock` must outlive the timeline; begin <= end are the first and last log times.
  ReplayTimeline(const Clock& clock, Time begin, Time end, const ReplayTimelineOptions& options);

  // Reads the first and last log times of the recording at `path`. Null with a message when
  // the file cannot be read, has no records, or the options are invalid.
  static std::shared_ptr<ReplayTimeline> ForRecording(const std::string& path, const Clock& clock,
                                                      const ReplayTimelineOptions& options,
                                                      std::string* error);

  // Anchors the timeline: `begin` of pass 0 is due now. Only the first call does anything, so
  // every backend sharing the timeline calls it when it starts.
  void Start();
  bool started() const;

  // Steady time when log time `log_time` of pass `pass` is due. Start() first.
  SteadyTime DueTime(Time log_time, uint64_t pass) const;
  // The stamp to publish for recorded stamp `stamp` of pass `pass`. Start() first.
  Time Restamp(Time stamp, uint64_t pass) const;
  // The pass and log time due now (at most `end` of the last pass without loop). Start() first.
  Time RecordingNow(uint64_t* pass) const;

  Time begin() const { return begin_; }
  Time end() const { return end_; }
  Duration loop_period() const { return end_ - begin_ + options_.loop_gap; }
  const ReplayTimelineOptions& options() const { return options_; }

 private:
  Duration Scaled(Duration d) const;  // d / rate

  const Clock& clock_;
  const Time begin_;
  const Time end_;
  const ReplayTimelineOptions options_;
  mutable std::mutex mutex_;
  record::ReplayClock replay_clock_;  // recording time (pass 0 axis) -> steady time
  Time wall_anchor_;
  bool started_ = false;
};

}  // namespace mostar::replay
