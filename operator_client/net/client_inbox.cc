#include "operator_client/net/client_inbox.h"

namespace mostar::client {

OperatorNode::Callbacks InboxCallbacks(const ClientInbox& in) {
  OperatorNode::Callbacks callbacks;
  callbacks.on_image = [in](Eye eye, const CompressedImage& image) {
    if (in.trace) {
      in.trace->Add(eye == Eye::kLeft ? "left" : "right", image.stamp, 0);
      // Arrival time with the capture stamp in the sequence field: the image's age on arrival.
      if (eye == Eye::kLeft) {
        in.trace->Add("left_rx", in.clock->Now(), static_cast<uint64_t>(ToUnixNanos(image.stamp)));
      }
    }
    if (in.recorder) in.recorder->Write(image, eye);
    in.video->Push(eye, image);
  };
  callbacks.on_video = [in](const StereoVideoFrame& frame) {
    if (in.trace) {
      in.trace->Add("left", frame.stamp, 0);
      in.trace->Add("right", frame.stamp, 0);
      in.trace->Add("left_rx", in.clock->Now(), static_cast<uint64_t>(ToUnixNanos(frame.stamp)));
    }
    in.video->PushVideo(frame);  // not recorded: recordings hold JPEG images
  };
  callbacks.on_scan = [in](const LaserScan& scan) {
    if (in.trace) in.trace->Add("scan", scan.stamp, 0);
    if (in.recorder) in.recorder->Write(scan);
    in.robot->AddScan(scan);
  };
  callbacks.on_health = [in](const RobotHealth& health) {
    if (in.trace) in.trace->Add("health", health.stamp, health.last_command_sequence);
    if (in.recorder) in.recorder->Write(health);
    in.robot->SetHealth(health);
  };
  callbacks.on_lease = [in](const ControlLease& lease) {
    if (in.recorder) in.recorder->Write(lease);
    in.robot->SetLease(lease);
  };
  callbacks.on_odometry = [in](const Odometry& odometry) {
    if (in.recorder) in.recorder->Write(odometry);
    in.robot->SetOdometry(odometry);
  };
  callbacks.on_sonar = [in](const SonarRanges& sonar) {
    if (in.recorder) in.recorder->Write(sonar);
    in.robot->SetSonar(sonar);
  };
  callbacks.on_bumpers = [in](const BumperState& bumpers) {
    if (in.recorder) in.recorder->Write(bumpers);
    in.robot->SetBumpers(bumpers);
  };
  callbacks.on_frame_timing = [in](const FrameTiming& timing) { in.robot->AddFrameTiming(timing); };
  callbacks.on_camera_info = [in](Eye eye, const CameraIntrinsicsInfo& info) {
    in.robot->SetIntrinsics(eye, info);
    in.video->SetExpectedSize(eye, info.width_px, info.height_px);
  };
  callbacks.on_pong = [in](const ClockProbe& probe) {
    if (probe.sender_id != in.client_id) return;
    in.robot->AddClockSample(probe);
    in.video->SetClockOffset(in.robot->Snapshot().clock);
  };
  return callbacks;
}

}  // namespace mostar::client
