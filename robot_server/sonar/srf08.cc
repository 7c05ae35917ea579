#include "robot_server/sonar/srf08.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "common/log/log.h"

namespace mostar::sonar {

uint8_t Srf08RangeRegisterFor(double max_range_m) {
  const double steps = std::ceil(max_range_m / 0.043) - 1;
  return static_cast<uint8_t>(std::clamp(steps, 0.0, 255.0));
}

double Srf08WindowMetres(uint8_t range_register) { return (range_register + 1) * 0.043; }

float Srf08EchoMetres(uint8_t high, uint8_t low) {
  const int centimetres = (high << 8) | low;
  if (centimetres == 0) return std::numeric_limits<float>::infinity();
  return static_cast<float>(centimetres) / 100.0f;
}

bool Srf08RingOptions::IsValid(std::string* error) const {
  if (sensors.empty()) {
    *error = "no sonar sensors configured";
    return false;
  }
  std::set<uint8_t> addresses;
  for (const Srf08Sensor& s : sensors) {
    if (s.address < kSrf08MinAddress || s.address > kSrf08MaxAddress) {
      *error = "sensor " + s.mount.frame_id + ": address must be within 0x70..0x7f";
      return false;
    }
    if (!addresses.insert(s.address).second) {
      *error = "sensor " + s.mount.frame_id + ": address used twice";
      return false;
    }
  }
  if (!ping_groups.empty()) {
    std::vector<int> seen(sensors.size(), 0);
    for (const auto& group : ping_groups) {
      if (group.empty()) {
        *error = "ping_groups: an empty group";
        return false;
      }
      for (int i : group) {
        if (i < 0 || static_cast<size_t>(i) >= sensors.size()) {
          *error = "ping_groups: sensor index " + std::to_string(i) + " out of range";
          return false;
        }
        ++seen[static_cast<size_t>(i)];
      }
    }
    for (size_t i = 0; i < seen.size(); ++i) {
      if (seen[i] != 1) {
        *error = "ping_groups: sensor " + std::to_string(i) + " must be in exactly one group";
        return false;
      }
    }
  }
  if (!(max_range_m >= 0.043 && max_range_m <= 11.008)) {
    *error = "max_range_m must be within 0.043..11";
    return false;
  }
  if (gain < 0 || gain > 31) {
    *error = "gain must be within 0..31";
    return false;
  }
  if (ranging_time <= Duration::zero() || poll_timeout < Duration::zero()) {
    *error = "ranging_time must be > 0 and poll_timeout >= 0";
    return false;
  }
  if (!(min_range_m >= 0 && min_range_m < max_range_m)) {
    *error = "min_range_m must be within [0, max_range_m)";
    return false;
  }
  if (!(field_of_view_rad > 0 && field_of_view_rad < M_PI)) {
    *error = "field_of_view_rad must be within (0, pi)";
    return false;
  }
  return true;
}

Srf08Ring::Srf08Ring(std::unique_ptr<I2cBus> bus, const Srf08RingOptions& options,
                     const Clock& clock)
    : bus_(std::move(bus)), options_(options), clock_(clock) {
  if (options_.ping_groups.empty()) {
    for (size_t i = 0; i < options_.sensors.size(); ++i) {
      options_.ping_groups.push_back({static_cast<int>(i)});
    }
  }
  configured_.assign(options_.sensors.size(), false);
}

Srf08Ring::~Srf08Ring() { Stop(); }

bool Srf08Ring::Start(RangesCallback on_ranges, std::string* error) {
  if (started_) {
    *error = "the sonar ring is already started";
    return false;
  }
  if (!options_.IsValid(error)) return false;
  on_ranges_ = std::move(on_ranges);
  started_ = true;
  thread_ = std::thread([this] { Run(); });
  return true;
}

void Srf08Ring::Stop() {
  {
    std::lock_guard<std::mutex> lock(stop_mutex_);
    stopping_ = true;
  }
  stop_cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

bool Srf08Ring::Sleep(Duration duration) {
  std::unique_lock<std::mutex> lock(stop_mutex_);
  return !stop_cv_.wait_for(lock, duration, [this] { return stopping_; });
}

bool Srf08Ring::Configure(size_t sensor, std::string* error) {
  const uint8_t address = options_.sensors[sensor].address;
  return bus_->WriteRegister(address, kSrf08RangeRegister,
                             Srf08RangeRegisterFor(options_.max_range_m), error) &&
         bus_->WriteRegister(address, kSrf08GainRegister, static_cast<uint8_t>(options_.gain),
                             error);
}

void Srf08Ring::Run() {
  const float max_range = static_cast<float>(std::min(
      options_.max_range_m, Srf08WindowMetres(Srf08RangeRegisterFor(options_.max_range_m))));
  uint64_t cycle = 0;
  for (;;) {
    SonarRanges out;
    out.cycle = ++cycle;
    out.ranges.resize(options_.sensors.size());
    std::vector<std::string> failed;
    uint64_t bus_errors = 0, timeouts = 0, no_echo = 0;
    for (const auto& group : options_.ping_groups) {
      std::vector<int> ranging;
      std::string error;
      for (int i : group) {
        const size_t s = static_cast<size_t>(i);
        SonarRange& r = out.ranges[s];
        r.mount = options_.sensors[s].mount;
        r.min_range_m = static_cast<float>(options_.min_range_m);
        r.max_range_m = max_range;
        r.field_of_view_rad = static_cast<float>(options_.field_of_view_rad);
        r.range_m = std::numeric_limits<float>::quiet_NaN();
        if (!configured_[s]) configured_[s] = Configure(s, &error);
        if (configured_[s] &&
            bus_->WriteRegister(options_.sensors[s].address, kSrf08CommandRegister,
                                kSrf08RangeCentimetres, &error)) {
          ranging.push_back(i);
        } else {
          configured_[s] = false;
          ++bus_errors;
          failed.push_back(r.mount.frame_id);
          MOSTAR_LOG_EVERY_SEC(WARNING, 10) << "sonar " << r.mount.frame_id << ": " << error;
        }
      }
      if (!Sleep(options_.ranging_time)) return;
      const SteadyTime poll_end = clock_.SteadyNow() + options_.poll_timeout;
      for (int i : ranging) {
        const size_t s = static_cast<size_t>(i);
        const uint8_t address = options_.sensors[s].address;
        // The sensor does not answer while it ranges: poll its revision register.
        bool ready = false;
        for (;;) {
          uint8_t revision = 0xFF;
          if (bus_->ReadRegisters(address, kSrf08CommandRegister, &revision, 1, &error) &&
              revision != 0xFF) {
            ready = true;
            break;
          }
          if (clock_.SteadyNow() >= poll_end) break;
          if (!Sleep(std::chrono::milliseconds(2))) return;
        }
        SonarRange& r = out.ranges[s];
        uint8_t echo[2] = {0, 0};
        if (!ready) {
          ++timeouts;
          configured_[s] = false;
          failed.push_back(r.mount.frame_id);
        } else if (!bus_->ReadRegisters(address, kSrf08FirstEchoRegister, echo, 2, &error)) {
          ++bus_errors;
          configured_[s] = false;
          failed.push_back(r.mount.frame_id);
        } else {
          r.range_m = Srf08EchoMetres(echo[0], echo[1]);
          if (std::isinf(r.range_m) || r.range_m > max_range) {
            r.range_m = std::numeric_limits<float>::infinity();
            ++no_echo;
          }
        }
        r.stamp = clock_.Now();
      }
    }
    {
      std::lock_guard<std::mutex> lock(health_mutex_);
      const SteadyTime now = clock_.SteadyNow();
      if (cycles_ == 0) first_cycle_end_ = now;
      last_cycle_end_ = now;
      ++cycles_;
      bus_errors_ += bus_errors;
      timeouts_ += timeouts;
      no_echo_ += no_echo;
      failed_last_cycle_ = failed;
    }
    if (on_ranges_) on_ranges_(out);
  }
}

DeviceHealth Srf08Ring::Health() const {
  std::lock_guard<std::mutex> lock(health_mutex_);
  DeviceHealth h;
  h.name = "sonar";
  const size_t total = options_.sensors.size();
  if (cycles_ == 0) {
    h.state = DeviceState::kWarn;
    h.message = "no belt cycle yet";
  } else if (failed_last_cycle_.size() == total) {
    h.state = DeviceState::kError;
    h.message = "no sonar answered in the last cycle";
  } else if (!failed_last_cycle_.empty()) {
    h.state = DeviceState::kWarn;
    h.message = "no range from";
    for (const std::string& name : failed_last_cycle_) h.message += " " + name;
  } else {
    h.state = DeviceState::kOk;
  }
  if (cycles_ > 1) {
    h.rate_hz = static_cast<float>((cycles_ - 1) / ToSeconds(last_cycle_end_ - first_cycle_end_));
  }
  h.counters = {{"cycles", cycles_},
                {"bus_errors", bus_errors_},
                {"timeouts", timeouts_},
                {"no_echo", no_echo_}};
  return h;
}

}  // namespace mostar::sonar
