#include "robot_server/control/robot_controller.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "common/check/check.h"
#include "common/log/log.h"
#include "common/record/recording_writer.h"

namespace mostar::server {
namespace {

// A fitted sonar belt is expected to deliver fresh cycles.
drive::SafetyOptions WithSonar(drive::SafetyOptions options, bool fitted) {
  options.sonar_expected = options.sonar_expected || fitted;
  return options;
}

bool SameBumpers(const BumperState& a, const BumperState& b) {
  return a.segment_count == b.segment_count && a.pressed == b.pressed && a.latched == b.latched &&
         a.readable == b.readable;
}

}  // namespace

bool RobotControllerOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (health_period <= Duration::zero()) return fail("health_period must be positive");
  if (lease_period <= Duration::zero()) return fail("lease_period must be positive");
  if (bumper_period <= Duration::zero()) return fail("bumper_period must be positive");
  if (holder_timeout <= Duration::zero()) return fail("holder_timeout must be positive");
  if (write_stall_limit < Duration::zero()) return fail("write_stall_limit must not be negative");
  if (intrinsics.size() > 2) return fail("at most two intrinsics (left, right)");
  std::string why;
  if (!odometry.IsValid(&why)) return fail("odometry: " + why);
  if (!safety.IsValid(&why)) return fail("safety: " + why);
  return true;
}

RobotController::RobotController(const RobotControllerOptions& options,
                                 RobotControllerDevices devices, RobotLink* link,
                                 const Clock* clock, StampTrace* trace)
    : options_(options),
      devices_(std::move(devices)),
      link_(link),
      clock_(clock),
      trace_(trace),
      lease_(*clock, options.roles, options.holder_timeout),
      governor_(*clock, WithSonar(options.safety, devices_.sonar != nullptr)),
      odometry_(options.odometry) {
  std::string error;
  MOSTAR_CHECK(options_.IsValid(&error)) << error;
  MOSTAR_CHECK(devices_.motors != nullptr && link_ != nullptr && clock_ != nullptr);
  if (devices_.estop_latch != nullptr) {
    const drive::EstopLatchDecision latch = devices_.estop_latch->Start();
    if (latch.latched) {
      governor_.RestoreEstop(latch.engaged_by, latch.reason);
      MOSTAR_LOG(WARNING) << "starting with the e-stop engaged: " << latch.reason;
    }
  }
}

RobotController::~RobotController() { Stop(); }

bool RobotController::Start(std::string* error) {
  if (devices_.laser != nullptr &&
      !devices_.laser->Start([this](const LaserScan& scan) { OnScan(scan); }, error)) {
    *error = "laser: " + *error;
    return false;
  }
  if (devices_.sonar != nullptr &&
      !devices_.sonar->Start([this](const SonarRanges& ranges) { OnSonar(ranges); }, error)) {
    *error = "sonar: " + *error;
    return false;
  }
  return true;
}

void RobotController::Stop() {
  if (stopped_) return;
  stopped_ = true;
  if (devices_.laser != nullptr) devices_.laser->Stop();
  if (devices_.sonar != nullptr) devices_.sonar->Stop();
  std::string error;
  if (!devices_.motors->Stop(&error)) MOSTAR_LOG(ERROR) << "motors: stop failed: " << error;
  if (devices_.estop_latch != nullptr) {
    const drive::SafetyStatus status = governor_.status();
    if (!devices_.estop_latch->RecordCleanStop(status.estop_engaged, status.estop_engaged_by,
                                               &error)) {
      MOSTAR_LOG(ERROR) << "e-stop latch: " << error;
    }
  }
}

void RobotController::OnCommand(const VelocityCommand& command) {
  const drive::CommandVerdict verdict =
      governor_.HandleCommand(command, link_->RobotMinusClient(command.sender_id));
  if (verdict != drive::CommandVerdict::kAccepted) {
    MOSTAR_LOG_EVERY_SEC(DEBUG, 2)
        << "command " << command.sequence << " from " << command.sender_id << ": "
        << drive::CommandVerdictName(verdict);
    return;
  }
  // Only accepted commands keep the holder alive: a rejected stream (stale, out of order, not
  // the holder) is no sign of a pilot in control.
  lease_.NoteAlive(command.sender_id);
  if (trace_) {
    trace_->Add("command", command.stamp, command.sequence);
    trace_->Add("command_rx", clock_->Now(), command.sequence);  // robot clock, on arrival
  }
  if (record::RecordingWriter* recorder = recorder_.load()) recorder->Write(command);
}

void RobotController::OnEmergencyStop(const EmergencyStop& stop) {
  const bool authorised =
      stop.engage ? lease_.MayEngageEstop(stop.sender_id) : lease_.MayReleaseEstop(stop.sender_id);
  std::string error;
  const bool was_engaged = governor_.status().estop_engaged;
  // A release takes effect only once recorded (else a restart could come back unlatched); an
  // engagement takes effect at once and is recorded after (once: clients repeat it).
  if (authorised && !stop.engage && was_engaged && devices_.estop_latch != nullptr &&
      !devices_.estop_latch->Record(false, "", &error)) {
    MOSTAR_LOG(ERROR) << "emergency stop release from " << stop.sender_id
                      << " refused: cannot record it: " << error;
    return;
  }
  governor_.HandleEmergencyStop(stop, authorised);
  if (authorised && stop.engage && !was_engaged && devices_.estop_latch != nullptr &&
      !devices_.estop_latch->Record(true, stop.sender_id, &error)) {
    MOSTAR_LOG(ERROR) << "e-stop latch: " << error;
  }
  MOSTAR_LOG(WARNING) << "emergency stop " << (stop.engage ? "engage" : "release") << " from "
                      << stop.sender_id << (authorised ? "" : " refused (not authorised)");
}

bool RobotController::ReleaseEstopLocally() {
  if (!governor_.status().estop_engaged) return false;
  std::string error;
  if (devices_.estop_latch != nullptr && !devices_.estop_latch->Record(false, "", &error)) {
    MOSTAR_LOG(ERROR) << "local emergency stop release refused: cannot record it: " << error;
    return false;
  }
  EmergencyStop release;
  release.sender_id = "local";
  release.engage = false;
  governor_.HandleEmergencyStop(release, /*authorised=*/true);
  MOSTAR_LOG(WARNING) << "emergency stop released locally (at the robot); the pilot must re-arm";
  return true;
}

void RobotController::OnControlRequest(const ControlRequest& request) {
  const drive::LeaseDecision decision = lease_.HandleRequest(request);
  governor_.SetLeaseHolder(lease_.holder());
  lease_changed_ = true;
  MOSTAR_LOG(INFO) << "control " << (request.take ? "take" : "release") << " by "
                   << request.sender_id << ": " << drive::LeaseDecisionName(decision)
                   << "; holder now '" << lease_.holder() << "'";
}

void RobotController::OnCommandStreamLost(const std::string& client_id) {
  if (!lease_.OnLivelinessLost(client_id)) return;  // not the holder
  governor_.OnLinkLost(client_id);
  governor_.SetLeaseHolder(lease_.holder());
  lease_changed_ = true;
  MOSTAR_LOG(WARNING) << "pilot '" << client_id << "' lost its command stream: lease released";
}

void RobotController::OnScan(const LaserScan& scan) {
  governor_.SetLaserScan(scan);
  link_->PublishScan(scan);
  if (record::RecordingWriter* recorder = recorder_.load()) recorder->Write(scan);
  if (trace_) trace_->Add("scan", scan.stamp, scan.sequence);
}

void RobotController::OnSonar(const SonarRanges& ranges) {
  governor_.SetSonarRanges(ranges);
  link_->PublishSonar(ranges);
  if (record::RecordingWriter* recorder = recorder_.load()) recorder->Write(ranges);
}

void RobotController::ReadBumpers(SteadyTime now) {
  uint32_t pressed = 0;
  std::string error;
  const bool readable = devices_.bumpers->Read(&pressed, &error);
  governor_.SetBumpers(pressed, devices_.bumpers->segments(), readable, error);
  const drive::SafetyStatus status = governor_.status();
  BumperState state;
  state.stamp = clock_->Now();
  state.segment_count = status.bumper_segments;
  state.pressed = status.bumper_pressed;
  state.latched = status.bumper_latched;
  state.readable = status.bumper_readable;
  const bool changed = !last_bumpers_ || !SameBumpers(*last_bumpers_, state);
  if (!readable) {
    MOSTAR_LOG_EVERY_SEC(ERROR, 5) << "bumpers unreadable (" << error << "): robot stopped";
  }
  const uint32_t new_latches = state.latched & ~(last_bumpers_ ? last_bumpers_->latched : 0u);
  if (new_latches != 0) {
    MOSTAR_LOG(WARNING) << "bumper contact on segment "
                        << drive::BumperSegmentList(new_latches, state.segment_count)
                        << ": robot stopped until the pilot re-arms";
  }
  if (!changed && next_bumpers_ && now < *next_bumpers_) return;
  next_bumpers_ = now + options_.bumper_period;
  last_bumpers_ = state;
  link_->PublishBumpers(state);
  if (record::RecordingWriter* recorder = recorder_.load()) recorder->Write(state);
}

DeviceHealth RobotController::BumperHealth() const {
  DeviceHealth health = devices_.bumpers->Health();
  const drive::SafetyStatus status = governor_.status();
  if (status.bumper_latched != 0) {
    if (health.state == DeviceState::kOk) health.state = DeviceState::kWarn;
    health.message += std::string(health.message.empty() ? "" : "; ") + "contact on segment " +
                      drive::BumperSegmentList(status.bumper_latched, status.bumper_segments) +
                      ": robot stopped until the pilot re-arms";
  }
  health.counters.emplace_back("latched_mask", status.bumper_latched);
  return health;
}

StepResult RobotController::Step(SteadyTime now) {
  // A holder that went silent loses the lease: nobody inherits motion.
  if (const std::optional<std::string> lost = lease_.ExpireSilentHolder(now)) {
    governor_.OnLinkLost(*lost);
    governor_.SetLeaseHolder(lease_.holder());
    lease_changed_ = true;
    MOSTAR_LOG(WARNING) << "pilot '" << *lost << "' went silent: lease released";
  }
  std::string error;
  if (options_.write_stall_limit > Duration::zero() &&
      link_->BlockedWriteDuration(now) > options_.write_stall_limit) {
    devices_.motors->Stop(&error);
    return StepResult::kWriteStalled;
  }
  if (devices_.bumpers != nullptr) ReadBumpers(now);
  const drive::GovernorOutput out = governor_.Update();
  if (trace_) {
    trace_->Add("drive_out_mmps", clock_->Now(),
                static_cast<uint64_t>(std::llround(std::abs(out.linear_mps) * 1000)));
  }
  if (!devices_.motors->SetVelocity(out.linear_mps, out.angular_radps, &error)) {
    ++motor_errors_;
    MOSTAR_LOG_EVERY_SEC(WARNING, 5) << "motors: " << error;
  }
  drive::EncoderReading reading;
  if (devices_.motors->ReadEncoders(&reading, &error) && odometry_.AddReading(reading)) {
    const Odometry& odometry = odometry_.odometry();
    link_->PublishOdometry(odometry);
    if (record::RecordingWriter* recorder = recorder_.load()) recorder->Write(odometry);
    if (trace_) {
      trace_->Add("odom_x_mm", odometry.stamp,
                  static_cast<uint64_t>(std::max(0.0, odometry.pose.x_m * 1000)));
    }
  }
  control_rate_.Tick(now);
  if (lease_changed_.exchange(false) || !next_lease_ || now >= *next_lease_) {
    next_lease_ = now + options_.lease_period;
    PublishLease();
  }
  if (!next_health_ || now >= *next_health_) {
    next_health_ = now + options_.health_period;
    const RobotHealth health = AssembleHealth(now);
    link_->PublishHealth(health);
    if (record::RecordingWriter* recorder = recorder_.load()) recorder->Write(health);
  }
  return StepResult::kRunning;
}

void RobotController::PublishLease() {
  const ControlLease current = lease_.lease();
  link_->PublishLease(current);
  for (size_t e = 0; e < options_.intrinsics.size(); ++e) {
    CameraIntrinsicsInfo info = options_.intrinsics[e];
    info.stamp = clock_->Now();
    link_->PublishCameraInfo(e == 0 ? Eye::kLeft : Eye::kRight, info);
  }
  if (trace_)
    trace_->Add(("lease:" + current.holder_id).c_str(), current.stamp, current.lease_sequence);
  if (record::RecordingWriter* recorder = recorder_.load()) recorder->Write(current);
}

RobotHealth RobotController::AssembleHealth(SteadyTime now) {
  RobotHealth health;
  health.stamp = clock_->Now();
  health.robot_id = options_.robot_id;
  governor_.FillRobotHealth(&health);
  health.lease_holder = lease_.holder();
  if (devices_.camera_health) health.devices.push_back(devices_.camera_health());
  if (devices_.laser != nullptr) health.devices.push_back(devices_.laser->Health());
  if (devices_.sonar != nullptr) health.devices.push_back(devices_.sonar->Health());
  if (devices_.bumpers != nullptr) health.devices.push_back(BumperHealth());
  health.devices.push_back(governor_.Health());
  if (devices_.estop_latch != nullptr) health.devices.push_back(devices_.estop_latch->Health());
  DeviceHealth drive = devices_.motors->Health();
  drive.rate_hz = static_cast<float>(control_rate_.RateHz(now));
  drive.counters.emplace_back("motor_errors", motor_errors_);
  drive.counters.emplace_back("odometry_glitches", odometry_.stats().glitches);
  health.devices.push_back(std::move(drive));
  health.devices.push_back(link_->NetworkHealth());
  return health;
}

}  // namespace mostar::server
