// The drive motors of a differential-drive base, with the wheel encoders of the same board.
//
// Contract:
// - Speeds are wheel rim speeds in m/s, positive drives the robot forward; (v, w) is the base
//   velocity (m/s forward, rad/s counter-clockwise) converted with the track width.
// - Set-points are held by the device for a short time only: the caller must repeat them every
//   control cycle (the MORDUC board stops by itself 300 ms after the last set-point). This
//   interface does no safety checking: the SafetyGovernor decides what is sent.
// - Stop() brakes now. It is also the right call on shutdown and on any doubt.
// - Calls come from one control thread; ReadEncoders() may be called from another thread.
//   Failures (port gone, board silent, board fault) return false with a message; the caller
//   counts and reports them and keeps calling (implementations reconnect if they can).
#pragma once

#include <cstdint>
#include <string>

#include "common/types/health.h"
#include "robot_server/drive/wheel_encoders.h"

namespace mostar::drive {

struct WheelVelocities {
  double left_mps = 0;
  double right_mps = 0;
};

// Base velocity -> wheel rim speeds.
inline WheelVelocities WheelsFromBase(double linear_mps, double angular_radps,
                                      double track_width_m) {
  return {linear_mps - 0.5 * track_width_m * angular_radps,
          linear_mps + 0.5 * track_width_m * angular_radps};
}

// What the board last said about itself.
struct MotorStatus {
  bool link_ok = false;      // frames from the board arrive
  bool driving = false;      // the board reports running speed loops
  bool fault = false;        // the board reports a fault (see fault_flags)
  uint16_t fault_flags = 0;  // device-specific bits (motor_protocol.h FaultFlag)
  double battery_v = 0;      // NaN or 0 when unknown
  uint64_t frames_received = 0;
  uint64_t bad_frames = 0;  // CRC, length or payload errors
  uint64_t write_errors = 0;
};

class DriveMotors : public WheelEncoders {
 public:
  // Commands wheel rim speeds (m/s). The device clamps to its own limits.
  virtual bool SetWheelVelocities(const WheelVelocities& wheels, std::string* error) = 0;
  // Commands a base velocity (m/s, rad/s), converted with the device's track width.
  virtual bool SetVelocity(double linear_mps, double angular_radps, std::string* error) = 0;
  // Brakes both wheels. `clear_faults` also asks the board to clear latched faults.
  virtual bool Stop(std::string* error, bool clear_faults = false) = 0;
  // Thread-safe snapshot.
  virtual MotorStatus Status() const = 0;
  // The board as the health device "drive": kError without a link, kWarn on a fault, the
  // board's frame counters. Callers add the control rate and their own counters. Thread-safe.
  virtual DeviceHealth Health() const { return HealthFromStatus(Status(), "motor fault"); }

 protected:
  // `fault_message`: what a fault means on this device.
  static DeviceHealth HealthFromStatus(const MotorStatus& status,
                                       const std::string& fault_message) {
    DeviceHealth health;
    health.name = "drive";
    health.state = !status.link_ok ? DeviceState::kError
                   : status.fault  ? DeviceState::kWarn
                                   : DeviceState::kOk;
    if (status.fault) health.message = fault_message;
    if (!status.link_ok) health.message = "no link to the motor board";
    health.counters = {{"board_frames", status.frames_received},
                       {"board_bad_frames", status.bad_frames},
                       {"board_write_errors", status.write_errors}};
    return health;
  }
};

}  // namespace mostar::drive
