// The safety governor: decides, every control cycle, the base velocity sent to the motors.
//
// Inputs (any thread): velocity commands, the lease holder (from PilotLease), e-stop events,
// link-loss events (DDS liveliness/deadline), laser scans. Output (control thread): `Update()`
// once per cycle gives (v, w) and the watchdog state. All times come from the injected Clock.
// docs/safety.md lists every rule with its default and its test. In short:
// - Only the lease holder's commands count; others are rejected and counted.
// - Commands must have strictly increasing sequence numbers (a sender restart, recognised by a
//   lower sequence with a stamp newer than the last accepted one by more than the deadman
//   period, starts a new sequence).
// - Commands older than `max_command_age` are ignored. The age uses the sender's clock offset
//   when known; otherwise the command's delay relative to the smallest delay seen from this
//   sender over `delay_window` (a burst of commands queued during an outage shows up as a
//   delay jump even without knowing the offset).
// - Motion needs an armed pilot: a command with enable=false followed by one with
//   enable=true. Needed at start (configurable), after a lease change, after a link loss and
//   after an e-stop release.
// - No accepted command for `deadman_period`: the target becomes zero and the output ramps
//   down at the deceleration limits; if the pilot was armed this is a link loss and re-arming
//   is required.
// - Velocity, reverse and acceleration/deceleration limits.
// - E-stop latches zero output at once (no ramp) until released.
// - Forward speed is capped by the free distance along the path ahead (straight corridor or
//   arc of the commanded curvature, robot width plus margin): zero at `stop_distance_m`, full
//   at `slow_distance_m`, linear between. A missing or stale scan caps it at
//   `unknown_scan_speed_factor` of the maximum, and so does a beam of unknown space (NaN: a
//   laser error code such as dazzle; anything but a range or +Inf) that crosses the swept path
//   ahead of the bumper closer than `slow_distance_m`: an obstacle may hide behind it. Only
//   +Inf (no echo, beyond range) counts as free. Reverse (unseen by the front laser) is limited
//   by `max_reverse_mps` only; rotation in place is always allowed.
// - Sonar (SetSonarRanges): each reading of a fresh belt cycle is an obstacle arc across its
//   cone at its range, from its mount (base frame), for the same free-distance check; a failed
//   sensor (NaN) is unknown space across its cone like a laser error beam. A cycle older than
//   `sonar_max_age` is not used: once a belt is expected (`sonar_expected`, or after its first
//   cycle) forward speed is then capped as for a missing scan.
// - Bumpers (SetBumpers, every cycle before Update): a new contact stops the robot at once (no
//   ramp) and latches the segment until the pilot re-arms (state kWaitRearm); an unreadable belt
//   stops it too and arming waits until the belt reads again. A segment still pressed after the
//   re-arm blocks the linear motion towards it (front half: forward; rear half: reverse).
// Thread-safe (one internal mutex).
#pragma once

#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/time/time.h"
#include "common/types/commands.h"
#include "common/types/health.h"
#include "common/types/laser_scan.h"
#include "common/types/sonar.h"

namespace mostar::drive {

struct SafetyOptions {
  // Limits. unit: m/s, rad/s, m/s^2, rad/s^2; all positive.
  double max_linear_mps = 0.6;
  double max_reverse_mps = 0.2;
  double max_angular_radps = 1.0;
  double max_linear_accel_mps2 = 0.5;
  double max_linear_decel_mps2 = 1.0;
  double max_angular_accel_radps2 = 1.5;
  double max_angular_decel_radps2 = 3.0;

  // Command freshness.
  Duration deadman_period = std::chrono::milliseconds(250);
  Duration max_command_age = std::chrono::milliseconds(300);
  Duration delay_window = std::chrono::seconds(10);  // offset unknown: minimum-delay window
  bool require_arm_at_start = true;

  // Obstacles. Base frame = laser frame in x/y (base origin on the floor under the laser).
  double robot_width_m = 0.60;
  double lateral_margin_m = 0.05;  // added on each side of the corridor
  double front_extent_m = 0.20;    // from the base origin forward to the front bumper
  double stop_distance_m = 0.30;   // free space ahead of the bumper at which forward speed is 0
  double slow_distance_m = 1.20;   // free space from which full forward speed is allowed
  Duration scan_max_age = std::chrono::milliseconds(500);
  double unknown_scan_speed_factor = 0.3;  // in [0, 1]

  // Sonar belt. Mounts are in the base frame (= laser frame in x/y).
  bool sonar_expected = false;  // a belt is fitted: no fresh cycle caps forward speed
  Duration sonar_max_age = std::chrono::milliseconds(1000);  // > 0; older cycles are not used
  double sonar_arc_step_m = 0.05;  // > 0: spacing of the obstacle points along a reading's arc

  // A longer gap between two Update() calls is treated as this long (bounds one ramp step).
  Duration max_cycle = std::chrono::milliseconds(100);

  bool IsValid(std::string* error) const;
};

enum class CommandVerdict : uint8_t {
  kAccepted = 0,
  kRejectedNotHolder = 1,
  kRejectedOutOfOrder = 2,
  kRejectedStale = 3,
  kRejectedInvalid = 4,  // NaN or infinite velocity
};
const char* CommandVerdictName(CommandVerdict verdict);

struct SafetyCounters {
  uint64_t accepted = 0;
  uint64_t rejected_not_holder = 0;
  uint64_t rejected_stale = 0;
  uint64_t rejected_out_of_order = 0;
  uint64_t rejected_invalid = 0;
  uint64_t deadman_expiries = 0;  // while armed (link loss seen by the watchdog)
  uint64_t link_losses = 0;       // OnLinkLost events for the holder
  uint64_t estops = 0;            // engagements
  uint64_t estop_refused = 0;     // unauthorised engage or release
  uint64_t sender_restarts = 0;
  uint64_t scans = 0;
  uint64_t unknown_beams = 0;        // beams of unknown space (error codes) in the scans received
  uint64_t unknown_path_cycles = 0;  // cycles capped by unknown beams in the path ahead
  uint64_t sonar_cycles = 0;
  uint64_t sonar_failed_readings = 0;  // NaN readings (sensor failed), unknown space
  uint64_t sonar_stale_cycles = 0;     // control cycles capped because no fresh sonar cycle
  uint64_t bumper_contacts = 0;        // contacts that stopped the robot and latched
  uint64_t bumper_read_failures = 0;   // control cycles whose bumper reading failed
  std::vector<std::pair<std::string, uint64_t>> AsList() const;
};

// What one control cycle decided.
struct GovernorOutput {
  double linear_mps = 0;  // send these to the motors
  double angular_radps = 0;
  WatchdogState state = WatchdogState::kIdle;
  double forward_limit_mps = 0;  // obstacle cap on forward speed this cycle
  // Free distance ahead of the bumper along the target path; +inf when clear, NaN when the
  // scan is missing or stale or when not driving forward.
  double free_distance_m = 0;
  bool scan_fresh = false;
  // Beams of unknown space crossing the path ahead (0 when not driving forward); any caps the
  // forward speed like a missing scan.
  int unknown_beams_in_path = 0;
  // Sonar obstacles were used this cycle (a fresh belt cycle).
  bool sonar_fresh = false;
};

struct SafetyStatus {
  WatchdogState state = WatchdogState::kIdle;
  std::string holder_id;
  bool armed = false;
  bool estop_engaged = false;
  std::string estop_engaged_by;
  std::string estop_reason;       // of a latch restored at start (RestoreEstop), else ""
  float last_command_age_s = -1;  // since the last accepted command arrived; -1 never
  uint64_t last_command_sequence = 0;
  // Bumpers (SetBumpers): segments, pressed now, latched until the re-arm, readable.
  int bumper_segments = 0;
  uint32_t bumper_pressed = 0;
  uint32_t bumper_latched = 0;
  bool bumper_readable = true;
  std::string bumper_error;  // of the last failed reading while unreadable
  SafetyCounters counters;
};

// "0 (0 deg), 15 (338 deg)": the segments of `mask` among `segments` with their centre angle
// counter-clockwise from straight ahead; "" for an empty mask.
std::string BumperSegmentList(uint32_t mask, int segments);

class SafetyGovernor {
 public:
  SafetyGovernor(const Clock& clock, const SafetyOptions& options);

  // Sets who may drive (PilotLease::holder()); "" = nobody. A change disarms and clears the
  // command history; the output ramps down.
  void SetLeaseHolder(const std::string& holder_id);

  // A velocity command as received. `robot_minus_sender`: the sender's clock offset
  // (robot clock minus sender clock) when known.
  CommandVerdict HandleCommand(const VelocityCommand& command,
                               std::optional<Duration> robot_minus_sender = std::nullopt);

  // E-stop event. `authorised` comes from PilotLease::MayEngageEstop / MayReleaseEstop.
  // Returns false (and counts) when refused.
  bool HandleEmergencyStop(const EmergencyStop& estop, bool authorised);
  // Starts latched, as the previous run left the e-stop (EstopLatchStore): like an engagement
  // by `engaged_by` ("" when nobody engaged it, e.g. after an unclean stop), with `reason` in the
  // health message until the next engagement or release.
  void RestoreEstop(const std::string& engaged_by, const std::string& reason);

  // The client's DDS liveliness or command deadline was lost. Acts like an immediate deadman
  // expiry when it is the holder.
  void OnLinkLost(const std::string& client_id);

  // The latest scan (laser frame; stamp on the robot's wall clock). A range is an obstacle,
  // +Inf free space, anything else (NaN, -Inf, below range_min_m) unknown space.
  void SetLaserScan(const LaserScan& scan);

  // The latest sonar belt cycle (mounts in the base frame; stamps on the robot's wall clock).
  // Finite range: obstacle arc at max(range, min_range_m); +Inf: free; NaN or other: unknown.
  void SetSonarRanges(const SonarRanges& ranges);

  // The bumper belt's reading of this control cycle (`segments` 1..32, bit i = segment i
  // centred at i x 360/segments deg CCW from ahead). `readable` false: the contacts cannot be
  // read (`error` says why). Call before Update().
  void SetBumpers(uint32_t pressed, int segments, bool readable, const std::string& error = "");

  // One control cycle: call at a steady rate (e.g. 50 Hz) and send the result to the motors.
  GovernorOutput Update();

  SafetyStatus status() const;
  // "drive_safety": kOk while idle or driving with a fresh scan, kWarn otherwise.
  DeviceHealth Health() const;
  // Sets watchdog_state, last_command_age_s, last_command_sequence, estop_engaged,
  // lease_holder.
  void FillRobotHealth(RobotHealth* health) const;

 private:
  struct DelaySample {
    SteadyTime arrival;
    int64_t apparent_ns;
  };
  struct Point {
    double x_m;
    double y_m;
  };
  struct Direction {  // ray of unknown space from (x_m, y_m), base (= laser) frame
    double cos_a;
    double sin_a;
    double x_m = 0;
    double y_m = 0;
  };

  void DisarmLocked();
  void LinkLostLocked();
  bool IsStaleLocked(const VelocityCommand& command, std::optional<Duration> offset,
                     SteadyTime now_steady, Time now);
  double FreeDistanceLocked(double linear_mps, double angular_radps) const;
  // Free distance ahead of the bumper to `p` along the path of `curvature` (1/m, CCW > 0);
  // +inf when p is outside the swept band (or more than half a turn away).
  double PathDistance(const Point& p, double curvature) const;
  int UnknownBeamsInPathLocked(double linear_mps, double angular_radps) const;
  WatchdogState StateLocked(SteadyTime now) const;
  // Bumper contact or unreadable belt: zero output at once, disarmed, re-arm required.
  void StopAtOnceLocked();

  const Clock& clock_;
  const SafetyOptions options_;
  mutable std::mutex mutex_;

  std::string holder_id_;
  // Command stream of the holder.
  bool have_command_ = false;
  uint64_t last_sequence_ = 0;
  Time last_stamp_;
  SteadyTime last_arrival_;
  bool command_fresh_ = false;      // an accepted command within the deadman period
  std::deque<DelaySample> delays_;  // increasing apparent delay (sliding-window minimum)

  // Arming.
  bool armed_ = false;
  bool ready_to_arm_ = false;    // saw enable=false since the last disarm
  bool rearm_required_ = false;  // after link loss or e-stop release (state kWaitRearm)
  double target_linear_mps_ = 0;
  double target_angular_radps_ = 0;

  bool estop_ = false;
  std::string estop_engaged_by_;
  std::string estop_reason_;  // why a restored latch is engaged; "" otherwise

  // Scan.
  std::vector<Point> scan_points_;
  std::vector<Direction> unknown_beams_;
  double scan_range_max_m_ = 0;  // 0 or non-finite: not limited
  Time scan_stamp_;
  bool have_scan_ = false;
  bool last_scan_fresh_ = false;
  int last_unknown_in_path_ = 0;

  // Sonar.
  std::vector<Point> sonar_points_;
  std::vector<Direction> sonar_unknown_;
  Time sonar_stamp_;  // oldest reading of the cycle
  bool have_sonar_ = false;
  bool last_sonar_fresh_ = true;  // for health; true while no belt is expected

  // Bumpers.
  int bumper_segments_ = 0;
  uint32_t bumper_pressed_ = 0;
  uint32_t bumper_latched_ = 0;
  bool bumper_readable_ = true;
  std::string bumper_error_;

  // Output.
  double output_linear_mps_ = 0;
  double output_angular_radps_ = 0;
  std::optional<SteadyTime> last_update_;

  SafetyCounters counters_;
};

}  // namespace mostar::drive
