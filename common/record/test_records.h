// Sample records and helpers for the recording tests (test-only, header-only).
#pragma once

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "common/record/record_conversions.h"
#include "common/record/recording_format.h"

namespace mostar::record::testing {

inline Time T0() { return FromUnixNanos(1'700'000'000'000'000'000); }

inline RecordedImage MakeImage(Eye eye, Time stamp, uint64_t sequence, size_t size_bytes = 64) {
  RecordedImage image;
  image.eye = eye;
  image.pair_sequence = sequence;
  image.image.stamp = stamp;
  image.image.frame_id = eye == Eye::kLeft ? "camera_left" : "camera_right";
  image.image.format = "jpeg";
  image.image.data.resize(size_bytes);
  for (size_t i = 0; i < size_bytes; ++i) {
    image.image.data[i] =
        static_cast<uint8_t>((i * 31 + sequence * 7 + (eye == Eye::kLeft ? 0 : 1)) & 0xFF);
  }
  return image;
}

inline LaserScan MakeScan(Time stamp, uint64_t sequence) {
  LaserScan scan;
  scan.stamp = stamp;
  scan.sequence = sequence;
  scan.angle_min_rad = -1.5707964f;
  scan.angle_increment_rad = 0.017453292f;
  scan.time_increment_s = 1.0f / 75.0f / 360.0f;
  scan.scan_time_s = 1.0f / 37.5f;
  scan.range_min_m = 0.1f;
  scan.range_max_m = 8.0f;
  for (int i = 0; i < 181; ++i) scan.ranges_m.push_back(1.0f + 0.01f * static_cast<float>(i));
  scan.ranges_m[3] = std::numeric_limits<float>::quiet_NaN();
  scan.ranges_m[4] = std::numeric_limits<float>::infinity();
  scan.intensities.assign(181, 2.0f);
  return scan;
}

inline Odometry MakeOdometry(Time stamp) {
  Odometry odometry;
  odometry.stamp = stamp;
  odometry.pose = Pose2D{1.25, -0.5, 0.3};
  odometry.linear_mps = 0.4;
  odometry.angular_radps = -0.1;
  odometry.pose_variance = {0.01, 0.02, 0.003};
  return odometry;
}

inline VelocityCommand MakeCommand(Time stamp, uint64_t sequence) {
  VelocityCommand command;
  command.stamp = stamp;
  command.sequence = sequence;
  command.sender_id = "operator-1";
  command.linear_mps = 0.3;
  command.angular_radps = 0.2;
  command.enable = true;
  return command;
}

inline ControlLease MakeLease(Time stamp) {
  ControlLease lease;
  lease.stamp = stamp;
  lease.holder_id = "operator-1";
  lease.holder_strength = 5;
  lease.since = stamp - std::chrono::seconds(3);
  lease.lease_sequence = 12;
  return lease;
}

inline RobotHealth MakeHealth(Time stamp) {
  RobotHealth health;
  health.stamp = stamp;
  health.robot_id = "morduc";
  DeviceHealth laser;
  laser.name = "laser";
  laser.state = DeviceState::kWarn;
  laser.message = "2 CRC errors";
  laser.rate_hz = 37.5f;
  laser.counters = {{"crc_errors", 2}, {"scans", 1000}};
  health.devices.push_back(laser);
  health.lease_holder = "operator-1";
  health.watchdog_state = WatchdogState::kDriving;
  health.last_command_age_s = 0.05f;
  health.last_command_sequence = 77;
  health.estop_engaged = false;
  return health;
}

inline EmergencyStop MakeStop(Time stamp) {
  EmergencyStop stop;
  stop.stamp = stamp;
  stop.sender_id = "operator-2";
  stop.engage = true;
  return stop;
}

inline ControlRequest MakeRequest(Time stamp) {
  ControlRequest request;
  request.stamp = stamp;
  request.sender_id = "operator-2";
  request.strength = 3;
  request.take = false;
  return request;
}

inline SonarRanges MakeSonar(Time stamp) {
  SonarRanges sonar;
  sonar.cycle = 41;
  const float ranges[3] = {1.25f, std::numeric_limits<float>::infinity(),
                           std::numeric_limits<float>::quiet_NaN()};
  for (int i = 0; i < 3; ++i) {
    SonarRange r;
    r.mount = SonarMount{"sonar_" + std::to_string(i), 0.3 - 0.1 * i, 0.05 * i, 0.785 * i};
    r.stamp = stamp + std::chrono::milliseconds(65 * i);
    r.range_m = ranges[i];
    r.min_range_m = 0.03f;
    r.max_range_m = 6.0f;
    r.field_of_view_rad = 0.96f;
    sonar.ranges.push_back(r);
  }
  return sonar;
}

inline BumperState MakeBumpers(Time stamp) {
  BumperState bumpers;
  bumpers.stamp = stamp;
  bumpers.segment_count = 16;
  bumpers.pressed = 0x8001;
  bumpers.latched = 0x0001;
  bumpers.readable = true;
  return bumpers;
}

inline RecordedMessage At(Time log_time, RecordPayload payload) {
  RecordedMessage message;
  message.log_time = log_time;
  message.payload = std::move(payload);
  return message;
}

// One record of every kind, log times `step` apart from `start`.
inline std::vector<RecordedMessage> OneOfEach(Time start, Duration step) {
  std::vector<RecordedMessage> out;
  Time t = start;
  auto next = [&]() {
    const Time now = t;
    t += step;
    return now;
  };
  Time s = next();
  out.push_back(At(s, MakeImage(Eye::kLeft, s, 1)));
  out.push_back(At(next(), MakeImage(Eye::kRight, s, 1)));
  out.push_back(At(next(), MakeScan(s, 9)));
  out.push_back(At(next(), MakeOdometry(s)));
  out.push_back(At(next(), MakeCommand(s, 3)));
  out.push_back(At(next(), MakeStop(s)));
  out.push_back(At(next(), MakeRequest(s)));
  out.push_back(At(next(), MakeLease(s)));
  out.push_back(At(next(), MakeHealth(s)));
  out.push_back(At(next(), MakeSonar(s)));
  out.push_back(At(next(), MakeBumpers(s)));
  return out;
}

// Equality through the serialized form (bit-exact, NaN included).
inline std::string Serialized(const RecordedMessage& message) {
  proto::Record record;
  ToProto(message, &record);
  return record.SerializeAsString();
}

inline RecordingInfo MakeInfo() {
  RecordingInfo info;
  info.creation_time = T0();
  info.robot_id = "morduc";
  info.sensors.laser_angle_min_rad = -1.5707964f;
  info.sensors.laser_angle_increment_rad = 0.017453292f;
  info.sensors.laser_beam_count = 181;
  info.sensors.laser_range_max_m = 8.0f;
  info.sensors.laser_scan_rate_hz = 37.5f;
  info.sensors.camera_width_px = 640;
  info.sensors.camera_height_px = 480;
  info.sensors.camera_frame_rate_hz = 15.0f;
  info.sensors.camera_format = "jpeg";
  info.calibration_text = "name: \"morduc\"\nfocal_px: 525\n";
  info.metadata = {{"operator", "alice"}, {"site", "lab"}};
  return info;
}

// Records in memory, in the order given.
class VectorRecordStream final : public RecordStream {
 public:
  explicit VectorRecordStream(std::vector<RecordedMessage> messages)
      : messages_(std::move(messages)) {}
  bool Next(RecordedMessage* message) override {
    if (next_ >= messages_.size()) return false;
    *message = messages_[next_++];
    return true;
  }
  bool SeekToTime(Time t) override {
    next_ = 0;
    while (next_ < messages_.size() && messages_[next_].log_time < t) ++next_;
    return next_ < messages_.size();
  }

 private:
  std::vector<RecordedMessage> messages_;
  size_t next_ = 0;
};

// A fresh path in the test's temporary directory.
inline std::string TempPath(const std::string& name) {
  const char* dir = std::getenv("TEST_TMPDIR");
  std::string base = dir != nullptr ? dir : "/tmp";
  return base + "/mostar_record_" + std::to_string(::getpid()) + "_" + name;
}

inline std::string ReadFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  const std::streamoff size = in.tellg();
  if (size <= 0) return "";
  std::string bytes(static_cast<size_t>(size), '\0');
  in.seekg(0);
  in.read(bytes.data(), size);
  return bytes;
}

inline void WriteFileBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace mostar::record::testing
