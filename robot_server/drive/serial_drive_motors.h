// DriveMotors over a serial port to the MORDUC motor + encoder board (docs/motor_protocol.md).
//
// A reader thread decodes the board's frames (encoder reports, status, heartbeats) into the
// latest values; commands are written from the caller's thread. Wheel speeds are converted to
// encoder ticks per second with the geometry given here, the single source of it (the board
// knows no geometry). Encoder readings are stamped with the host clock on arrival.
// The port may be missing at start or vanish later (USB unplugged): the reader thread then
// opens it again every kReopenPeriod; meanwhile writes fail, Status().link_ok is false and the
// health says so. The destructor sends Stop and joins the reader.
#pragma once

#include <libserial/SerialPort.h>
#include <sys/types.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "common/time/time.h"
#include "robot_server/drive/drive_motors.h"
#include "robot_server/drive/motor_protocol.h"

namespace mostar::drive {

struct SerialDriveMotorsOptions {
  std::string port = "/dev/mostar-drive";  // udev symlink, see deploy/udev
  int baud = 115200;                       // 9600 .. 460800
  double wheel_radius_m = 0.10;
  double track_width_m = 0.50;
  double ticks_per_turn = 500;
  int counter_bits = 16;
  double max_wheel_speed_mps = 1.5;  // set-points are clamped to this
  // No frame from the board for this long: the link is down and ReadEncoders fails.
  Duration link_timeout = std::chrono::milliseconds(200);

  bool IsValid(std::string* error) const;
};

class SerialDriveMotors final : public DriveMotors {
 public:
  // Opens and configures the port (8N1, no flow control) and starts the reader; a port that
  // cannot be opened yet is retried by the reader. nullptr with a message for invalid options.
  static std::unique_ptr<SerialDriveMotors> Open(const Clock& clock,
                                                 const SerialDriveMotorsOptions& options,
                                                 std::string* error);
  ~SerialDriveMotors() override;

  bool SetWheelVelocities(const WheelVelocities& wheels, std::string* error) override;
  bool SetVelocity(double linear_mps, double angular_radps, std::string* error) override;
  bool Stop(std::string* error, bool clear_faults = false) override;
  MotorStatus Status() const override;
  bool ReadEncoders(EncoderReading* reading, std::string* error) override;
  int counter_bits() const override { return options_.counter_bits; }

  // Sends a heartbeat (the board echoes it); use while idle to keep the link observable.
  bool SendHeartbeat(std::string* error);
  // Decoder counters, for health reporting.
  MotorDecoderStats decoder_stats() const;
  // Whether the port is open now, and how many times it was opened.
  bool port_open() const { return port_open_.load(); }
  int port_opens() const { return port_opens_.load(); }
  static constexpr Duration kReopenPeriod = std::chrono::seconds(1);

 private:
  SerialDriveMotors(const Clock& clock, const SerialDriveMotorsOptions& options);
  bool Write(const MotorMessage& message, std::string* error);
  bool OpenPort(std::string* error);
  void ClosePortLocked();  // port_mutex_ held
  bool PortStillThere() const;
  void ReadLoop();
  void HandleMessage(const MotorMessage& message);

  const Clock& clock_;
  const SerialDriveMotorsOptions options_;
  const double ticks_per_metre_;
  std::mutex port_mutex_;  // open, close and write; the reader thread alone reads
  std::unique_ptr<LibSerial::SerialPort> port_;  // null while closed
  std::atomic<bool> port_open_{false};
  std::atomic<int> port_opens_{0};
  dev_t port_device_ = 0;  // st_rdev of the open port (reader thread and OpenPort only)
  std::mutex write_mutex_;
  uint16_t next_sequence_ = 0;  // guarded by write_mutex_

  mutable std::mutex state_mutex_;
  std::optional<EncoderReading> latest_reading_;
  std::optional<SteadyTime> last_frame_;
  StatusMsg last_status_;
  bool have_status_ = false;
  uint64_t frames_received_ = 0;
  uint64_t bad_frames_ = 0;
  uint64_t write_errors_ = 0;
  MotorDecoderStats decoder_stats_;

  std::atomic<bool> running_{true};
  std::thread reader_;
};

}  // namespace mostar::drive
