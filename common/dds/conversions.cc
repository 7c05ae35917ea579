#include "common/dds/conversions.h"

#include <algorithm>
#include <cmath>

namespace mostar::dds {

wire::Time ToIdl(Time t) {
  const SecNanosec s = ToSecNanosec(t);
  wire::Time out;
  out.sec(s.sec);
  out.nanosec(s.nanosec);
  return out;
}

Time FromIdl(const wire::Time& t) { return FromSecNanosec(t.sec(), t.nanosec()); }

wire::LaserScan ToIdl(const LaserScan& scan) {
  wire::LaserScan out;
  out.header().stamp(ToIdl(scan.stamp));
  out.header().frame_id(kLaserFrame);
  out.angle_min(scan.angle_min_rad);
  out.angle_max(scan.angle_max_rad());
  out.angle_increment(scan.angle_increment_rad);
  out.time_increment(scan.time_increment_s);
  out.scan_time(scan.scan_time_s);
  out.range_min(scan.range_min_m);
  out.range_max(scan.range_max_m);
  out.ranges(scan.ranges_m);
  out.intensities(scan.intensities);
  return out;
}

LaserScan FromIdl(const wire::LaserScan& scan) {
  LaserScan out;
  out.stamp = FromIdl(scan.header().stamp());
  out.angle_min_rad = scan.angle_min();
  out.angle_increment_rad = scan.angle_increment();
  out.time_increment_s = scan.time_increment();
  out.scan_time_s = scan.scan_time();
  out.range_min_m = scan.range_min();
  out.range_max_m = scan.range_max();
  out.ranges_m = scan.ranges();
  out.intensities = scan.intensities();
  return out;
}

wire::CompressedImage ToIdl(const CompressedImage& image) {
  wire::CompressedImage out;
  out.header().stamp(ToIdl(image.stamp));
  out.header().frame_id(image.frame_id);
  out.format(image.format);
  out.data(image.data);
  return out;
}

CompressedImage FromIdl(const wire::CompressedImage& image) {
  CompressedImage out;
  out.stamp = FromIdl(image.header().stamp());
  out.frame_id = image.header().frame_id();
  out.format = image.format();
  out.data = image.data();
  return out;
}

wire::CameraInfo ToIdl(const CameraIntrinsicsInfo& info) {
  wire::CameraInfo out;
  out.header().stamp(ToIdl(info.stamp));
  out.header().frame_id(info.frame_id);
  out.width(static_cast<uint32_t>(info.width_px));
  out.height(static_cast<uint32_t>(info.height_px));
  out.distortion_model("plumb_bob");
  out.d(info.distortion);
  out.k() = {info.fx, 0, info.cx, 0, info.fy, info.cy, 0, 0, 1};
  out.r() = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  out.p() = {info.fx, 0, info.cx, 0, 0, info.fy, info.cy, 0, 0, 0, 1, 0};
  return out;
}

CameraIntrinsicsInfo FromIdl(const wire::CameraInfo& info) {
  CameraIntrinsicsInfo out;
  out.stamp = FromIdl(info.header().stamp());
  out.frame_id = info.header().frame_id();
  out.width_px = static_cast<int>(info.width());
  out.height_px = static_cast<int>(info.height());
  out.fx = info.k()[0];
  out.cx = info.k()[2];
  out.fy = info.k()[4];
  out.cy = info.k()[5];
  out.distortion = info.d();
  return out;
}

namespace {
constexpr double kUnknownVariance = 1e6;
}

wire::Odometry ToIdl(const Odometry& odom) {
  wire::Odometry out;
  out.header().stamp(ToIdl(odom.stamp));
  out.header().frame_id(kOdomFrame);
  out.child_frame_id(kBaseFrame);
  auto& pose = out.pose().pose();
  pose.position().x(odom.pose.x_m);
  pose.position().y(odom.pose.y_m);
  pose.position().z(0);
  pose.orientation().x(0);
  pose.orientation().y(0);
  pose.orientation().z(std::sin(odom.pose.theta_rad / 2));
  pose.orientation().w(std::cos(odom.pose.theta_rad / 2));
  auto& cov = out.pose().covariance();
  cov.fill(0);
  cov[0] = odom.pose_variance[0];
  cov[7] = odom.pose_variance[1];
  cov[14] = kUnknownVariance;
  cov[21] = kUnknownVariance;
  cov[28] = kUnknownVariance;
  cov[35] = odom.pose_variance[2];
  out.twist().twist().linear().x(odom.linear_mps);
  out.twist().twist().angular().z(odom.angular_radps);
  return out;
}

Odometry FromIdl(const wire::Odometry& odom) {
  Odometry out;
  out.stamp = FromIdl(odom.header().stamp());
  const auto& pose = odom.pose().pose();
  out.pose.x_m = pose.position().x();
  out.pose.y_m = pose.position().y();
  out.pose.theta_rad = 2 * std::atan2(pose.orientation().z(), pose.orientation().w());
  if (out.pose.theta_rad > M_PI) out.pose.theta_rad -= 2 * M_PI;
  if (out.pose.theta_rad <= -M_PI) out.pose.theta_rad += 2 * M_PI;
  const auto& cov = odom.pose().covariance();
  out.pose_variance = {cov[0], cov[7], cov[35]};
  out.linear_mps = odom.twist().twist().linear().x();
  out.angular_radps = odom.twist().twist().angular().z();
  return out;
}

wire::VelocityCommand ToIdl(const VelocityCommand& cmd) {
  wire::VelocityCommand out;
  out.stamp(ToIdl(cmd.stamp));
  out.sequence_number(cmd.sequence);
  out.sender_id(cmd.sender_id);
  out.linear_mps(cmd.linear_mps);
  out.angular_radps(cmd.angular_radps);
  out.enable(cmd.enable);
  return out;
}

VelocityCommand FromIdl(const wire::VelocityCommand& cmd) {
  VelocityCommand out;
  out.stamp = FromIdl(cmd.stamp());
  out.sequence = cmd.sequence_number();
  out.sender_id = cmd.sender_id().to_string();
  out.linear_mps = cmd.linear_mps();
  out.angular_radps = cmd.angular_radps();
  out.enable = cmd.enable();
  return out;
}

wire::EmergencyStop ToIdl(const EmergencyStop& stop) {
  wire::EmergencyStop out;
  out.stamp(ToIdl(stop.stamp));
  out.sender_id(stop.sender_id);
  out.engage(stop.engage);
  return out;
}

EmergencyStop FromIdl(const wire::EmergencyStop& stop) {
  EmergencyStop out;
  out.stamp = FromIdl(stop.stamp());
  out.sender_id = stop.sender_id().to_string();
  out.engage = stop.engage();
  return out;
}

wire::ControlRequest ToIdl(const ControlRequest& request) {
  wire::ControlRequest out;
  out.stamp(ToIdl(request.stamp));
  out.sender_id(request.sender_id);
  out.strength(request.strength);
  out.take(request.take);
  return out;
}

ControlRequest FromIdl(const wire::ControlRequest& request) {
  ControlRequest out;
  out.stamp = FromIdl(request.stamp());
  out.sender_id = request.sender_id().to_string();
  out.strength = request.strength();
  out.take = request.take();
  return out;
}

wire::ControlLease ToIdl(const ControlLease& lease) {
  wire::ControlLease out;
  out.stamp(ToIdl(lease.stamp));
  out.holder_id(lease.holder_id);
  out.holder_strength(lease.holder_strength);
  out.since(ToIdl(lease.since));
  out.lease_sequence(lease.lease_sequence);
  return out;
}

ControlLease FromIdl(const wire::ControlLease& lease) {
  ControlLease out;
  out.stamp = FromIdl(lease.stamp());
  out.holder_id = lease.holder_id().to_string();
  out.holder_strength = lease.holder_strength();
  out.since = FromIdl(lease.since());
  out.lease_sequence = lease.lease_sequence();
  return out;
}

wire::RobotHealth ToIdl(const RobotHealth& health) {
  wire::RobotHealth out;
  out.stamp(ToIdl(health.stamp));
  out.robot_id(health.robot_id);
  for (const DeviceHealth& d : health.devices) {
    if (out.devices().size() >= kMaxHealthDevices) break;
    mostar_msgs::msg::dds_::DeviceHealth_ w;
    w.name(d.name);
    w.state(static_cast<uint8_t>(d.state));
    w.message(d.message);
    w.rate_hz(d.rate_hz);
    for (const auto& [name, value] : d.counters) {
      if (w.counters().size() >= kMaxHealthCounters) break;
      mostar_msgs::msg::dds_::Counter_ c;
      c.name(name);
      c.value(value);
      w.counters().push_back(c);
    }
    out.devices().push_back(w);
  }
  out.lease_holder(health.lease_holder);
  out.watchdog_state(static_cast<uint8_t>(health.watchdog_state));
  out.last_command_age_s(health.last_command_age_s);
  out.last_command_sequence(health.last_command_sequence);
  out.estop_engaged(health.estop_engaged);
  return out;
}

RobotHealth FromIdl(const wire::RobotHealth& health) {
  RobotHealth out;
  out.stamp = FromIdl(health.stamp());
  out.robot_id = health.robot_id().to_string();
  for (const auto& w : health.devices()) {
    DeviceHealth d;
    d.name = w.name().to_string();
    d.state = w.state() <= 3 ? static_cast<DeviceState>(w.state()) : DeviceState::kError;
    d.message = w.message().to_string();
    d.rate_hz = w.rate_hz();
    for (const auto& c : w.counters()) d.counters.emplace_back(c.name().to_string(), c.value());
    out.devices.push_back(std::move(d));
  }
  out.lease_holder = health.lease_holder().to_string();
  out.watchdog_state = health.watchdog_state() <= 4
                           ? static_cast<WatchdogState>(health.watchdog_state())
                           : WatchdogState::kEstop;
  out.last_command_age_s = health.last_command_age_s();
  out.last_command_sequence = health.last_command_sequence();
  out.estop_engaged = health.estop_engaged();
  return out;
}

wire::ClockProbe ToIdl(const ClockProbe& probe) {
  wire::ClockProbe out;
  out.sender_id(probe.sender_id);
  out.sequence_number(probe.sequence);
  out.t0(ToIdl(probe.t0));
  out.t1(ToIdl(probe.t1));
  out.t2(ToIdl(probe.t2));
  out.t3(ToIdl(probe.t3));
  return out;
}

ClockProbe FromIdl(const wire::ClockProbe& probe) {
  ClockProbe out;
  out.sender_id = probe.sender_id().to_string();
  out.sequence = probe.sequence_number();
  out.t0 = FromIdl(probe.t0());
  out.t1 = FromIdl(probe.t1());
  out.t2 = FromIdl(probe.t2());
  out.t3 = FromIdl(probe.t3());
  return out;
}

wire::FrameTiming ToIdl(const FrameTiming& timing) {
  wire::FrameTiming out;
  out.capture(ToIdl(timing.capture));
  out.encoded(ToIdl(timing.encoded));
  out.written(ToIdl(timing.written));
  return out;
}

FrameTiming FromIdl(const wire::FrameTiming& timing) {
  return {FromIdl(timing.capture()), FromIdl(timing.encoded()), FromIdl(timing.written())};
}

wire::StereoVideoFrame ToIdl(const StereoVideoFrame& frame) {
  wire::StereoVideoFrame out;
  out.stamp(ToIdl(frame.stamp));
  out.encoded(ToIdl(frame.encoded));
  out.sequence_number(frame.sequence);
  out.idr(frame.idr);
  out.width_px(static_cast<uint16_t>(std::clamp(frame.width_px, 0, 65535)));
  out.height_px(static_cast<uint16_t>(std::clamp(frame.height_px, 0, 65535)));
  out.format(frame.format);
  out.left(frame.left);
  out.right(frame.right);
  return out;
}

StereoVideoFrame FromIdl(const wire::StereoVideoFrame& frame) {
  StereoVideoFrame out;
  out.stamp = FromIdl(frame.stamp());
  out.encoded = FromIdl(frame.encoded());
  out.sequence = frame.sequence_number();
  out.idr = frame.idr();
  out.width_px = frame.width_px();
  out.height_px = frame.height_px();
  out.format = frame.format().to_string();
  out.left = frame.left();
  out.right = frame.right();
  return out;
}

wire::KeyframeRequest ToIdl(const KeyframeRequest& request) {
  wire::KeyframeRequest out;
  out.stamp(ToIdl(request.stamp));
  out.sender_id(request.sender_id);
  out.last_sequence(request.last_sequence);
  out.reason(request.reason);
  return out;
}

KeyframeRequest FromIdl(const wire::KeyframeRequest& request) {
  return {FromIdl(request.stamp()), request.sender_id().to_string(), request.last_sequence(),
          request.reason().to_string()};
}

wire::VideoFeedback ToIdl(const VideoFeedback& feedback) {
  wire::VideoFeedback out;
  out.stamp(ToIdl(feedback.stamp));
  out.sender_id(feedback.sender_id);
  const size_t n = std::min(feedback.arrivals.size(), VideoFeedback::kMaxArrivals);
  for (size_t i = 0; i < n; ++i) {
    mostar_msgs::msg::dds_::FrameArrival_ arrival;
    arrival.sequence_number(feedback.arrivals[i].sequence);
    arrival.arrival_ns(feedback.arrivals[i].arrival_ns);
    arrival.bytes(feedback.arrivals[i].bytes);
    out.arrivals().push_back(arrival);
  }
  return out;
}

VideoFeedback FromIdl(const wire::VideoFeedback& feedback) {
  VideoFeedback out;
  out.stamp = FromIdl(feedback.stamp());
  out.sender_id = feedback.sender_id().to_string();
  for (const auto& arrival : feedback.arrivals()) {
    out.arrivals.push_back({arrival.sequence_number(), arrival.arrival_ns(), arrival.bytes()});
  }
  return out;
}

wire::CompressedVideo ToFoxgloveVideo(const StereoVideoFrame& frame, Eye eye) {
  wire::CompressedVideo out;
  out.timestamp(ToIdl(frame.stamp));
  out.frame_id(eye == Eye::kLeft ? "camera_left" : "camera_right");
  out.data(eye == Eye::kLeft ? frame.left : frame.right);
  out.format("h264");
  return out;
}

namespace {

mostar_msgs::msg::dds_::SonarReading_ ToReading(const SonarRange& r) {
  mostar_msgs::msg::dds_::SonarReading_ out;
  out.frame_id(r.mount.frame_id);
  out.x_m(static_cast<float>(r.mount.x_m));
  out.y_m(static_cast<float>(r.mount.y_m));
  out.yaw_rad(static_cast<float>(r.mount.yaw_rad));
  out.stamp(ToIdl(r.stamp));
  out.range_m(r.range_m);
  out.min_range_m(r.min_range_m);
  out.max_range_m(r.max_range_m);
  out.field_of_view_rad(r.field_of_view_rad);
  return out;
}

}  // namespace

wire::SonarRing ToIdl(const SonarRanges& ranges) {
  wire::SonarRing out;
  out.cycle(ranges.cycle);
  Time newest{};
  for (const SonarRange& r : ranges.ranges) {
    if (out.sensors().size() >= kMaxSonars) break;
    out.sensors().push_back(ToReading(r));
    newest = std::max(newest, r.stamp);
  }
  out.stamp(ToIdl(newest));
  return out;
}

SonarRanges FromIdl(const wire::SonarRing& ring) {
  SonarRanges out;
  out.cycle = ring.cycle();
  for (const auto& w : ring.sensors()) {
    SonarRange r;
    r.mount.frame_id = w.frame_id().to_string();
    r.mount.x_m = w.x_m();
    r.mount.y_m = w.y_m();
    r.mount.yaw_rad = w.yaw_rad();
    r.stamp = FromIdl(w.stamp());
    r.range_m = w.range_m();
    r.min_range_m = w.min_range_m();
    r.max_range_m = w.max_range_m();
    r.field_of_view_rad = w.field_of_view_rad();
    out.ranges.push_back(std::move(r));
  }
  return out;
}

wire::Range ToIdl(const SonarRange& range) {
  wire::Range out;
  out.header().stamp(ToIdl(range.stamp));
  out.header().frame_id(range.mount.frame_id);
  out.radiation_type(0);  // ULTRASOUND
  out.field_of_view(range.field_of_view_rad);
  out.min_range(range.min_range_m);
  out.max_range(range.max_range_m);
  out.range(range.range_m);
  out.variance(0);
  return out;
}

SonarRange FromIdl(const wire::Range& range) {
  SonarRange out;
  out.mount.frame_id = range.header().frame_id();
  out.stamp = FromIdl(range.header().stamp());
  out.field_of_view_rad = range.field_of_view();
  out.min_range_m = range.min_range();
  out.max_range_m = range.max_range();
  out.range_m = range.range();
  return out;
}

wire::BumperState ToIdl(const BumperState& state) {
  wire::BumperState out;
  out.stamp(ToIdl(state.stamp));
  out.segment_count(static_cast<uint8_t>(std::clamp(state.segment_count, 0, kMaxBumperSegments)));
  out.pressed(state.pressed);
  out.latched(state.latched);
  out.readable(state.readable);
  return out;
}

BumperState FromIdl(const wire::BumperState& state) {
  BumperState out;
  out.stamp = FromIdl(state.stamp());
  out.segment_count = std::min<int>(state.segment_count(), kMaxBumperSegments);
  out.pressed = state.pressed();
  out.latched = state.latched();
  out.readable = state.readable();
  return out;
}

}  // namespace mostar::dds
