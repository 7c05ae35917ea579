#include "operator_client/net/operator_node.h"

#include "common/dds/conversions.h"
#include "common/dds/topics.h"
#include "common/identity/client_id.h"
#include "common/identity/sender_partition.h"
#include "common/log/log.h"

namespace mostar::client {

namespace topics = dds::topics;
using dds::Stream;

namespace {
template <class T>
bool Check(const std::unique_ptr<T>& endpoint, std::string* error) {
  if (!endpoint || endpoint->ok()) return true;
  *error = endpoint->error();
  return false;
}
}  // namespace

std::unique_ptr<OperatorNode> OperatorNode::Create(dds::Participant* participant,
                                                   const Options& options, Callbacks callbacks,
                                                   std::string* error) {
  std::string why;
  if (!identity::IsValidClientId(options.client_id, &why)) {
    *error = "the client id '" + options.client_id + "' is not valid: " + why;
    return nullptr;
  }
  std::unique_ptr<OperatorNode> node(new OperatorNode());
  node->callbacks_ = std::move(callbacks);
  OperatorNode* self = node.get();
  auto& p = *participant;
  const bool video = options.streams != Options::Streams::kAllButVideo;
  const bool rest = options.streams != Options::Streams::kVideoOnly;
  if (video) {
    using ImageReader = dds::Reader<sensor_msgs::msg::dds_::CompressedImage_PubSubType>;
    node->left_ = std::make_unique<ImageReader>(
        p, topics::kCameraLeft, Stream::kVideo, [self](const dds::wire::CompressedImage& image) {
          if (self->callbacks_.on_image) self->callbacks_.on_image(Eye::kLeft, dds::FromIdl(image));
        });
    node->right_ = std::make_unique<ImageReader>(
        p, topics::kCameraRight, Stream::kVideo, [self](const dds::wire::CompressedImage& image) {
          if (self->callbacks_.on_image) {
            self->callbacks_.on_image(Eye::kRight, dds::FromIdl(image));
          }
        });
  }
  if (rest) {
    using InfoReader = dds::Reader<sensor_msgs::msg::dds_::CameraInfo_PubSubType>;
    for (const Eye eye : {Eye::kLeft, Eye::kRight}) {
      auto reader = std::make_unique<InfoReader>(
          p, eye == Eye::kLeft ? topics::kCameraInfoLeft : topics::kCameraInfoRight, Stream::kState,
          [self, eye](const dds::wire::CameraInfo& info) {
            if (self->callbacks_.on_camera_info) {
              self->callbacks_.on_camera_info(eye, dds::FromIdl(info));
            }
          });
      (eye == Eye::kLeft ? node->left_info_ : node->right_info_) = std::move(reader);
    }
    node->scan_ = std::make_unique<decltype(node->scan_)::element_type>(
        p, topics::kScan, Stream::kSensor, [self](const dds::wire::LaserScan& scan) {
          if (self->callbacks_.on_scan) self->callbacks_.on_scan(dds::FromIdl(scan));
        });
    node->odom_ = std::make_unique<decltype(node->odom_)::element_type>(
        p, topics::kOdometry, Stream::kSensor, [self](const dds::wire::Odometry& odom) {
          if (self->callbacks_.on_odometry) self->callbacks_.on_odometry(dds::FromIdl(odom));
        });
    node->health_ = std::make_unique<decltype(node->health_)::element_type>(
        p, topics::kHealth, Stream::kState, [self](const dds::wire::RobotHealth& health) {
          if (self->callbacks_.on_health) self->callbacks_.on_health(dds::FromIdl(health));
        });
    node->lease_ = std::make_unique<decltype(node->lease_)::element_type>(
        p, topics::kControlLease, Stream::kState, [self](const dds::wire::ControlLease& lease) {
          if (self->callbacks_.on_lease) self->callbacks_.on_lease(dds::FromIdl(lease));
        });
    node->pong_ = std::make_unique<decltype(node->pong_)::element_type>(
        p, topics::kClockPong, Stream::kControl, [self](const dds::wire::ClockProbe& probe) {
          if (self->callbacks_.on_pong) self->callbacks_.on_pong(dds::FromIdl(probe));
        });
    node->sonar_ = std::make_unique<decltype(node->sonar_)::element_type>(
        p, topics::kSonar, Stream::kSensor, [self](const dds::wire::SonarRing& ring) {
          if (self->callbacks_.on_sonar) self->callbacks_.on_sonar(dds::FromIdl(ring));
        });
    node->bumpers_ = std::make_unique<decltype(node->bumpers_)::element_type>(
        p, topics::kBumpers, Stream::kState, [self](const dds::wire::BumperState& state) {
          if (self->callbacks_.on_bumpers) self->callbacks_.on_bumpers(dds::FromIdl(state));
        });
  }
  if (video) {
    node->timing_ = std::make_unique<decltype(node->timing_)::element_type>(
        p, topics::kCameraTiming, Stream::kSensor, [self](const dds::wire::FrameTiming& timing) {
          if (self->callbacks_.on_frame_timing)
            self->callbacks_.on_frame_timing(dds::FromIdl(timing));
        });
    node->video_ = std::make_unique<decltype(node->video_)::element_type>(
        p, topics::kCameraStereoVideo, dds::VideoStreamReaderQos(dds::kVideoStreamDepth),
        dds::kWithWriter, [self](const dds::wire::StereoVideoFrame& frame, const dds::WriterId&) {
          if (self->callbacks_.on_video) self->callbacks_.on_video(dds::FromIdl(frame));
        });
    // Keyframe requests go in the default partition: the robot only rate-limits them. Permissions
    // signed before the topic existed refuse the writer; the console then runs without it (H.264
    // pictures resume at the robot's periodic IDR).
    node->keyframe_ = std::make_unique<decltype(node->keyframe_)::element_type>(
        p, topics::kKeyframeRequest, dds::WriterQos(Stream::kControl));
    if (!node->keyframe_->ok()) {
      MOSTAR_LOG(WARNING) << node->keyframe_->error()
                          << ": the robot cannot be asked for H.264 keyframes; re-sign the "
                             "permissions (make_pki.sh --update-permissions)";
      node->keyframe_.reset();
    }
    node->feedback_ = std::make_unique<decltype(node->feedback_)::element_type>(
        p, topics::kVideoFeedback, dds::WriterQos(Stream::kControl));
    if (!node->feedback_->ok()) {
      MOSTAR_LOG(WARNING) << node->feedback_->error()
                          << ": the robot's video rate control cannot hear this console; re-sign "
                             "the permissions (make_pki.sh --update-permissions)";
      node->feedback_.reset();
    }
  }
  // What the robot must know the sender of goes out in this client's own partition: under DDS
  // Security the permissions of this client's certificate allow no other
  // (common/identity/sender_partition.h).
  const std::string partition = identity::SenderPartition(options.client_id);
  const auto command_qos = dds::InPartition(dds::WriterQos(Stream::kCommand), partition);
  const auto control_qos = dds::InPartition(dds::WriterQos(Stream::kControl), partition);
  if (rest && options.pilot) {
    node->command_ =
        std::make_unique<decltype(node->command_)::element_type>(p, topics::kCommand, command_qos);
  }
  if (rest) {
    node->estop_ = std::make_unique<decltype(node->estop_)::element_type>(p, topics::kEmergencyStop,
                                                                          control_qos);
    node->ping_ =
        std::make_unique<decltype(node->ping_)::element_type>(p, topics::kClockPing, control_qos);
  }
  if (rest && options.pilot) {  // observers never ask for control (and may lack the permission)
    node->request_ = std::make_unique<decltype(node->request_)::element_type>(
        p, topics::kControlRequest, control_qos);
  }
  if (!Check(node->left_, error) || !Check(node->right_, error) || !Check(node->scan_, error) ||
      !Check(node->left_info_, error) || !Check(node->right_info_, error) ||
      !Check(node->odom_, error) || !Check(node->health_, error) || !Check(node->lease_, error) ||
      !Check(node->pong_, error) || !Check(node->sonar_, error) || !Check(node->bumpers_, error) ||
      !Check(node->timing_, error) || !Check(node->video_, error) ||
      !Check(node->command_, error) || !Check(node->estop_, error) ||
      !Check(node->request_, error) || !Check(node->ping_, error)) {
    return nullptr;
  }
  return node;
}

bool OperatorNode::SendCommand(const VelocityCommand& command) {
  return command_ != nullptr && command_->Write(dds::ToIdl(command));
}
bool OperatorNode::SendEmergencyStop(const EmergencyStop& stop) {
  return estop_ != nullptr && estop_->Write(dds::ToIdl(stop));
}
bool OperatorNode::SendControlRequest(const ControlRequest& request) {
  return request_ != nullptr && request_->Write(dds::ToIdl(request));
}
bool OperatorNode::SendKeyframeRequest(const KeyframeRequest& request) {
  return keyframe_ != nullptr && keyframe_->Write(dds::ToIdl(request));
}
bool OperatorNode::SendVideoFeedback(const VideoFeedback& feedback) {
  return feedback_ != nullptr && feedback_->Write(dds::ToIdl(feedback));
}
bool OperatorNode::SendPing(const ClockProbe& probe) {
  return ping_ != nullptr && ping_->Write(dds::ToIdl(probe));
}

}  // namespace mostar::client
