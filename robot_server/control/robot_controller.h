// The robot's control loop, one Step() per control period: pilot lease liveliness, the safety
// governor's output to the motors, odometry, the lease and camera intrinsics (on change and
// every lease period), robot health (every health period) and the DDS-stall verdict.
//
// Inputs arrive on other threads: commands, e-stops and control requests from the network
// (OnCommand, OnEmergencyStop, OnControlRequest), scans from the laser's thread (OnScan) and
// sonar cycles from the sonar belt's thread (OnSonar), both wired by Start. All of them are
// thread-safe. Step() runs on one control thread; it reads the bumper belt every cycle before
// the governor decides (a contact stops the robot in the same cycle) and publishes the bumper
// state on change and every bumper period.
// Knows no DDS: it publishes through a RobotLink. Time comes from the injected clock; Step()
// takes the steady `now` of its cycle so tests drive it without sleeping.
#pragma once

#include <atomic>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "common/log/stamp_trace.h"
#include "common/time/rate_meter.h"
#include "common/time/time.h"
#include "common/types/commands.h"
#include "common/types/health.h"
#include "common/types/laser_scan.h"
#include "common/types/sonar.h"
#include "robot_server/bumper/bumper_belt.h"
#include "robot_server/drive/drive_motors.h"
#include "robot_server/drive/estop_latch_store.h"
#include "robot_server/drive/odometry.h"
#include "robot_server/drive/pilot_lease.h"
#include "robot_server/drive/safety_governor.h"
#include "robot_server/laser/laser_scanner.h"
#include "robot_server/node/robot_link.h"
#include "robot_server/sonar/sonar_ring.h"

namespace mostar::record {
class RecordingWriter;
}

namespace mostar::server {

struct RobotControllerOptions {
  std::string robot_id = "robot";
  Duration health_period = std::chrono::milliseconds(500);  // > 0
  Duration lease_period = std::chrono::seconds(1);          // > 0: lease re-published at least
  Duration bumper_period = std::chrono::seconds(1);  // > 0: bumper state re-published at least
  // A silent lease holder loses the lease after this long (> 0).
  Duration holder_timeout = drive::PilotLease::kDefaultHolderTimeout;
  // A network write blocked longer than this makes Step() return kWriteStalled; zero: never.
  Duration write_stall_limit = std::chrono::seconds(30);
  drive::OdometryOptions odometry;
  drive::SafetyOptions safety;
  drive::RoleTable roles;
  // Intrinsics published for the clients, left eye then right; empty when unknown.
  std::vector<CameraIntrinsicsInfo> intrinsics;

  bool IsValid(std::string* error) const;
};

// The devices the loop drives and reports on; not owned, outlive the controller.
struct RobotControllerDevices {
  drive::DriveMotors* motors = nullptr;  // required
  laser::LaserScanner* laser = nullptr;  // optional (no laser: scans never fresh)
  // Optional: the sonar belt (started by Start; its cycles are obstacles for the governor,
  // which then expects fresh cycles) and the bumper belt (read every Step).
  sonar::SonarRing* sonar = nullptr;
  bumper::BumperBelt* bumpers = nullptr;
  std::function<DeviceHealth()> camera_health;  // optional, thread-safe
  // Optional: the e-stop latch persisted across restarts. The controller starts it (and starts
  // latched when it says so), records every engagement and release (a release that cannot be
  // recorded does not take effect) and a clean stop in Stop().
  drive::EstopLatchStore* estop_latch = nullptr;
};

enum class StepResult {
  kRunning,
  // A network write has been blocked for longer than write_stall_limit (a DDS deadlock): the
  // motors were stopped; the caller should end the process (an orderly teardown would wait on
  // the blocked write) so that the service manager restarts it.
  kWriteStalled,
};

class RobotController {
 public:
  // `options` must be valid (checked). `link`, `clock` and `trace` (optional) outlive this.
  RobotController(const RobotControllerOptions& options, RobotControllerDevices devices,
                  RobotLink* link, const Clock* clock, StampTrace* trace = nullptr);
  ~RobotController();
  RobotController(const RobotController&) = delete;
  RobotController& operator=(const RobotController&) = delete;

  // Starts the laser (its scans go to OnScan) and the sonar belt (OnSonar). False with a
  // message when one cannot start.
  bool Start(std::string* error);
  // One control cycle at steady time `now`.
  StepResult Step(SteadyTime now);
  // Stops the laser and the sonar and brakes the motors. Idempotent.
  void Stop();

  // Records accepted commands, scans, odometry, lease and health from now on; null stops it.
  // The writer must stay open until it is replaced or Stop() returned.
  void SetRecorder(record::RecordingWriter* recorder) { recorder_ = recorder; }

  // Network inputs (any thread).
  void OnCommand(const VelocityCommand& command);
  void OnEmergencyStop(const EmergencyStop& stop);
  void OnControlRequest(const ControlRequest& request);
  // A release by someone at the robot (robot_server's SIGUSR2: root on the robot), the path
  // besides the lease holder's (docs/safety.md G10). Recorded first like any release; the
  // pilot must re-arm before driving. False when nothing was engaged or it cannot be recorded.
  bool ReleaseEstopLocally();
  // The DDS liveliness of `client_id`'s command stream was lost: when it holds the lease, the
  // lease is freed and the governor stops as for a link loss.
  void OnCommandStreamLost(const std::string& client_id);
  // Laser input (the laser's thread): to the governor, the link, the recorder.
  void OnScan(const LaserScan& scan);
  // Sonar input (the belt's thread): to the governor, the link, the recorder.
  void OnSonar(const SonarRanges& ranges);

  const drive::PilotLease& lease() const { return lease_; }
  const drive::SafetyGovernor& governor() const { return governor_; }
  uint64_t motor_errors() const { return motor_errors_; }

 private:
  void PublishLease();
  RobotHealth AssembleHealth(SteadyTime now);
  // Reads the bumper belt into the governor; publishes its state on change or when due.
  void ReadBumpers(SteadyTime now);
  // The belt's health with the latched segments named.
  DeviceHealth BumperHealth() const;

  const RobotControllerOptions options_;
  const RobotControllerDevices devices_;
  RobotLink* const link_;
  const Clock* const clock_;
  StampTrace* const trace_;
  drive::PilotLease lease_;
  drive::SafetyGovernor governor_;
  std::atomic<record::RecordingWriter*> recorder_{nullptr};
  std::atomic<bool> lease_changed_{true};

  // Control thread only.
  drive::OdometryIntegrator odometry_;
  RateMeter control_rate_;
  std::optional<SteadyTime> next_lease_;
  std::optional<SteadyTime> next_health_;
  std::optional<SteadyTime> next_bumpers_;
  std::optional<BumperState> last_bumpers_;
  uint64_t motor_errors_ = 0;
  bool stopped_ = false;
};

}  // namespace mostar::server
