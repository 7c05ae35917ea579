#include "robot_server/replay/replay_laser_scanner.h"

#include <algorithm>
#include <sstream>
#include <utility>

#include "common/log/log.h"
#include "common/record/recording_reader.h"
#include "common/record/replay_sources.h"

namespace mostar::replay {

ReplayLaserScanner::ReplayLaserScanner(Options options) : options_(std::move(options)) {}

ReplayLaserScanner::~ReplayLaserScanner() { Stop(); }

bool ReplayLaserScanner::Start(ScanCallback on_scan, std::string* error) {
  if (thread_.joinable()) {
    *error = "laser replay already started";
    return false;
  }
  if (!options_.timeline) {
    *error = "laser replay without a timeline";
    return false;
  }
  reader_ = record::RecordingReader::Open(options_.path, error);
  if (!reader_) return false;
  stop_ = false;
  thread_ = std::thread([this, on_scan = std::move(on_scan)] { Run(on_scan); });
  return true;
}

void ReplayLaserScanner::Stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void ReplayLaserScanner::SetState(DeviceState state, const std::string& message) {
  std::lock_guard<std::mutex> lock(mutex_);
  state_ = state;
  message_ = message;
}

DeviceHealth ReplayLaserScanner::Health() const {
  DeviceHealth health;
  health.name = options_.name;
  std::lock_guard<std::mutex> lock(mutex_);
  health.state = state_;
  health.message = message_;
  health.rate_hz = static_cast<float>(rate_.RateHz(options_.clock->SteadyNow()));
  health.counters = {{"scans_replayed", scans_replayed_.load()}, {"replay_loops", passes_.load()}};
  return health;
}

bool ReplayLaserScanner::SleepUntil(SteadyTime t) {
  for (SteadyTime now = options_.clock->SteadyNow(); now < t; now = options_.clock->SteadyNow()) {
    if (stop_) return false;
    options_.sleep(std::min<Duration>(t - now, std::chrono::milliseconds(20)));
  }
  return !stop_;
}

void ReplayLaserScanner::Run(ScanCallback on_scan) {
  record::RecordingReader* reader = reader_.get();
  record::ReplayScanSource source(std::move(reader_));
  ReplayTimeline& timeline = *options_.timeline;
  timeline.Start();
  // Start where the shared timeline is now (the camera may have started it earlier).
  uint64_t pass = 0;
  const Time now = timeline.RecordingNow(&pass);
  bool pass_from_begin = now <= timeline.begin();
  if (!pass_from_begin) source.SeekToTime(now);
  passes_ = pass;
  uint64_t in_pass = 0;
  uint64_t sequence = 0;
  {
    std::ostringstream message;
    message << "replaying " << options_.path << " at " << timeline.options().rate << "x"
            << (timeline.options().loop ? ", looping" : "");
    SetState(DeviceState::kOk, message.str());
  }
  while (!stop_) {
    record::TimedScan scan;
    if (!source.Next(&scan)) {
      std::string damage;
      if (reader->damage()) {
        damage = " (damaged at byte " + std::to_string(reader->damage()->offset) + ": " +
                 reader->damage()->reason + ")";
        MOSTAR_LOG_EVERY_SEC(WARNING, 10)
            << "laser replay: " << options_.path << damage << "; replayed the scans before it";
      }
      if (pass_from_begin && in_pass == 0) {
        SetState(DeviceState::kError, "no scans in " + options_.path + damage);
        MOSTAR_LOG(ERROR) << "laser replay: no scans in " << options_.path << damage;
        finished_ = true;
        return;
      }
      if (!timeline.options().loop) {
        const std::string message = "end of recording " + options_.path + " after " +
                                    std::to_string(sequence) + " scans" + damage;
        SetState(damage.empty() ? DeviceState::kOff : DeviceState::kWarn, message);
        MOSTAR_LOG(INFO) << "laser replay: " << message;
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
    if (!SleepUntil(timeline.DueTime(scan.log_time, pass))) break;
    scan.scan.stamp = timeline.Restamp(scan.scan.stamp, pass);
    scan.scan.sequence = ++sequence;
    on_scan(scan.scan);
    scans_replayed_ = sequence;
    std::lock_guard<std::mutex> lock(mutex_);
    rate_.Tick(options_.clock->SteadyNow());
  }
  SetState(DeviceState::kOff, "stopped after " + std::to_string(sequence) + " scans");
}

}  // namespace mostar::replay
