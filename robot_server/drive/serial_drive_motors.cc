#include "robot_server/drive/serial_drive_motors.h"

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <iterator>
#include <thread>

#include "common/log/log.h"
#include "robot_server/serial/baud_rate.h"

namespace mostar::drive {
namespace {

// Rates the motor board accepts.
constexpr int kBoardBauds[] = {9600, 19200, 38400, 57600, 115200, 230400, 460800};

bool BoardAccepts(int baud) {
  return std::find(std::begin(kBoardBauds), std::end(kBoardBauds), baud) != std::end(kBoardBauds);
}

}  // namespace

bool SerialDriveMotorsOptions::IsValid(std::string* error) const {
  if (port.empty()) {
    *error = "port must not be empty";
    return false;
  }
  if (!BoardAccepts(baud)) {
    *error = "baud must be one of 9600, 19200, 38400, 57600, 115200, 230400, 460800";
    return false;
  }
  if (!(wheel_radius_m > 0) || !(track_width_m > 0) || !(ticks_per_turn >= 1)) {
    *error = "wheel_radius_m, track_width_m must be positive and ticks_per_turn at least 1";
    return false;
  }
  if (counter_bits < 8 || counter_bits > 32) {
    *error = "counter_bits must be in [8, 32]";
    return false;
  }
  if (!(max_wheel_speed_mps > 0)) {
    *error = "max_wheel_speed_mps must be positive";
    return false;
  }
  if (link_timeout <= Duration::zero()) {
    *error = "link_timeout must be positive";
    return false;
  }
  return true;
}

SerialDriveMotors::SerialDriveMotors(const Clock& clock, const SerialDriveMotorsOptions& options)
    : clock_(clock),
      options_(options),
      ticks_per_metre_(options.ticks_per_turn / (2.0 * M_PI * options.wheel_radius_m)) {}

std::unique_ptr<SerialDriveMotors> SerialDriveMotors::Open(const Clock& clock,
                                                           const SerialDriveMotorsOptions& options,
                                                           std::string* error) {
  if (!options.IsValid(error)) return nullptr;
  std::unique_ptr<SerialDriveMotors> motors(new SerialDriveMotors(clock, options));
  std::string open_error;
  if (!motors->OpenPort(&open_error)) {
    MOSTAR_LOG(WARNING) << "motor board: " << open_error << "; trying again every "
                        << ToSeconds(kReopenPeriod) << " s";
  }
  motors->reader_ = std::thread([m = motors.get()] { m->ReadLoop(); });
  return motors;
}

bool SerialDriveMotors::OpenPort(std::string* error) {
  // IsValid admitted only board rates, which libserial all has.
  const LibSerial::BaudRate rate =
      serial::ToLibSerialBaudRate(options_.baud).value_or(LibSerial::BaudRate::BAUD_115200);
  std::lock_guard<std::mutex> lock(port_mutex_);
  try {
    port_ = std::make_unique<LibSerial::SerialPort>();
    port_->Open(options_.port);
    port_->SetBaudRate(rate);
    port_->SetCharacterSize(LibSerial::CharacterSize::CHAR_SIZE_8);
    port_->SetParity(LibSerial::Parity::PARITY_NONE);
    port_->SetStopBits(LibSerial::StopBits::STOP_BITS_1);
    port_->SetFlowControl(LibSerial::FlowControl::FLOW_CONTROL_NONE);
  } catch (const std::exception& e) {
    *error = "cannot open motor board port " + options_.port + ": " + e.what();
    ClosePortLocked();
    return false;
  }
  struct stat st {};
  port_device_ = ::fstat(port_->GetFileDescriptor(), &st) == 0 ? st.st_rdev : 0;
  port_open_ = true;
  ++port_opens_;
  return true;
}

bool SerialDriveMotors::PortStillThere() const {
  // A USB adapter that was unplugged, or a udev link now naming another device: the path no
  // longer leads to the device we hold open (reads on a dead tty may just time out).
  struct stat st {};
  return ::stat(options_.port.c_str(), &st) == 0 && st.st_rdev == port_device_;
}

void SerialDriveMotors::ClosePortLocked() {
  port_open_ = false;
  serial::ClosePort(&port_);
}

SerialDriveMotors::~SerialDriveMotors() {
  std::string error;
  if (port_open_ && !Stop(&error)) {
    MOSTAR_LOG(WARNING) << "motor board: stop on shutdown failed: " << error;
  }
  running_ = false;
  if (reader_.joinable()) reader_.join();
  std::lock_guard<std::mutex> lock(port_mutex_);
  ClosePortLocked();
}

bool SerialDriveMotors::Write(const MotorMessage& message, std::string* error) {
  const std::vector<uint8_t> frame = EncodeMessage(message);
  {
    std::lock_guard<std::mutex> lock(port_mutex_);
    if (port_open_) {
      try {
        port_->Write(frame);
        return true;
      } catch (const std::exception& e) {
        *error = std::string("motor board write failed: ") + e.what();
      }
    } else {
      *error = "motor board port " + options_.port + " is not open";
    }
  }
  std::lock_guard<std::mutex> lock(state_mutex_);
  ++write_errors_;
  return false;
}

bool SerialDriveMotors::SetWheelVelocities(const WheelVelocities& wheels, std::string* error) {
  if (!std::isfinite(wheels.left_mps) || !std::isfinite(wheels.right_mps)) {
    *error = "wheel velocity is not finite";
    return false;
  }
  const double max = options_.max_wheel_speed_mps;
  std::lock_guard<std::mutex> lock(write_mutex_);
  SetVelocityMsg m;
  m.sequence = next_sequence_++;
  m.left_ticks_per_s =
      static_cast<int32_t>(std::lround(std::clamp(wheels.left_mps, -max, max) * ticks_per_metre_));
  m.right_ticks_per_s =
      static_cast<int32_t>(std::lround(std::clamp(wheels.right_mps, -max, max) * ticks_per_metre_));
  return Write(m, error);
}

bool SerialDriveMotors::SetVelocity(double linear_mps, double angular_radps, std::string* error) {
  return SetWheelVelocities(WheelsFromBase(linear_mps, angular_radps, options_.track_width_m),
                            error);
}

bool SerialDriveMotors::Stop(std::string* error, bool clear_faults) {
  std::lock_guard<std::mutex> lock(write_mutex_);
  return Write(StopMsg{next_sequence_++, clear_faults}, error);
}

bool SerialDriveMotors::SendHeartbeat(std::string* error) {
  std::lock_guard<std::mutex> lock(write_mutex_);
  return Write(HeartbeatMsg{next_sequence_++}, error);
}

MotorStatus SerialDriveMotors::Status() const {
  const SteadyTime now = clock_.SteadyNow();
  std::lock_guard<std::mutex> lock(state_mutex_);
  MotorStatus s;
  s.link_ok = last_frame_ && now - *last_frame_ <= options_.link_timeout;
  if (have_status_) {
    s.driving = last_status_.state == BoardState::kDriving;
    s.fault = last_status_.state == BoardState::kFault;
    s.fault_flags = last_status_.fault_flags;
    s.battery_v = last_status_.battery_mv * 1e-3;
  }
  s.frames_received = frames_received_;
  s.bad_frames = bad_frames_;
  s.write_errors = write_errors_;
  return s;
}

bool SerialDriveMotors::ReadEncoders(EncoderReading* reading, std::string* error) {
  const SteadyTime now = clock_.SteadyNow();
  std::lock_guard<std::mutex> lock(state_mutex_);
  if (!latest_reading_) {
    *error = "no encoder report from the motor board yet";
    return false;
  }
  if (now - latest_reading_->steady_stamp > options_.link_timeout) {
    *error = "motor board silent for " +
             std::to_string(ToSeconds(now - latest_reading_->steady_stamp)) + " s";
    return false;
  }
  *reading = *latest_reading_;
  return true;
}

MotorDecoderStats SerialDriveMotors::decoder_stats() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return decoder_stats_;
}

void SerialDriveMotors::HandleMessage(const MotorMessage& message) {
  // Called with state_mutex_ held.
  if (const auto* report = std::get_if<EncoderReportMsg>(&message)) {
    EncoderReading r;
    r.stamp = clock_.Now();
    r.steady_stamp = clock_.SteadyNow();
    r.left_count = report->left_count;
    r.right_count = report->right_count;
    latest_reading_ = r;
  } else if (const auto* status = std::get_if<StatusMsg>(&message)) {
    if (status->state == BoardState::kFault &&
        (!have_status_ || last_status_.state != BoardState::kFault)) {
      MOSTAR_LOG(WARNING) << "motor board fault, flags 0x" << std::hex << status->fault_flags;
    }
    last_status_ = *status;
    have_status_ = true;
  }
  // Heartbeats only prove the link (last_frame_), and host-bound command types are ignored.
}

void SerialDriveMotors::ReadLoop() {
  MotorFrameDecoder decoder;
  LibSerial::DataBuffer buffer;
  SteadyTime last_attempt = clock_.SteadyNow();
  while (running_) {
    if (!port_open_) {
      // Missing at start or vanished (USB unplugged): try again every kReopenPeriod.
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      if (clock_.SteadyNow() - last_attempt < kReopenPeriod) continue;
      last_attempt = clock_.SteadyNow();
      std::string error;
      if (OpenPort(&error)) {
        MOSTAR_LOG(INFO) << "motor board: port " << options_.port << " open";
        decoder = MotorFrameDecoder();
      } else {
        MOSTAR_LOG_EVERY_SEC(WARNING, 30) << "motor board: " << error;
      }
      continue;
    }
    if (clock_.SteadyNow() - last_attempt >= kReopenPeriod) {
      last_attempt = clock_.SteadyNow();
      if (!PortStillThere()) {
        MOSTAR_LOG(ERROR) << "motor board: port " << options_.port
                          << " vanished or now names another device; reopening";
        std::lock_guard<std::mutex> lock(port_mutex_);
        ClosePortLocked();
        continue;
      }
    }
    buffer.clear();
    try {
      port_->Read(buffer, 1, 20);  // wait up to 20 ms for the first byte
      while (buffer.size() < 4096 && port_->IsDataAvailable()) {
        unsigned char byte = 0;
        port_->ReadByte(byte, 1);
        buffer.push_back(byte);
      }
    } catch (const LibSerial::ReadTimeout&) {
      // Nothing within 20 ms: check `running_` and wait again.
    } catch (const std::exception& e) {
      MOSTAR_LOG(ERROR) << "motor board read failed: " << e.what() << "; reopening "
                        << options_.port;
      std::lock_guard<std::mutex> lock(port_mutex_);
      ClosePortLocked();
      last_attempt = clock_.SteadyNow();
      continue;
    }
    if (buffer.empty()) continue;
    decoder.Push(buffer);
    std::lock_guard<std::mutex> lock(state_mutex_);
    while (auto frame = decoder.Next()) {
      MotorMessage message;
      std::string error;
      if (!DecodeMessage(*frame, &message, &error)) {
        ++bad_frames_;
        MOSTAR_LOG_EVERY_SEC(WARNING, 5) << "motor board: " << error;
        continue;
      }
      ++frames_received_;
      last_frame_ = clock_.SteadyNow();
      HandleMessage(message);
    }
    const MotorDecoderStats& stats = decoder.stats();
    bad_frames_ += (stats.crc_errors + stats.bad_lengths) -
                   (decoder_stats_.crc_errors + decoder_stats_.bad_lengths);
    decoder_stats_ = stats;
  }
}

}  // namespace mostar::drive
