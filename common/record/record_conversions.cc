#include "common/record/record_conversions.h"

#include <algorithm>
#include <type_traits>

namespace mostar::record {
namespace {

int64_t Ns(Time t) { return ToUnixNanos(t); }
Time At(int64_t ns) { return FromUnixNanos(ns); }

template <typename T>
struct AlwaysFalse : std::false_type {};

void ToProtoImage(const RecordedImage& in, proto::CompressedImage* out) {
  out->set_eye(in.eye == Eye::kLeft ? proto::EYE_LEFT : proto::EYE_RIGHT);
  out->set_stamp_unix_ns(Ns(in.image.stamp));
  out->set_frame_id(in.image.frame_id);
  out->set_format(in.image.format);
  out->set_data(in.image.data.data(), in.image.data.size());
  out->set_pair_sequence(in.pair_sequence);
}

RecordedImage FromProtoImage(const proto::CompressedImage& in) {
  RecordedImage out;
  out.eye = in.eye() == proto::EYE_RIGHT ? Eye::kRight : Eye::kLeft;
  out.pair_sequence = in.pair_sequence();
  out.image.stamp = At(in.stamp_unix_ns());
  out.image.frame_id = in.frame_id();
  out.image.format = in.format();
  out.image.data.assign(in.data().begin(), in.data().end());
  return out;
}

void ToProtoScan(const LaserScan& in, proto::LaserScan* out) {
  out->set_stamp_unix_ns(Ns(in.stamp));
  out->set_sequence(in.sequence);
  out->set_angle_min_rad(in.angle_min_rad);
  out->set_angle_increment_rad(in.angle_increment_rad);
  out->set_time_increment_s(in.time_increment_s);
  out->set_scan_time_s(in.scan_time_s);
  out->set_range_min_m(in.range_min_m);
  out->set_range_max_m(in.range_max_m);
  out->mutable_ranges_m()->Add(in.ranges_m.begin(), in.ranges_m.end());
  out->mutable_intensities()->Add(in.intensities.begin(), in.intensities.end());
}

LaserScan FromProtoScan(const proto::LaserScan& in) {
  LaserScan out;
  out.stamp = At(in.stamp_unix_ns());
  out.sequence = in.sequence();
  out.angle_min_rad = in.angle_min_rad();
  out.angle_increment_rad = in.angle_increment_rad();
  out.time_increment_s = in.time_increment_s();
  out.scan_time_s = in.scan_time_s();
  out.range_min_m = in.range_min_m();
  out.range_max_m = in.range_max_m();
  out.ranges_m.assign(in.ranges_m().begin(), in.ranges_m().end());
  out.intensities.assign(in.intensities().begin(), in.intensities().end());
  return out;
}

void ToProtoOdometry(const Odometry& in, proto::Odometry* out) {
  out->set_stamp_unix_ns(Ns(in.stamp));
  out->set_x_m(in.pose.x_m);
  out->set_y_m(in.pose.y_m);
  out->set_theta_rad(in.pose.theta_rad);
  out->set_linear_mps(in.linear_mps);
  out->set_angular_radps(in.angular_radps);
  out->mutable_pose_variance()->Add(in.pose_variance.begin(), in.pose_variance.end());
}

Odometry FromProtoOdometry(const proto::Odometry& in) {
  Odometry out;
  out.stamp = At(in.stamp_unix_ns());
  out.pose.x_m = in.x_m();
  out.pose.y_m = in.y_m();
  out.pose.theta_rad = in.theta_rad();
  out.linear_mps = in.linear_mps();
  out.angular_radps = in.angular_radps();
  for (int i = 0; i < in.pose_variance_size() && i < 3; ++i) {
    out.pose_variance[static_cast<size_t>(i)] = in.pose_variance(i);
  }
  return out;
}

void ToProtoCommand(const VelocityCommand& in, proto::VelocityCommand* out) {
  out->set_stamp_unix_ns(Ns(in.stamp));
  out->set_sequence(in.sequence);
  out->set_sender_id(in.sender_id);
  out->set_linear_mps(in.linear_mps);
  out->set_angular_radps(in.angular_radps);
  out->set_enable(in.enable);
}

VelocityCommand FromProtoCommand(const proto::VelocityCommand& in) {
  VelocityCommand out;
  out.stamp = At(in.stamp_unix_ns());
  out.sequence = in.sequence();
  out.sender_id = in.sender_id();
  out.linear_mps = in.linear_mps();
  out.angular_radps = in.angular_radps();
  out.enable = in.enable();
  return out;
}

void ToProtoEstop(const EmergencyStop& in, proto::EmergencyStop* out) {
  out->set_stamp_unix_ns(Ns(in.stamp));
  out->set_sender_id(in.sender_id);
  out->set_engage(in.engage);
}

EmergencyStop FromProtoEstop(const proto::EmergencyStop& in) {
  EmergencyStop out;
  out.stamp = At(in.stamp_unix_ns());
  out.sender_id = in.sender_id();
  out.engage = in.has_engage() ? in.engage() : true;
  return out;
}

void ToProtoRequest(const ControlRequest& in, proto::ControlRequest* out) {
  out->set_stamp_unix_ns(Ns(in.stamp));
  out->set_sender_id(in.sender_id);
  out->set_strength(in.strength);
  out->set_take(in.take);
}

ControlRequest FromProtoRequest(const proto::ControlRequest& in) {
  ControlRequest out;
  out.stamp = At(in.stamp_unix_ns());
  out.sender_id = in.sender_id();
  out.strength = in.strength();
  out.take = in.has_take() ? in.take() : true;
  return out;
}

void ToProtoLease(const ControlLease& in, proto::ControlLease* out) {
  out->set_stamp_unix_ns(Ns(in.stamp));
  out->set_holder_id(in.holder_id);
  out->set_holder_strength(in.holder_strength);
  out->set_since_unix_ns(Ns(in.since));
  out->set_lease_sequence(in.lease_sequence);
}

ControlLease FromProtoLease(const proto::ControlLease& in) {
  ControlLease out;
  out.stamp = At(in.stamp_unix_ns());
  out.holder_id = in.holder_id();
  out.holder_strength = in.holder_strength();
  out.since = At(in.since_unix_ns());
  out.lease_sequence = in.lease_sequence();
  return out;
}

void ToProtoHealth(const RobotHealth& in, proto::RobotHealth* out) {
  out->set_stamp_unix_ns(Ns(in.stamp));
  out->set_robot_id(in.robot_id);
  for (const DeviceHealth& device : in.devices) {
    proto::DeviceHealth* d = out->add_devices();
    d->set_name(device.name);
    d->set_state(static_cast<uint32_t>(device.state));
    d->set_message(device.message);
    d->set_rate_hz(device.rate_hz);
    for (const auto& [name, value] : device.counters) {
      proto::Counter* c = d->add_counters();
      c->set_name(name);
      c->set_value(value);
    }
  }
  out->set_lease_holder(in.lease_holder);
  out->set_watchdog_state(static_cast<uint32_t>(in.watchdog_state));
  out->set_last_command_age_s(in.last_command_age_s);
  out->set_last_command_sequence(in.last_command_sequence);
  out->set_estop_engaged(in.estop_engaged);
}

RobotHealth FromProtoHealth(const proto::RobotHealth& in) {
  RobotHealth out;
  out.stamp = At(in.stamp_unix_ns());
  out.robot_id = in.robot_id();
  for (const proto::DeviceHealth& d : in.devices()) {
    DeviceHealth device;
    device.name = d.name();
    device.state = d.state() <= static_cast<uint32_t>(DeviceState::kOff)
                       ? static_cast<DeviceState>(d.state())
                       : DeviceState::kError;
    device.message = d.message();
    device.rate_hz = d.rate_hz();
    for (const proto::Counter& c : d.counters()) device.counters.emplace_back(c.name(), c.value());
    out.devices.push_back(std::move(device));
  }
  out.lease_holder = in.lease_holder();
  out.watchdog_state = in.watchdog_state() <= static_cast<uint32_t>(WatchdogState::kEstop)
                           ? static_cast<WatchdogState>(in.watchdog_state())
                           : WatchdogState::kIdle;
  out.last_command_age_s = in.has_last_command_age_s() ? in.last_command_age_s() : -1.f;
  out.last_command_sequence = in.last_command_sequence();
  out.estop_engaged = in.estop_engaged();
  return out;
}

void ToProtoSonar(const SonarRanges& in, proto::SonarRanges* out) {
  out->set_cycle(in.cycle);
  for (const SonarRange& r : in.ranges) {
    proto::SonarRange* o = out->add_ranges();
    o->set_frame_id(r.mount.frame_id);
    o->set_x_m(r.mount.x_m);
    o->set_y_m(r.mount.y_m);
    o->set_yaw_rad(r.mount.yaw_rad);
    o->set_stamp_unix_ns(Ns(r.stamp));
    o->set_range_m(r.range_m);
    o->set_min_range_m(r.min_range_m);
    o->set_max_range_m(r.max_range_m);
    o->set_field_of_view_rad(r.field_of_view_rad);
  }
}

SonarRanges FromProtoSonar(const proto::SonarRanges& in) {
  SonarRanges out;
  out.cycle = in.cycle();
  for (const proto::SonarRange& r : in.ranges()) {
    SonarRange o;
    o.mount.frame_id = r.frame_id();
    o.mount.x_m = r.x_m();
    o.mount.y_m = r.y_m();
    o.mount.yaw_rad = r.yaw_rad();
    o.stamp = At(r.stamp_unix_ns());
    o.range_m = r.range_m();
    o.min_range_m = r.min_range_m();
    o.max_range_m = r.max_range_m();
    o.field_of_view_rad = r.field_of_view_rad();
    out.ranges.push_back(std::move(o));
  }
  return out;
}

void ToProtoBumpers(const BumperState& in, proto::BumperState* out) {
  out->set_stamp_unix_ns(Ns(in.stamp));
  out->set_segment_count(in.segment_count);
  out->set_pressed(in.pressed);
  out->set_latched(in.latched);
  out->set_readable(in.readable);
}

BumperState FromProtoBumpers(const proto::BumperState& in) {
  BumperState out;
  out.stamp = At(in.stamp_unix_ns());
  out.segment_count = std::clamp(in.segment_count(), 0, 32);  // as on the wire
  out.pressed = in.pressed();
  out.latched = in.latched();
  out.readable = in.readable();
  return out;
}

}  // namespace

void ToProto(const RecordingInfo& info, proto::Header* header) {
  header->set_format_version(kFormatVersion);
  header->set_creation_time_unix_ns(Ns(info.creation_time));
  header->set_robot_id(info.robot_id);
  const SensorDescription& s = info.sensors;
  proto::LaserDescription* laser = header->mutable_sensors()->mutable_laser();
  laser->set_angle_min_rad(s.laser_angle_min_rad);
  laser->set_angle_increment_rad(s.laser_angle_increment_rad);
  laser->set_beam_count(s.laser_beam_count);
  laser->set_range_max_m(s.laser_range_max_m);
  laser->set_scan_rate_hz(s.laser_scan_rate_hz);
  proto::CameraDescription* camera = header->mutable_sensors()->mutable_camera();
  camera->set_width_px(s.camera_width_px);
  camera->set_height_px(s.camera_height_px);
  camera->set_frame_rate_hz(s.camera_frame_rate_hz);
  camera->set_format(s.camera_format);
  header->set_calibration_text(info.calibration_text);
  for (const auto& [key, value] : info.metadata) {
    proto::MetadataEntry* entry = header->add_metadata();
    entry->set_key(key);
    entry->set_value(value);
  }
}

void FromProto(const proto::Header& header, RecordingInfo* info) {
  info->creation_time = At(header.creation_time_unix_ns());
  info->robot_id = header.robot_id();
  const proto::LaserDescription& laser = header.sensors().laser();
  const proto::CameraDescription& camera = header.sensors().camera();
  SensorDescription& s = info->sensors;
  s.laser_angle_min_rad = laser.angle_min_rad();
  s.laser_angle_increment_rad = laser.angle_increment_rad();
  s.laser_beam_count = laser.beam_count();
  s.laser_range_max_m = laser.range_max_m();
  s.laser_scan_rate_hz = laser.scan_rate_hz();
  s.camera_width_px = camera.width_px();
  s.camera_height_px = camera.height_px();
  s.camera_frame_rate_hz = camera.frame_rate_hz();
  s.camera_format = camera.format();
  info->calibration_text = header.calibration_text();
  info->metadata.clear();
  for (const proto::MetadataEntry& entry : header.metadata()) {
    info->metadata.emplace_back(entry.key(), entry.value());
  }
}

void ToProto(const RecordedMessage& message, proto::Record* record) {
  record->set_log_time_unix_ns(Ns(message.log_time));
  std::visit(
      [record](const auto& payload) {
        using T = std::decay_t<decltype(payload)>;
        if constexpr (std::is_same_v<T, RecordedImage>) {
          ToProtoImage(payload, record->mutable_image());
        } else if constexpr (std::is_same_v<T, LaserScan>) {
          ToProtoScan(payload, record->mutable_scan());
        } else if constexpr (std::is_same_v<T, Odometry>) {
          ToProtoOdometry(payload, record->mutable_odometry());
        } else if constexpr (std::is_same_v<T, VelocityCommand>) {
          ToProtoCommand(payload, record->mutable_velocity_command());
        } else if constexpr (std::is_same_v<T, EmergencyStop>) {
          ToProtoEstop(payload, record->mutable_emergency_stop());
        } else if constexpr (std::is_same_v<T, ControlRequest>) {
          ToProtoRequest(payload, record->mutable_control_request());
        } else if constexpr (std::is_same_v<T, ControlLease>) {
          ToProtoLease(payload, record->mutable_control_lease());
        } else if constexpr (std::is_same_v<T, RobotHealth>) {
          ToProtoHealth(payload, record->mutable_health());
        } else if constexpr (std::is_same_v<T, SonarRanges>) {
          ToProtoSonar(payload, record->mutable_sonar());
        } else if constexpr (std::is_same_v<T, BumperState>) {
          ToProtoBumpers(payload, record->mutable_bumpers());
        } else {
          static_assert(AlwaysFalse<T>::value, "unhandled record payload");
        }
      },
      message.payload);
}

FromProtoResult FromProto(const proto::Record& record, RecordedMessage* message) {
  RecordPayload payload;
  switch (record.payload_case()) {
    case proto::Record::kImage:
      payload = FromProtoImage(record.image());
      break;
    case proto::Record::kScan:
      payload = FromProtoScan(record.scan());
      break;
    case proto::Record::kOdometry:
      payload = FromProtoOdometry(record.odometry());
      break;
    case proto::Record::kVelocityCommand:
      payload = FromProtoCommand(record.velocity_command());
      break;
    case proto::Record::kEmergencyStop:
      payload = FromProtoEstop(record.emergency_stop());
      break;
    case proto::Record::kControlRequest:
      payload = FromProtoRequest(record.control_request());
      break;
    case proto::Record::kControlLease:
      payload = FromProtoLease(record.control_lease());
      break;
    case proto::Record::kHealth:
      payload = FromProtoHealth(record.health());
      break;
    case proto::Record::kSonar:
      payload = FromProtoSonar(record.sonar());
      break;
    case proto::Record::kBumpers:
      payload = FromProtoBumpers(record.bumpers());
      break;
    case proto::Record::kIndex:
      return FromProtoResult::kIndex;
    case proto::Record::PAYLOAD_NOT_SET:
      return FromProtoResult::kUnknown;
  }
  message->log_time = At(record.log_time_unix_ns());
  message->payload = std::move(payload);
  return FromProtoResult::kOk;
}

}  // namespace mostar::record
