// The thread of a sensor replay: reads the records of one kind T (LaserScan, SonarRanges,
// BumperState) of a recording, waits until each is due on the shared ReplayTimeline and hands
// it to the device's `deliver` (which restamps it with ReplayTimeline::Restamp and passes it
// on). At the end of the recording it logs it and Health() says "end of recording <file> after
// N <noun>" (state kOff); with the timeline's loop it starts the next pass. Damage in the file
// ends a pass early and shows in Health() as a warning; a recording without any such record is
// an error.
#pragma once

#include <algorithm>
#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <utility>

#include "common/log/log.h"
#include "common/record/recording_reader.h"
#include "common/record/replay_sources.h"
#include "common/time/rate_meter.h"
#include "common/types/health.h"
#include "robot_server/replay/replay_timeline.h"

namespace mostar::replay {

struct ReplayPumpNames {
  std::string device;   // DeviceHealth name, e.g. "laser_replay"
  std::string noun;     // what the records are in messages, e.g. "scans"
  std::string counter;  // the health counter of records delivered, e.g. "scans_replayed"
};

template <typename T>
class ReplayPump {
 public:
  // Called on the pump's thread with each due record and its pass (0, 1, ...). Must not block.
  using Deliver = std::function<void(T& value, uint64_t pass)>;

  ReplayPump(ReplayDeviceOptions options, ReplayPumpNames names)
      : options_(std::move(options)), names_(std::move(names)) {}
  ~ReplayPump() { Stop(); }
  ReplayPump(const ReplayPump&) = delete;
  ReplayPump& operator=(const ReplayPump&) = delete;

  // Opens the recording (false with the reason when it cannot be read) and starts the thread.
  bool Start(Deliver deliver, std::string* error) {
    if (thread_.joinable()) {
      *error = names_.device + " already started";
      return false;
    }
    if (!options_.timeline) {
      *error = names_.device + " without a timeline";
      return false;
    }
    std::unique_ptr<record::RecordingReader> reader =
        record::RecordingReader::Open(options_.path, error);
    if (!reader) return false;
    stop_ = false;
    thread_ = std::thread(
        [this, r = std::move(reader), d = std::move(deliver)]() mutable { Run(std::move(r), d); });
    return true;
  }
  // Stops and joins the thread; no delivery after it returns. Idempotent.
  void Stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }
  // Counters: <counter> and replay_loops (passes completed).
  DeviceHealth Health() const {
    DeviceHealth health;
    health.name = names_.device;
    std::lock_guard<std::mutex> lock(mutex_);
    health.state = state_;
    health.message = message_;
    health.rate_hz = static_cast<float>(rate_.RateHz(options_.clock->SteadyNow()));
    health.counters = {{names_.counter, delivered_.load()}, {"replay_loops", passes_.load()}};
    return health;
  }
  // True once a non-looping replay has delivered its last record (or met damage).
  bool finished() const { return finished_; }
  uint64_t delivered() const { return delivered_; }
  const ReplayDeviceOptions& options() const { return options_; }

 private:
  void SetState(DeviceState state, const std::string& message) {
    std::lock_guard<std::mutex> lock(mutex_);
    state_ = state;
    message_ = message;
  }
  // Sleeps until `t`; false when stopping.
  bool SleepUntil(SteadyTime t) {
    for (SteadyTime now = options_.clock->SteadyNow(); now < t; now = options_.clock->SteadyNow()) {
      if (stop_) return false;
      options_.sleep(std::min<Duration>(t - now, std::chrono::milliseconds(20)));
    }
    return !stop_;
  }

  void Run(std::unique_ptr<record::RecordingReader> owned_reader, const Deliver& deliver) {
    record::RecordingReader* reader = owned_reader.get();
    record::ReplayTopicSource<T> source(std::move(owned_reader));
    ReplayTimeline& timeline = *options_.timeline;
    timeline.Start();
    // Start where the shared timeline is now (another device may have started it earlier).
    uint64_t pass = 0;
    const Time now = timeline.RecordingNow(&pass);
    bool pass_from_begin = now <= timeline.begin();
    if (!pass_from_begin) source.SeekToTime(now);
    passes_ = pass;
    uint64_t in_pass = 0;
    uint64_t count = 0;
    {
      std::ostringstream message;
      message << "replaying " << options_.path << " at " << timeline.options().rate << "x"
              << (timeline.options().loop ? ", looping" : "");
      SetState(DeviceState::kOk, message.str());
    }
    const std::string log_prefix = names_.device + ": ";
    while (!stop_) {
      record::Timed<T> record;
      if (!source.Next(&record)) {
        std::string damage;
        if (reader->damage()) {
          damage = " (damaged at byte " + std::to_string(reader->damage()->offset) + ": " +
                   reader->damage()->reason + ")";
          MOSTAR_LOG_EVERY_SEC(WARNING, 10) << log_prefix << options_.path << damage
                                            << "; replayed the " << names_.noun << " before it";
        }
        if (pass_from_begin && in_pass == 0) {
          SetState(DeviceState::kError, "no " + names_.noun + " in " + options_.path + damage);
          MOSTAR_LOG(ERROR) << log_prefix << "no " << names_.noun << " in " << options_.path
                            << damage;
          finished_ = true;
          return;
        }
        if (!timeline.options().loop) {
          const std::string message = "end of recording " + options_.path + " after " +
                                      std::to_string(count) + " " + names_.noun + damage;
          SetState(damage.empty() ? DeviceState::kOff : DeviceState::kWarn, message);
          MOSTAR_LOG(INFO) << log_prefix << message;
          finished_ = true;
          return;
        }
        passes_ = ++pass;
        in_pass = 0;
        pass_from_begin = true;
        source.SeekToTime(Time::min());
        continue;
      }
      ++in_pass;
      if (!SleepUntil(timeline.DueTime(record.log_time, pass))) break;
      deliver(record.value, pass);
      delivered_ = ++count;
      std::lock_guard<std::mutex> lock(mutex_);
      rate_.Tick(options_.clock->SteadyNow());
    }
    SetState(DeviceState::kOff, "stopped after " + std::to_string(count) + " " + names_.noun);
  }

  const ReplayDeviceOptions options_;
  const ReplayPumpNames names_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> finished_{false};
  std::atomic<uint64_t> delivered_{0};
  std::atomic<uint64_t> passes_{0};
  std::thread thread_;

  mutable std::mutex mutex_;  // guards the health fields below
  DeviceState state_ = DeviceState::kOff;
  std::string message_ = "not started";
  mutable RateMeter rate_;
};

}  // namespace mostar::replay
