// Where each message the operator client receives goes: the recording (when one is written),
// the stamp trace, the robot state and the video receiver. The callbacks run on DDS threads;
// everything they call is thread-safe.
#pragma once

#include <string>

#include "common/log/stamp_trace.h"
#include "common/record/recording_writer.h"
#include "common/time/time.h"
#include "operator_client/net/operator_node.h"
#include "operator_client/net/robot_state.h"
#include "operator_client/video/stereo_receiver.h"

namespace mostar::client {

struct ClientInbox {
  std::string client_id;  // clock pongs answering other clients' pings are ignored
  const Clock* clock = nullptr;
  StereoReceiver* video = nullptr;
  RobotState* robot = nullptr;
  record::RecordingWriter* recorder = nullptr;  // null: nothing recorded
  StampTrace* trace = nullptr;                  // null: nothing traced
};

// The node's callbacks for `inbox`, whose members must outlive the node. Images go to the
// receiver, which refuses any larger than the size the robot's camera info announces; pongs
// update the clock offset with which the receiver refuses pairs stamped in the future.
OperatorNode::Callbacks InboxCallbacks(const ClientInbox& inbox);

}  // namespace mostar::client
