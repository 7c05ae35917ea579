// The console's DDS side: its participant and node on the robot's domain and, when it takes its
// video through mostar_relay, a second participant and node on the relay's observer domain.
// Made together and replaced together when the console joins again (RejoinPolicy): the nodes
// go before their participants.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "common/dds/participant.h"
#include "operator_client/net/operator_node.h"

namespace mostar::client {

class OperatorSession {
 public:
  struct Options {
    dds::ParticipantOptions dds;
    std::optional<dds::ParticipantOptions> video_dds;  // video through mostar_relay
    OperatorNode::Options node;  // streams: set here (all, or all but video + video only)
    OperatorNode::Callbacks callbacks;
  };

  // Makes what is missing: `participant` and `video_participant` when given (already made, e.g.
  // to read the client id from the certificate first) are used as they are. Null with `error`.
  static std::unique_ptr<OperatorSession> Create(
      const Options& options, std::string* error,
      std::unique_ptr<dds::Participant> participant = nullptr,
      std::unique_ptr<dds::Participant> video_participant = nullptr);
  ~OperatorSession();  // the nodes, then the participants
  OperatorSession(const OperatorSession&) = delete;
  OperatorSession& operator=(const OperatorSession&) = delete;

  dds::Participant& participant() { return *participant_; }
  dds::Participant* video_participant() { return video_participant_.get(); }  // or null
  OperatorNode& node() { return *node_; }
  // Where the camera streams come from and keyframe requests and receive reports go.
  OperatorNode& video_source() { return video_node_ ? *video_node_ : *node_; }
  // Some writer of the robot (or, for the video, of the relay) matched: the console's side of
  // the handshake ended, on both domains when it has two.
  bool robot_seen() const {
    return node_ != nullptr && node_->robot_seen() &&
           (video_node_ == nullptr || video_node_->robot_seen());
  }
  // Deletes the nodes (no more callbacks), keeps the participants; node() and video_source()
  // must not be called after it.
  void CloseNodes() {
    video_node_.reset();
    node_.reset();
  }

 private:
  OperatorSession() = default;
  std::unique_ptr<dds::Participant> participant_;
  std::unique_ptr<dds::Participant> video_participant_;
  std::unique_ptr<OperatorNode> node_;
  std::unique_ptr<OperatorNode> video_node_;
};

}  // namespace mostar::client
