#include "robot_server/replay/replay_sonar.h"

#include <utility>

namespace mostar::replay {

ReplaySonarRing::ReplaySonarRing(const Options& options)
    : pump_(options, {options.name, "sonar cycles", "cycles_replayed"}) {}

ReplaySonarRing::~ReplaySonarRing() { Stop(); }

bool ReplaySonarRing::Start(RangesCallback on_ranges, std::string* error) {
  cycle_ = 0;
  return pump_.Start(
      [this, on_ranges = std::move(on_ranges)](SonarRanges& ranges, uint64_t pass) {
        for (SonarRange& r : ranges.ranges) {
          r.stamp = pump_.options().timeline->Restamp(r.stamp, pass);
        }
        ranges.cycle = ++cycle_;
        on_ranges(ranges);
      },
      error);
}

void ReplaySonarRing::Stop() { pump_.Stop(); }

ReplayBumperBelt::ReplayBumperBelt(const Options& options, std::string* error)
    : segments_(options.segments),
      pump_(options, {options.name, "bumper states", "states_replayed"}) {
  if (!pump_.Start(
          [this](BumperState& state, uint64_t) {
            std::lock_guard<std::mutex> lock(mutex_);
            newest_ = state;
          },
          error)) {
    start_error_ = "bumper replay: " + *error;
  }
}

ReplayBumperBelt::~ReplayBumperBelt() { pump_.Stop(); }

bool ReplayBumperBelt::Read(uint32_t* pressed, std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!newest_) {
    *error = start_error_.empty() ? "no recorded bumper state replayed yet" : start_error_;
    return false;
  }
  if (!newest_->readable) {
    *error = "the recorded bumper belt was unreadable";
    return false;
  }
  *pressed = newest_->pressed;
  return true;
}

DeviceHealth ReplayBumperBelt::Health() const {
  DeviceHealth health = pump_.Health();
  if (!start_error_.empty()) {
    health.state = DeviceState::kError;
    health.message = start_error_;
    return health;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  if (newest_ && newest_->segment_count != segments_ && health.state == DeviceState::kOk) {
    health.state = DeviceState::kWarn;
    health.message += "; the recording has " + std::to_string(newest_->segment_count) +
                      " segments, the configuration " + std::to_string(segments_);
  }
  return health;
}

}  // namespace mostar::replay
