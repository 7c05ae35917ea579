#include "operator_client/net/robot_state.h"

namespace mostar::client {

void RobotState::AddScan(const LaserScan& scan) {
  std::lock_guard<std::mutex> lock(mutex_);
  scans_.push_back(scan);
  // By stamp, not by count: the LMS200 delivers 9.4 Hz at 38400 Bd but 75 Hz at 500 kBd.
  while (scans_.size() > kMaxScans || scans_.front().stamp < scan.stamp - kScanHistory) {
    scans_.pop_front();
  }
  snapshot_.scans++;
  snapshot_.last_scan_received = clock_->SteadyNow();
  scan_rate_.Tick(snapshot_.last_scan_received);
}

void RobotState::SetHealth(const RobotHealth& health) {
  std::lock_guard<std::mutex> lock(mutex_);
  snapshot_.health = health;
  snapshot_.last_health_received = clock_->SteadyNow();
}

void RobotState::SetLease(const ControlLease& lease) {
  std::lock_guard<std::mutex> lock(mutex_);
  snapshot_.lease = lease;
}

void RobotState::SetOdometry(const Odometry& odometry) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!snapshot_.odometry || odometry.stamp >= snapshot_.odometry->stamp) {
    snapshot_.odometry = odometry;
  }
  snapshot_.last_odometry_received = clock_->SteadyNow();
  odometry_.Add(odometry);
}

void RobotState::MoveScanToImageTime(const LaserScan& scan, Time image_stamp,
                                     const fusion::MotionCompensationOptions& options,
                                     fusion::MovedScan* out) const {
  std::lock_guard<std::mutex> lock(mutex_);
  fusion::MoveScanToImageTime(scan, image_stamp, odometry_, options, out);
}

void RobotState::SetSonar(const SonarRanges& sonar) {
  std::lock_guard<std::mutex> lock(mutex_);
  snapshot_.sonar = sonar;
  snapshot_.last_sonar_received = clock_->SteadyNow();
}

void RobotState::SetBumpers(const BumperState& bumpers) {
  std::lock_guard<std::mutex> lock(mutex_);
  snapshot_.bumpers = bumpers;
  snapshot_.last_bumpers_received = clock_->SteadyNow();
}

void RobotState::AddFrameTiming(const FrameTiming& timing) {
  std::lock_guard<std::mutex> lock(mutex_);
  timings_.push_back(timing);
  while (timings_.size() > kTimingHistory) timings_.pop_front();
}

std::optional<FrameTiming> RobotState::TimingOf(Time capture) const {
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto it = timings_.rbegin(); it != timings_.rend(); ++it) {
    if (it->capture == capture) return *it;
  }
  return std::nullopt;
}

void RobotState::SetIntrinsics(Eye eye, const CameraIntrinsicsInfo& info) {
  std::lock_guard<std::mutex> lock(mutex_);
  (eye == Eye::kLeft ? snapshot_.left_intrinsics : snapshot_.right_intrinsics) = info;
}

void RobotState::AddClockSample(const ClockProbe& probe) {
  const Time t3 = clock_->Now();
  std::lock_guard<std::mutex> lock(mutex_);
  offset_.AddSample({probe.t0, probe.t1, probe.t2, t3});
  snapshot_.clock = offset_.Estimate();
  last_pong_sequence_ = probe.sequence;
  last_pong_receipt_ = t3;
  if (pong_sequences_.empty() || probe.sequence > pong_sequences_.back()) {
    pong_sequences_.push_back(probe.sequence);
  }
  while (!pong_sequences_.empty() &&
         pong_sequences_.front() + kPingLossWindow <= pong_sequences_.back()) {
    pong_sequences_.pop_front();
  }
  if (pong_sequences_.size() >= 2) {
    const double span = static_cast<double>(pong_sequences_.back() - pong_sequences_.front() + 1);
    snapshot_.ping_loss = 1.0 - static_cast<double>(pong_sequences_.size()) / span;
  }
}

Time RobotState::PongReceipt(uint64_t sequence) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sequence == last_pong_sequence_ ? last_pong_receipt_ : Time();
}

std::optional<LaserScan> RobotState::NearestScan(Time stamp) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const LaserScan* best = nullptr;
  Duration best_gap = Duration::max();
  for (const LaserScan& s : scans_) {
    const Duration gap = s.stamp > stamp ? s.stamp - stamp : stamp - s.stamp;
    if (gap < best_gap) {
      best_gap = gap;
      best = &s;
    }
  }
  if (best == nullptr) return std::nullopt;
  return *best;
}

std::optional<bool> RobotState::EstopEngaged(SteadyTime* received) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!snapshot_.health) return std::nullopt;
  *received = snapshot_.last_health_received;
  return snapshot_.health->estop_engaged;
}

RobotSnapshot RobotState::Snapshot() const {
  std::lock_guard<std::mutex> lock(mutex_);
  RobotSnapshot s = snapshot_;
  if (!scans_.empty()) s.latest_scan = scans_.back();
  s.scan_rate_hz = scan_rate_.RateHz(clock_->SteadyNow());
  return s;
}

}  // namespace mostar::client
