#include "robot_server/drive/safety_governor.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace mostar::drive {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Step along a beam of unknown space when looking for the swept path. unit: m.
constexpr double kUnknownBeamStepM = 0.02;

// One ramp step of `current` towards `target`: `accel` when speeding up, `decel` when slowing
// down; a sign change first comes to rest.
double RampStep(double current, double target, double accel, double decel, double dt_s) {
  if (current * target < 0) {
    return current > 0 ? std::max(0.0, current - decel * dt_s)
                       : std::min(0.0, current + decel * dt_s);
  }
  const double limit = (std::abs(target) <= std::abs(current) ? decel : accel) * dt_s;
  return current + std::clamp(target - current, -limit, limit);
}

bool Positive(double v) { return std::isfinite(v) && v > 0; }

// Rays of unknown space across the cone of a failed sonar.
constexpr int kFailedSonarRays = 5;
// A pressed segment whose centre is within this many degrees of the side (90 deg) blocks
// neither direction of linear motion.
constexpr double kSideSegmentCos = 0.2;

double SegmentAngle(int i, int segments) { return 2 * M_PI * i / segments; }

}  // namespace

std::string BumperSegmentList(uint32_t mask, int segments) {
  std::ostringstream out;
  bool first = true;
  for (int i = 0; i < 32; ++i) {
    if (!(mask & (1u << i))) continue;
    out << (first ? "" : ", ") << i;
    if (segments > 0) out << " (" << std::lround(360.0 * i / segments) << " deg)";
    first = false;
  }
  return out.str();
}

bool SafetyOptions::IsValid(std::string* error) const {
  const std::pair<const char*, double> positives[] = {
      {"max_linear_mps", max_linear_mps},
      {"max_reverse_mps", max_reverse_mps},
      {"max_angular_radps", max_angular_radps},
      {"max_linear_accel_mps2", max_linear_accel_mps2},
      {"max_linear_decel_mps2", max_linear_decel_mps2},
      {"max_angular_accel_radps2", max_angular_accel_radps2},
      {"max_angular_decel_radps2", max_angular_decel_radps2},
      {"robot_width_m", robot_width_m},
      {"slow_distance_m", slow_distance_m},
  };
  for (const auto& [name, value] : positives) {
    if (!Positive(value)) {
      *error = std::string(name) + " must be positive";
      return false;
    }
  }
  if (deadman_period <= Duration::zero() || max_command_age <= Duration::zero() ||
      delay_window <= Duration::zero() || scan_max_age <= Duration::zero() ||
      max_cycle <= Duration::zero()) {
    *error =
        "deadman_period, max_command_age, delay_window, scan_max_age and max_cycle must be "
        "positive";
    return false;
  }
  if (!(lateral_margin_m >= 0) || !(front_extent_m >= 0) || !(stop_distance_m >= 0)) {
    *error = "lateral_margin_m, front_extent_m and stop_distance_m must not be negative";
    return false;
  }
  if (!(slow_distance_m > stop_distance_m)) {
    *error = "slow_distance_m must be greater than stop_distance_m";
    return false;
  }
  if (sonar_max_age <= Duration::zero() || !Positive(sonar_arc_step_m)) {
    *error = "sonar_max_age and sonar_arc_step_m must be positive";
    return false;
  }
  if (!(unknown_scan_speed_factor >= 0 && unknown_scan_speed_factor <= 1)) {
    *error = "unknown_scan_speed_factor must be in [0, 1]";
    return false;
  }
  return true;
}

const char* CommandVerdictName(CommandVerdict verdict) {
  switch (verdict) {
    case CommandVerdict::kAccepted:
      return "accepted";
    case CommandVerdict::kRejectedNotHolder:
      return "rejected: not the lease holder";
    case CommandVerdict::kRejectedOutOfOrder:
      return "rejected: out of order";
    case CommandVerdict::kRejectedStale:
      return "rejected: stale";
    case CommandVerdict::kRejectedInvalid:
      return "rejected: invalid velocity";
  }
  return "unknown";
}

std::vector<std::pair<std::string, uint64_t>> SafetyCounters::AsList() const {
  return {{"accepted", accepted},
          {"rejected_not_holder", rejected_not_holder},
          {"rejected_stale", rejected_stale},
          {"rejected_out_of_order", rejected_out_of_order},
          {"rejected_invalid", rejected_invalid},
          {"deadman_expiries", deadman_expiries},
          {"link_losses", link_losses},
          {"estops", estops},
          {"estop_refused", estop_refused},
          {"sender_restarts", sender_restarts},
          {"scans", scans},
          {"unknown_beams", unknown_beams},
          {"unknown_path_cycles", unknown_path_cycles},
          {"sonar_cycles", sonar_cycles},
          {"sonar_failed_readings", sonar_failed_readings},
          {"sonar_stale_cycles", sonar_stale_cycles},
          {"bumper_contacts", bumper_contacts},
          {"bumper_read_failures", bumper_read_failures}};
}

SafetyGovernor::SafetyGovernor(const Clock& clock, const SafetyOptions& options)
    : clock_(clock), options_(options), ready_to_arm_(!options.require_arm_at_start) {}

void SafetyGovernor::DisarmLocked() {
  armed_ = false;
  ready_to_arm_ = false;
  target_linear_mps_ = 0;
  target_angular_radps_ = 0;
}

void SafetyGovernor::LinkLostLocked() {
  if (armed_) rearm_required_ = true;
  DisarmLocked();
  command_fresh_ = false;
}

void SafetyGovernor::SetLeaseHolder(const std::string& holder_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (holder_id == holder_id_) return;
  holder_id_ = holder_id;
  DisarmLocked();
  ready_to_arm_ = !options_.require_arm_at_start;
  rearm_required_ = false;
  have_command_ = false;
  command_fresh_ = false;
  delays_.clear();
}

bool SafetyGovernor::IsStaleLocked(const VelocityCommand& command, std::optional<Duration> offset,
                                   SteadyTime now_steady, Time now) {
  if (offset) {
    const Duration age = now - (command.stamp + *offset);
    // A stamp from the future beyond the same tolerance means a wrong offset: refuse it too.
    return age > options_.max_command_age || age < -options_.max_command_age;
  }
  // Offset unknown: apparent delay = robot steady time - sender stamp = true delay + an
  // unknown constant. Compare with the smallest apparent delay over the window.
  const int64_t apparent_ns =
      now_steady.time_since_epoch().count() - command.stamp.time_since_epoch().count();
  while (!delays_.empty() && delays_.back().apparent_ns >= apparent_ns) delays_.pop_back();
  delays_.push_back(DelaySample{now_steady, apparent_ns});
  while (delays_.front().arrival < now_steady - options_.delay_window) delays_.pop_front();
  const int64_t excess_ns = apparent_ns - delays_.front().apparent_ns;
  return Duration(excess_ns) > options_.max_command_age;
}

CommandVerdict SafetyGovernor::HandleCommand(const VelocityCommand& command,
                                             std::optional<Duration> robot_minus_sender) {
  const SteadyTime now_steady = clock_.SteadyNow();
  const Time now = clock_.Now();
  std::lock_guard<std::mutex> lock(mutex_);
  if (holder_id_.empty() || command.sender_id != holder_id_) {
    ++counters_.rejected_not_holder;
    return CommandVerdict::kRejectedNotHolder;
  }
  if (!std::isfinite(command.linear_mps) || !std::isfinite(command.angular_radps)) {
    ++counters_.rejected_invalid;
    return CommandVerdict::kRejectedInvalid;
  }
  bool restart = false;
  if (have_command_ && command.sequence <= last_sequence_) {
    restart =
        command.sequence < last_sequence_ && command.stamp > last_stamp_ + options_.deadman_period;
    if (!restart) {
      ++counters_.rejected_out_of_order;
      return CommandVerdict::kRejectedOutOfOrder;
    }
  }
  if (restart) delays_.clear();  // the sender's clock may have changed too
  if (IsStaleLocked(command, robot_minus_sender, now_steady, now)) {
    ++counters_.rejected_stale;
    return CommandVerdict::kRejectedStale;
  }
  if (restart) ++counters_.sender_restarts;
  ++counters_.accepted;
  have_command_ = true;
  last_sequence_ = command.sequence;
  last_stamp_ = command.stamp;
  last_arrival_ = now_steady;
  command_fresh_ = true;

  if (!command.enable) {
    DisarmLocked();
    ready_to_arm_ = true;
    return CommandVerdict::kAccepted;
  }
  if (!armed_ && ready_to_arm_ && !estop_ && bumper_readable_) {
    armed_ = true;
    rearm_required_ = false;
    bumper_latched_ = 0;  // the pilot's re-arm releases the bumper latch
  }
  if (armed_) {
    target_linear_mps_ =
        std::clamp(command.linear_mps, -options_.max_reverse_mps, options_.max_linear_mps);
    target_angular_radps_ =
        std::clamp(command.angular_radps, -options_.max_angular_radps, options_.max_angular_radps);
  }
  return CommandVerdict::kAccepted;
}

bool SafetyGovernor::HandleEmergencyStop(const EmergencyStop& estop, bool authorised) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!authorised) {
    ++counters_.estop_refused;
    return false;
  }
  if (estop.engage) {
    if (!estop_) ++counters_.estops;
    estop_ = true;
    estop_engaged_by_ = estop.sender_id;
    estop_reason_.clear();
    DisarmLocked();
    output_linear_mps_ = 0;
    output_angular_radps_ = 0;
  } else if (estop_) {
    estop_ = false;
    estop_engaged_by_.clear();
    estop_reason_.clear();
    DisarmLocked();
    rearm_required_ = true;
  }
  return true;
}

void SafetyGovernor::RestoreEstop(const std::string& engaged_by, const std::string& reason) {
  std::lock_guard<std::mutex> lock(mutex_);
  estop_ = true;
  estop_engaged_by_ = engaged_by;
  estop_reason_ = reason;
  DisarmLocked();
  output_linear_mps_ = 0;
  output_angular_radps_ = 0;
}

void SafetyGovernor::OnLinkLost(const std::string& client_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (client_id.empty() || client_id != holder_id_) return;
  ++counters_.link_losses;
  LinkLostLocked();
}

void SafetyGovernor::SetLaserScan(const LaserScan& scan) {
  std::vector<Point> points;
  std::vector<Direction> unknown;
  points.reserve(scan.ranges_m.size());
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const float r = scan.ranges_m[i];
    if (LaserScan::IsFreeRange(r)) continue;  // nothing up to the maximum range
    const double a = scan.AngleOf(i);
    if (!LaserScan::IsValidRange(r) || r < scan.range_min_m) {
      unknown.push_back(Direction{std::cos(a), std::sin(a)});
      continue;
    }
    points.push_back(Point{r * std::cos(a), r * std::sin(a)});
  }
  std::lock_guard<std::mutex> lock(mutex_);
  scan_points_ = std::move(points);
  unknown_beams_ = std::move(unknown);
  scan_range_max_m_ = scan.range_max_m;
  scan_stamp_ = scan.stamp;
  have_scan_ = true;
  ++counters_.scans;
  counters_.unknown_beams += unknown_beams_.size();
}

void SafetyGovernor::SetSonarRanges(const SonarRanges& ranges) {
  std::vector<Point> points;
  std::vector<Direction> unknown;
  std::optional<Time> oldest;
  uint64_t failed = 0;
  for (const SonarRange& r : ranges.ranges) {
    if (!oldest || r.stamp < *oldest) oldest = r.stamp;
    const SonarMount& m = r.mount;
    const double fov = std::isfinite(r.field_of_view_rad) && r.field_of_view_rad > 0
                           ? static_cast<double>(r.field_of_view_rad)
                           : 0.0;
    if (LaserScan::IsFreeRange(r.range_m)) continue;  // no echo within the window
    if (!std::isfinite(r.range_m) || r.range_m <= 0) {
      ++failed;  // the sensor failed: anything may be in its cone
      for (int k = 0; k < kFailedSonarRays; ++k) {
        const double a = m.yaw_rad + fov * (k / (kFailedSonarRays - 1.0) - 0.5);
        unknown.push_back(Direction{std::cos(a), std::sin(a), m.x_m, m.y_m});
      }
      continue;
    }
    // The echo may come from anywhere across the cone at that range: an arc of points.
    const double d = std::max<double>(r.range_m, r.min_range_m);
    const int n = std::max(2, static_cast<int>(std::ceil(fov * d / options_.sonar_arc_step_m)) + 1);
    for (int j = 0; j < n; ++j) {
      const double a = m.yaw_rad + fov * (j / (n - 1.0) - 0.5);
      points.push_back(Point{m.x_m + d * std::cos(a), m.y_m + d * std::sin(a)});
    }
  }
  std::lock_guard<std::mutex> lock(mutex_);
  sonar_points_ = std::move(points);
  sonar_unknown_ = std::move(unknown);
  sonar_stamp_ = oldest.value_or(Time{});
  have_sonar_ = oldest.has_value();
  ++counters_.sonar_cycles;
  counters_.sonar_failed_readings += failed;
}

void SafetyGovernor::StopAtOnceLocked() {
  DisarmLocked();
  rearm_required_ = true;
  output_linear_mps_ = 0;
  output_angular_radps_ = 0;
}

void SafetyGovernor::SetBumpers(uint32_t pressed, int segments, bool readable,
                                const std::string& error) {
  std::lock_guard<std::mutex> lock(mutex_);
  bumper_segments_ = std::clamp(segments, 0, 32);
  if (bumper_segments_ < 32) pressed &= (1u << bumper_segments_) - 1;
  if (!readable) {
    ++counters_.bumper_read_failures;
    bumper_readable_ = false;
    bumper_error_ = error;
    StopAtOnceLocked();
    return;
  }
  bumper_readable_ = true;
  bumper_error_.clear();
  const uint32_t new_contacts = pressed & ~bumper_pressed_;
  bumper_pressed_ = pressed;
  if (new_contacts != 0) {
    ++counters_.bumper_contacts;
    bumper_latched_ |= new_contacts;
    StopAtOnceLocked();
  }
}

double SafetyGovernor::PathDistance(const Point& p, double curvature) const {
  const double half_width = 0.5 * options_.robot_width_m + options_.lateral_margin_m;
  if (std::abs(curvature) < 1e-3) {
    return p.x_m > 0 && std::abs(p.y_m) <= half_width ? p.x_m - options_.front_extent_m : kInf;
  }
  // Arc of radius |R| about the centre (0, R); the band |rho - |R|| <= half_width is swept.
  const double radius = 1.0 / curvature;
  const double direction = radius > 0 ? 1.0 : -1.0;  // counter-clockwise for left turns
  const double bx = p.x_m;
  const double by = p.y_m - radius;
  const double rho = std::hypot(bx, by);
  if (std::abs(rho - std::abs(radius)) > half_width) return kInf;
  // Angle travelled from the robot (at (0, -R) from the centre) to the point.
  const double ax = 0;
  const double ay = -radius;
  double phi = std::atan2(direction * (ax * by - ay * bx), ax * bx + ay * by);
  if (phi < 0) phi += 2 * M_PI;
  if (phi > M_PI) return kInf;  // behind, or more than half a turn away
  return phi * std::abs(radius) - options_.front_extent_m;
}

double SafetyGovernor::FreeDistanceLocked(double linear_mps, double angular_radps) const {
  const double curvature = angular_radps / linear_mps;  // linear_mps > 0
  double best = kInf;
  for (const Point& p : scan_points_) best = std::min(best, PathDistance(p, curvature));
  if (last_sonar_fresh_ && have_sonar_) {
    for (const Point& p : sonar_points_) best = std::min(best, PathDistance(p, curvature));
  }
  return best;
}

int SafetyGovernor::UnknownBeamsInPathLocked(double linear_mps, double angular_radps) const {
  const bool sonar = last_sonar_fresh_ && have_sonar_ && !sonar_unknown_.empty();
  if (unknown_beams_.empty() && !sonar) return 0;
  const double curvature = angular_radps / linear_mps;  // linear_mps > 0
  // A point of the path less than slow_distance ahead of the bumper is at most this far from
  // the laser (an arc is longer than its chord, plus half the band's width).
  double reach_m = options_.front_extent_m + options_.slow_distance_m +
                   0.5 * options_.robot_width_m + options_.lateral_margin_m;
  if (std::isfinite(scan_range_max_m_) && scan_range_max_m_ > 0) {
    reach_m = std::min(reach_m, scan_range_max_m_);
  }
  int in_path = 0;
  auto count = [&](const std::vector<Direction>& rays, double reach) {
    for (const Direction& d : rays) {
      // The beam could end anywhere along its ray: it is in the path when some point of the
      // ray lies in the swept band ahead of the bumper, closer than the slow distance.
      for (double r = kUnknownBeamStepM; r <= reach; r += kUnknownBeamStepM) {
        const double s = PathDistance(Point{d.x_m + r * d.cos_a, d.y_m + r * d.sin_a}, curvature);
        if (s >= 0 && s < options_.slow_distance_m) {
          ++in_path;
          break;
        }
      }
    }
  };
  count(unknown_beams_, reach_m);
  // From a mount off the laser's origin: reach the same band (plus the mount's offset).
  if (sonar) {
    count(sonar_unknown_, options_.front_extent_m + options_.slow_distance_m +
                              options_.robot_width_m + options_.lateral_margin_m);
  }
  return in_path;
}

WatchdogState SafetyGovernor::StateLocked(SteadyTime /*now*/) const {
  if (estop_) return WatchdogState::kEstop;
  if (armed_ && command_fresh_) return WatchdogState::kDriving;
  if (output_linear_mps_ != 0 || output_angular_radps_ != 0) return WatchdogState::kStopping;
  if (rearm_required_ || bumper_latched_ != 0 || !bumper_readable_) {
    return WatchdogState::kWaitRearm;
  }
  return WatchdogState::kIdle;
}

GovernorOutput SafetyGovernor::Update() {
  const SteadyTime now_steady = clock_.SteadyNow();
  const Time now = clock_.Now();
  std::lock_guard<std::mutex> lock(mutex_);
  GovernorOutput out;

  // Deadman.
  if (command_fresh_ && now_steady - last_arrival_ > options_.deadman_period) {
    if (armed_) ++counters_.deadman_expiries;
    LinkLostLocked();
  }

  double dt_s = 0;
  if (last_update_) {
    dt_s = ToSeconds(std::clamp(now_steady - *last_update_, Duration::zero(), options_.max_cycle));
  }
  last_update_ = now_steady;

  double target_v = armed_ ? target_linear_mps_ : 0.0;
  const double target_w = armed_ ? target_angular_radps_ : 0.0;

  // Obstacles ahead.
  const Duration scan_age = now - scan_stamp_;
  out.scan_fresh =
      have_scan_ && scan_age <= options_.scan_max_age && scan_age >= -options_.scan_max_age;
  last_scan_fresh_ = out.scan_fresh;
  last_unknown_in_path_ = 0;
  const Duration sonar_age = now - sonar_stamp_;
  out.sonar_fresh =
      have_sonar_ && sonar_age <= options_.sonar_max_age && sonar_age >= -options_.sonar_max_age;
  const bool sonar_expected = options_.sonar_expected || counters_.sonar_cycles > 0;
  last_sonar_fresh_ = out.sonar_fresh || !sonar_expected;
  out.forward_limit_mps = options_.max_linear_mps;
  out.free_distance_m = kNaN;
  const double heading_v = target_v > 0 ? target_v : output_linear_mps_;
  if (heading_v > 0) {
    if (out.scan_fresh) {
      const double heading_w = target_v > 0 ? target_w : output_angular_radps_;
      out.free_distance_m = FreeDistanceLocked(heading_v, heading_w);
      const double scale = std::clamp((out.free_distance_m - options_.stop_distance_m) /
                                          (options_.slow_distance_m - options_.stop_distance_m),
                                      0.0, 1.0);
      out.forward_limit_mps = scale * options_.max_linear_mps;
      out.unknown_beams_in_path = UnknownBeamsInPathLocked(heading_v, heading_w);
      if (out.unknown_beams_in_path > 0) {
        out.forward_limit_mps = std::min(
            out.forward_limit_mps, options_.unknown_scan_speed_factor * options_.max_linear_mps);
        ++counters_.unknown_path_cycles;
      }
    } else {
      out.forward_limit_mps = options_.unknown_scan_speed_factor * options_.max_linear_mps;
    }
    if (!last_sonar_fresh_) {
      out.forward_limit_mps = std::min(
          out.forward_limit_mps, options_.unknown_scan_speed_factor * options_.max_linear_mps);
      ++counters_.sonar_stale_cycles;
    }
  }
  last_unknown_in_path_ = out.unknown_beams_in_path;
  target_v = std::min(target_v, out.forward_limit_mps);
  // A segment still pressed after the re-arm: no linear motion towards it.
  for (int i = 0; i < bumper_segments_; ++i) {
    if (!(bumper_pressed_ & (1u << i))) continue;
    const double c = std::cos(SegmentAngle(i, bumper_segments_));
    if (c > kSideSegmentCos) target_v = std::min(target_v, 0.0);
    if (c < -kSideSegmentCos) target_v = std::max(target_v, 0.0);
  }

  if (estop_) {
    output_linear_mps_ = 0;
    output_angular_radps_ = 0;
  } else {
    output_linear_mps_ = RampStep(output_linear_mps_, target_v, options_.max_linear_accel_mps2,
                                  options_.max_linear_decel_mps2, dt_s);
    output_angular_radps_ =
        RampStep(output_angular_radps_, target_w, options_.max_angular_accel_radps2,
                 options_.max_angular_decel_radps2, dt_s);
  }
  out.linear_mps = output_linear_mps_;
  out.angular_radps = output_angular_radps_;
  out.state = StateLocked(now_steady);
  return out;
}

SafetyStatus SafetyGovernor::status() const {
  const SteadyTime now_steady = clock_.SteadyNow();
  std::lock_guard<std::mutex> lock(mutex_);
  SafetyStatus s;
  s.state = StateLocked(now_steady);
  s.holder_id = holder_id_;
  s.armed = armed_;
  s.estop_engaged = estop_;
  s.estop_engaged_by = estop_engaged_by_;
  s.estop_reason = estop_reason_;
  if (have_command_) {
    s.last_command_age_s = static_cast<float>(ToSeconds(now_steady - last_arrival_));
    s.last_command_sequence = last_sequence_;
  }
  s.bumper_segments = bumper_segments_;
  s.bumper_pressed = bumper_pressed_;
  s.bumper_latched = bumper_latched_;
  s.bumper_readable = bumper_readable_;
  s.bumper_error = bumper_error_;
  s.counters = counters_;
  return s;
}

DeviceHealth SafetyGovernor::Health() const {
  const SafetyStatus s = status();
  bool scan_fresh;
  bool sonar_fresh;
  int unknown_in_path;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    scan_fresh = last_scan_fresh_;
    sonar_fresh = last_sonar_fresh_;
    unknown_in_path = last_unknown_in_path_;
  }
  DeviceHealth health;
  health.name = "drive_safety";
  const bool nominal = (s.state == WatchdogState::kIdle || s.state == WatchdogState::kDriving) &&
                       scan_fresh && sonar_fresh && unknown_in_path == 0 && s.bumper_latched == 0 &&
                       s.bumper_readable;
  health.state = nominal ? DeviceState::kOk : DeviceState::kWarn;
  std::ostringstream message;
  message << WatchdogStateName(s.state);
  if (s.estop_engaged) {
    message << " (e-stop " << (s.estop_engaged_by.empty() ? "latched" : "by " + s.estop_engaged_by);
    if (!s.estop_reason.empty()) message << ": " << s.estop_reason;
    message << ")";
  }
  message << ", holder " << (s.holder_id.empty() ? "none" : s.holder_id);
  if (s.bumper_latched != 0) {
    message << ", bumper contact on segment "
            << BumperSegmentList(s.bumper_latched, s.bumper_segments)
            << ": stopped until the pilot re-arms";
  }
  if (!s.bumper_readable) message << ", bumpers unreadable (" << s.bumper_error << "): stopped";
  if (!scan_fresh) message << ", no fresh scan";
  if (!sonar_fresh) message << ", no fresh sonar: speed capped";
  if (unknown_in_path > 0) {
    message << ", " << unknown_in_path
            << " unknown beams (laser or sonar) in the path: speed capped";
  }
  health.message = message.str();
  health.counters = s.counters.AsList();
  return health;
}

void SafetyGovernor::FillRobotHealth(RobotHealth* health) const {
  const SafetyStatus s = status();
  health->watchdog_state = s.state;
  health->last_command_age_s = s.last_command_age_s;
  health->last_command_sequence = s.last_command_sequence;
  health->estop_engaged = s.estop_engaged;
  health->lease_holder = s.holder_id;
}

}  // namespace mostar::drive
