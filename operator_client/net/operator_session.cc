#include "operator_client/net/operator_session.h"

#include <utility>

namespace mostar::client {

std::unique_ptr<OperatorSession> OperatorSession::Create(
    const Options& options, std::string* error, std::unique_ptr<dds::Participant> participant,
    std::unique_ptr<dds::Participant> video_participant) {
  std::unique_ptr<OperatorSession> session(new OperatorSession());
  session->participant_ =
      participant ? std::move(participant) : dds::Participant::Create(options.dds, error);
  if (!session->participant_) return nullptr;
  if (options.video_dds) {
    session->video_participant_ = video_participant
                                      ? std::move(video_participant)
                                      : dds::Participant::Create(*options.video_dds, error);
    if (!session->video_participant_) {
      *error = "video through the relay: " + *error;
      return nullptr;
    }
  }
  OperatorNode::Options node_options = options.node;
  node_options.streams = session->video_participant_ ? OperatorNode::Options::Streams::kAllButVideo
                                                     : OperatorNode::Options::Streams::kAll;
  session->node_ =
      OperatorNode::Create(session->participant_.get(), node_options, options.callbacks, error);
  if (!session->node_) return nullptr;
  if (session->video_participant_) {
    node_options.streams = OperatorNode::Options::Streams::kVideoOnly;
    session->video_node_ = OperatorNode::Create(session->video_participant_.get(), node_options,
                                                options.callbacks, error);
    if (!session->video_node_) return nullptr;
  }
  return session;
}

OperatorSession::~OperatorSession() {
  video_node_.reset();
  node_.reset();
  video_participant_.reset();
  participant_.reset();
}

}  // namespace mostar::client
