#include "robot_server/node/robot_node.h"

#include <algorithm>
#include <set>

#include "common/dds/conversions.h"
#include "common/dds/topics.h"
#include "common/identity/client_id.h"
#include "common/identity/sender_partition.h"
#include "common/log/log.h"

namespace mostar::server {

namespace topics = dds::topics;
using dds::Stream;

namespace {

template <class T>
bool Check(const std::unique_ptr<T>& endpoint, std::string* error) {
  if (endpoint->ok()) return true;
  *error = endpoint->error();
  return false;
}

// An id as it may be logged: valid ids as they are, others replaced (no control characters).
std::string Printable(const std::string& id) {
  return identity::IsValidClientId(id) ? "'" + id + "'" : "an invalid id";
}

// "e7.3d.67...": as Fast DDS prints a GUID prefix (the participant logs of common/dds/security.cc).
std::string Hex(const identity::GuidPrefix& prefix) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (const uint8_t b : prefix) {
    if (!out.empty()) out += '.';
    out += digits[b >> 4];
    out += digits[b & 15];
  }
  return out;
}

}  // namespace

DeviceHealth RobotNode::NetworkHealth() const {
  DeviceHealth network;
  network.name = "network";
  network.counters = {
      {"video_pairs_sent", pairs_sent()},
      {"video_pairs_skipped", pairs_skipped()},
      {"video_lanes_reclaimed", lanes_reclaimed()},
      {"outbox_dropped", outbox_dropped()},
      {"frame_subscribers", static_cast<uint64_t>(frame_subscribers())},
      {"h264_frames_sent", video_frames_sent()},
      {"keyframe_requests_heard", keyframe_requests()},
      {"tcp_sockets_guarded", static_cast<uint64_t>(participant_->tcp_sockets_guarded())},
      {"dds_security_off", static_cast<uint64_t>(participant_->security_off())}};
  for (auto& counter : sender_check_->HealthCounters()) network.counters.push_back(counter);
  const dds::PeerIdentityCounters identities = participant_->identity_counters();
  network.counters.emplace_back("certificates_verified", identities.certificates_verified);
  network.counters.emplace_back("certificates_refused", identities.certificates_refused);
  network.counters.emplace_back("clock_clients_evicted", unlisted_clock_responder_->evicted());
  const std::vector<std::string> missing = participant_->MissingProfileAddresses();
  network.counters.emplace_back("profile_addresses_missing", missing.size());
  if (!missing.empty()) {
    // Nobody remote reads this while it lasts; the local log, the recording and a console on
    // this host do.
    network.state = DeviceState::kWarn;
    network.message = "address " + missing.front() +
                      " of the DDS profile is not on this host (overlay down?): unreachable";
  } else if (participant_->security_off()) {
    network.state = DeviceState::kWarn;  // every console's HUD lists it
    network.message = "dds security off (--insecure): sender ids unverified";
  } else if (!sender_check_->identities_verified()) {
    network.message = "sender ids unverified: DDS Security is off";
  }
  return network;
}

std::unique_ptr<RobotNode> RobotNode::Create(dds::Participant* participant,
                                             const std::vector<RobotSender>& senders,
                                             Callbacks callbacks, const Clock* clock,
                                             std::string* error, VideoOptions video) {
  if (video.window_pairs < 1) {
    if (error) *error = "the video window must be at least one pair";
    return nullptr;
  }
  if (video.lane_timeout <= Duration::zero()) {
    if (error) *error = "the video lane timeout must be positive";
    return nullptr;
  }
  if (video.repair_period <= std::chrono::milliseconds::zero()) {
    if (error) *error = "the video repair period must be positive";
    return nullptr;
  }
  if (video.repair_deadline < std::chrono::milliseconds::zero()) {
    if (error) *error = "the video repair deadline must not be negative";
    return nullptr;
  }
  std::unique_ptr<RobotNode> node(new RobotNode());
  node->clock_ = clock;
  node->participant_ = participant;
  node->callbacks_ = std::move(callbacks);
  for (const RobotSender& sender : senders) {
    std::string why;
    if (!identity::IsValidClientId(sender.client_id, &why)) {
      if (error) *error = "sender '" + sender.client_id + "': " + why;
      return nullptr;
    }
    if (!node->listed_.insert(sender.client_id).second) {
      if (error) *error = "sender '" + sender.client_id + "' is listed twice";
      return nullptr;
    }
  }
  node->sender_check_ = std::make_unique<SenderCheck>(participant->secure());
  // One slot per role-table client: only they reach it, so none is ever evicted.
  node->clock_responder_ =
      std::make_unique<ClockResponder>(*clock, std::max<size_t>(1, senders.size()));
  node->unlisted_clock_responder_ = std::make_unique<ClockResponder>(*clock);
  if (!participant->secure()) {
    MOSTAR_LOG(WARNING) << "DDS Security is off: the sender ids of commands, e-stops, control "
                           "requests and clock pings cannot be verified";
  }
  node->lane_timeout_ = video.lane_timeout;
  RobotNode* self = node.get();
  auto& p = *participant;
  const auto video_qos = dds::VideoWriterQos(video.repair_period);
  for (int i = 0; i < video.window_pairs; ++i) {
    VideoLane lane;
    lane.left = std::make_unique<ImageWriter>(p, topics::kCameraLeft, video_qos);
    lane.right = std::make_unique<ImageWriter>(p, topics::kCameraRight, video_qos);
    node->lanes_.push_back(std::move(lane));
  }
  // The H.264 endpoints only when the camera sends H.264: a JPEG robot has no more endpoints
  // to rediscover after an outage than before.
  if (video.h264) {
    node->stereo_video_ = std::make_unique<decltype(node->stereo_video_)::element_type>(
        p, topics::kCameraStereoVideo,
        dds::VideoStreamWriterQos(video.repair_period, dds::kVideoStreamDepth,
                                  video.repair_deadline),
        [self](int change) {
          // Each reader is one copy of the stream up the robot's uplink (viewers behind
          // mostar_relay are not readers here).
          const int readers = self->h264_readers_.fetch_add(change) + change;
          MOSTAR_LOG(INFO) << "readers of the H.264 stream: " << readers;
          // A new viewer of the H.264 stream needs an IDR to start decoding: ask at once rather
          // than wait for its own request one round trip later.
          if (change > 0 && self->callbacks_.on_keyframe_request) {
            KeyframeRequest join;
            join.stamp = self->clock_->Now();
            join.reason = "join";
            self->callbacks_.on_keyframe_request(join);
          }
        });
    for (const Eye eye : {Eye::kLeft, Eye::kRight}) {
      (eye == Eye::kLeft ? node->left_video_ : node->right_video_) =
          std::make_unique<decltype(node->left_video_)::element_type>(
              p, eye == Eye::kLeft ? topics::kCameraLeftVideo : topics::kCameraRightVideo,
              dds::VideoStreamWriterQos(video.repair_period, dds::kVideoStreamDepth,
                                        video.repair_deadline),
              [self](int change) {
                if (change > 0 && self->callbacks_.on_keyframe_request) {
                  KeyframeRequest join;
                  join.stamp = self->clock_->Now();
                  join.reason = "join (foxglove)";
                  self->callbacks_.on_keyframe_request(join);
                }
              });
    }
  }
  node->left_info_ = std::make_unique<decltype(node->left_info_)::element_type>(
      p, topics::kCameraInfoLeft, Stream::kState);
  node->right_info_ = std::make_unique<decltype(node->right_info_)::element_type>(
      p, topics::kCameraInfoRight, Stream::kState);
  node->scan_ =
      std::make_unique<decltype(node->scan_)::element_type>(p, topics::kScan, Stream::kSensor);
  node->odom_ =
      std::make_unique<decltype(node->odom_)::element_type>(p, topics::kOdometry, Stream::kSensor);
  node->timing_ = std::make_unique<decltype(node->timing_)::element_type>(p, topics::kCameraTiming,
                                                                          Stream::kSensor);
  node->sonar_ =
      std::make_unique<decltype(node->sonar_)::element_type>(p, topics::kSonar, Stream::kSensor);
  node->sonar_range_ = std::make_unique<decltype(node->sonar_range_)::element_type>(
      p, topics::kSonarRange, Stream::kSensor);
  node->bumpers_ =
      std::make_unique<decltype(node->bumpers_)::element_type>(p, topics::kBumpers, Stream::kState);
  node->health_ =
      std::make_unique<decltype(node->health_)::element_type>(p, topics::kHealth, Stream::kState);
  node->lease_ = std::make_unique<decltype(node->lease_)::element_type>(p, topics::kControlLease,
                                                                        Stream::kState);
  node->pong_ = std::make_unique<decltype(node->pong_)::element_type>(p, topics::kClockPong,
                                                                      Stream::kControl);
  for (const RobotSender& sender : senders) {
    if (!node->AddSender(p, sender, error)) return nullptr;
  }
  node->unlisted_ping_ = std::make_unique<PingReader>(
      p, topics::kClockPing,
      dds::InPartition(dds::ReaderQos(Stream::kControl), identity::kAnySenderPartition),
      dds::kWithWriter, [self](const dds::wire::ClockProbe& ping, const dds::WriterId& from) {
        self->OnUnlistedPing(dds::FromIdl(ping), from);
      });
  if (video.h264) {
    // Keyframe requests come in the default partition from any viewer (they only cost an IDR,
    // at most one per 300 ms). Permissions signed before this topic existed refuse the reader:
    // the robot then runs without it (viewers wait for the periodic IDR), and says so.
    node->keyframe_requests_reader_ = std::make_unique<KeyframeReader>(
        p, topics::kKeyframeRequest, dds::ReaderQos(Stream::kControl), dds::kWithWriter,
        [self](const dds::wire::KeyframeRequest& r, const dds::WriterId&) {
          ++self->keyframe_requests_;
          if (self->callbacks_.on_keyframe_request) {
            self->callbacks_.on_keyframe_request(dds::FromIdl(r));
          }
        });
    if (!node->keyframe_requests_reader_->ok()) {
      MOSTAR_LOG(WARNING) << node->keyframe_requests_reader_->error()
                          << ": keyframe requests are not heard (H.264 viewers wait for the "
                             "periodic IDR); re-sign the permissions: make_pki.sh "
                             "--update-permissions";
      node->keyframe_requests_reader_.reset();
    }
    node->feedback_reader_ = std::make_unique<FeedbackReader>(
        p, topics::kVideoFeedback, dds::ReaderQos(Stream::kControl), dds::kWithWriter,
        [self](const dds::wire::VideoFeedback& f, const dds::WriterId&) {
          if (self->callbacks_.on_video_feedback)
            self->callbacks_.on_video_feedback(dds::FromIdl(f));
        });
    if (!node->feedback_reader_->ok()) {
      MOSTAR_LOG(WARNING) << node->feedback_reader_->error()
                          << ": viewers' receive reports are not heard (the H.264 rate stays at "
                             "the class target); re-sign the permissions: make_pki.sh "
                             "--update-permissions";
      node->feedback_reader_.reset();
    }
  }
  for (const VideoLane& lane : node->lanes_) {
    if (!Check(lane.left, error) || !Check(lane.right, error)) return nullptr;
  }
  if (video.h264 && (!Check(node->stereo_video_, error) || !Check(node->left_video_, error) ||
                     !Check(node->right_video_, error))) {
    return nullptr;
  }
  if (!Check(node->scan_, error) || !Check(node->left_info_, error) ||
      !Check(node->right_info_, error) || !Check(node->odom_, error) ||
      !Check(node->timing_, error) || !Check(node->health_, error) || !Check(node->sonar_, error) ||
      !Check(node->sonar_range_, error) || !Check(node->bumpers_, error) ||
      !Check(node->lease_, error) || !Check(node->pong_, error) ||
      !Check(node->unlisted_ping_, error)) {
    return nullptr;
  }
  node->publisher_ = std::thread([self] { self->PublisherLoop(); });
  return node;
}

bool RobotNode::AddSender(dds::Participant& p, const RobotSender& sender, std::string* error) {
  auto readers = std::make_unique<SenderReaders>();
  readers->client_id = sender.client_id;
  const std::string client = sender.client_id;
  const std::string partition = identity::SenderPartition(client);
  const auto control_qos = dds::InPartition(dds::ReaderQos(Stream::kControl), partition);
  const auto matched = [this, client](SenderChannel channel) {
    return [this, client, channel](const dds::MatchChange& change) {
      if (change.current_count_change > 0) OnSenderMatched(channel, client, change.writer);
    };
  };
  if (sender.pilot) {
    readers->command = std::make_unique<CommandReader>(
        p, topics::kCommand, dds::InPartition(dds::ReaderQos(Stream::kCommand), partition),
        dds::kWithWriter,
        [this, client](const dds::wire::VelocityCommand& c, const dds::WriterId& from) {
          const VelocityCommand command = dds::FromIdl(c);
          if (!Admit(SenderChannel::kCommand, command.sender_id, client, from)) return;
          command_writers_.NoteCommand(from, client);
          if (callbacks_.on_command) callbacks_.on_command(command);
        },
        [this](const dds::LivelinessChange& change) {
          if (change.alive_count_change >= 0) return;
          const std::optional<std::string> lost = command_writers_.WriterLost(change.writer);
          if (lost && callbacks_.on_command_stream_lost) callbacks_.on_command_stream_lost(*lost);
        },
        matched(SenderChannel::kCommand));
    readers->request = std::make_unique<RequestReader>(
        p, topics::kControlRequest, control_qos, dds::kWithWriter,
        [this, client](const dds::wire::ControlRequest& r, const dds::WriterId& from) {
          const ControlRequest request = dds::FromIdl(r);
          if (!Admit(SenderChannel::kControlRequest, request.sender_id, client, from)) return;
          if (callbacks_.on_control_request) callbacks_.on_control_request(request);
        },
        RequestReader::LivelinessCallback(), matched(SenderChannel::kControlRequest));
  }
  readers->estop = std::make_unique<EstopReader>(
      p, topics::kEmergencyStop, control_qos, dds::kWithWriter,
      [this, client](const dds::wire::EmergencyStop& s, const dds::WriterId& from) {
        const EmergencyStop stop = dds::FromIdl(s);
        if (!Admit(SenderChannel::kEmergencyStop, stop.sender_id, client, from)) return;
        if (callbacks_.on_estop) callbacks_.on_estop(stop);
      },
      EstopReader::LivelinessCallback(), matched(SenderChannel::kEmergencyStop));
  readers->ping = std::make_unique<PingReader>(
      p, topics::kClockPing, control_qos, dds::kWithWriter,
      [this, client](const dds::wire::ClockProbe& ping, const dds::WriterId& from) {
        const ClockProbe probe = dds::FromIdl(ping);
        if (!Admit(SenderChannel::kClockPing, probe.sender_id, client, from)) return;
        OnPing(probe, client);
      },
      PingReader::LivelinessCallback(), matched(SenderChannel::kClockPing));
  if ((readers->command && !Check(readers->command, error)) ||
      (readers->request && !Check(readers->request, error)) || !Check(readers->estop, error) ||
      !Check(readers->ping, error)) {
    return false;
  }
  senders_.push_back(std::move(readers));
  return true;
}

int RobotNode::command_writers() const {
  int matched = 0;
  for (const auto& readers : senders_) {
    if (readers->command) matched += readers->command->matched();
  }
  return matched;
}

bool RobotNode::Admit(SenderChannel channel, const std::string& sender_id,
                      const std::string& client, const dds::WriterId& from) {
  const SenderVerdict verdict = sender_check_->Check(channel, sender_id, client);
  if (SenderCheck::Admits(verdict)) return true;
  MOSTAR_LOG_EVERY_SEC(WARNING, 5)
      << SenderChannelName(channel) << " as " << Printable(sender_id) << " in the partition of '"
      << client << "'" << (sender_check_->identities_verified() ? " (its certificate's)" : "")
      << " from participant " << Hex(from.participant)
      << " dropped: " << SenderVerdictName(verdict);
  return false;
}

void RobotNode::OnSenderMatched(SenderChannel channel, const std::string& client,
                                const dds::WriterId& writer) {
  const std::string participant = Hex(writer.participant);
  if (!proofs_.First(client, participant)) return;
  if (sender_check_->identities_verified()) {
    MOSTAR_LOG(INFO) << "client '" << client << "' is DDS participant " << participant << ": its "
                     << SenderChannelName(channel) << " writer matched in partition "
                     << identity::SenderPartition(client)
                     << ", which DDS access control allows only the signed permissions of '"
                     << client << "'";
  } else {
    MOSTAR_LOG(INFO) << "DDS participant " << participant << " writes as '" << client << "' (its "
                     << SenderChannelName(channel) << " writer matched in partition "
                     << identity::SenderPartition(client) << "; unproven: DDS Security is off)";
  }
}

void RobotNode::OnPing(const ClockProbe& ping, const std::string& client) {
  const Time received = clock_->Now();
  pong_->Write(dds::ToIdl(clock_responder_->Answer(client, ping, received)));
}

void RobotNode::OnUnlistedPing(const ClockProbe& ping, const dds::WriterId& from) {
  const Time received = clock_->Now();
  // A role-table client's pings count in its own partition only (this reader hears them there
  // too); here its id is anybody's claim.
  if (listed_.count(ping.sender_id) != 0) return;
  if (!identity::IsValidClientId(ping.sender_id)) {
    // Counted as an invalid id (the check fails on the id before it compares).
    sender_check_->Check(SenderChannel::kClockPing, ping.sender_id, ping.sender_id);
    MOSTAR_LOG_EVERY_SEC(WARNING, 5)
        << "clock_ping from participant " << Hex(from.participant) << " dropped: invalid sender_id";
    return;
  }
  pong_->Write(dds::ToIdl(unlisted_clock_responder_->Answer(ping.sender_id, ping, received)));
}

std::optional<Duration> RobotNode::RobotMinusClient(const std::string& client_id) const {
  return clock_responder_->RobotMinusClient(client_id);
}

bool RobotNode::PublishStereo(const CompressedStereoPair& pair) {
  const SteadyTime now = clock_->SteadyNow();
  VideoLane* chosen = nullptr;
  for (VideoLane& lane : lanes_) {
    if (lane.left->AllAcknowledged() && lane.right->AllAcknowledged()) {
      chosen = &lane;
      break;
    }
  }
  if (chosen == nullptr) {
    // Every lane busy. Reclaim the oldest one if a reader has sat on it for lane_timeout.
    VideoLane* oldest = &lanes_.front();
    for (VideoLane& lane : lanes_) {
      if (!lane.written || (oldest->written && *lane.written < *oldest->written)) oldest = &lane;
    }
    if (oldest->written && now - *oldest->written >= lane_timeout_) {
      chosen = oldest;
      ++lanes_reclaimed_;
    }
  }
  if (chosen == nullptr) {
    ++pairs_skipped_;  // the link is full: skip rather than queue
    return false;
  }
  chosen->written = now;
  video_write_since_ns_ = now.time_since_epoch().count();
  const bool left_ok = chosen->left->Write(dds::ToIdl(pair.left));
  const bool right_ok = chosen->right->Write(dds::ToIdl(pair.right));
  video_write_since_ns_ = 0;
  if (!left_ok || !right_ok) return false;
  ++pairs_sent_;
  // The robot's half of the operator's latency trace, through the outbox (never blocks here).
  const FrameTiming timing{pair.left.stamp, pair.encoded, clock_->Now()};
  Post([this, m = dds::ToIdl(timing)] { timing_->Write(m); });
  return true;
}

bool RobotNode::SetVideoRepairDeadline(std::chrono::milliseconds deadline, std::string* error) {
  if (!stereo_video_) {
    *error = "no H.264 stream";
    return false;
  }
  for (eprosima::fastdds::dds::DataWriter* writer :
       {stereo_video_->get(), left_video_ ? left_video_->get() : nullptr,
        right_video_ ? right_video_->get() : nullptr}) {
    if (writer != nullptr && !dds::SetRepairDeadline(writer, deadline, error)) return false;
  }
  return true;
}

bool RobotNode::PublishStereoVideo(const StereoVideoFrame& frame) {
  if (!stereo_video_) return false;  // not created for H.264 (VideoOptions::h264)
  video_write_since_ns_ = clock_->SteadyNow().time_since_epoch().count();
  const bool ok = stereo_video_->Write(dds::ToIdl(frame));
  if (left_video_->matched() > 0) left_video_->Write(dds::ToFoxgloveVideo(frame, Eye::kLeft));
  if (right_video_->matched() > 0) right_video_->Write(dds::ToFoxgloveVideo(frame, Eye::kRight));
  video_write_since_ns_ = 0;
  if (!ok) return false;
  ++pairs_sent_;
  ++video_frames_sent_;
  const FrameTiming timing{frame.stamp, frame.encoded, clock_->Now()};
  Post([this, m = dds::ToIdl(timing)] { timing_->Write(m); });
  return true;
}

void RobotNode::PublishCameraInfo(Eye eye, const CameraIntrinsicsInfo& info) {
  // Through the outbox: the control loop re-publishes the intrinsics with the lease.
  Post([writer = (eye == Eye::kLeft ? left_info_ : right_info_).get(), m = dds::ToIdl(info)] {
    writer->Write(m);
  });
}

void RobotNode::PublishImage(Eye eye, const CompressedImage& image) {
  VideoLane& lane = lanes_.front();
  (eye == Eye::kLeft ? lane.left : lane.right)->Write(dds::ToIdl(image));
}

void RobotNode::PublishScan(const LaserScan& scan) {
  Post([this, m = dds::ToIdl(scan)] { scan_->Write(m); });
}
void RobotNode::PublishOdometry(const Odometry& odometry) {
  Post([this, m = dds::ToIdl(odometry)] { odom_->Write(m); });
}
void RobotNode::PublishSonar(const SonarRanges& ranges) {
  Post([this, m = dds::ToIdl(ranges)] { sonar_->Write(m); });
  for (const SonarRange& range : ranges.ranges) {
    Post([this, m = dds::ToIdl(range)] { sonar_range_->Write(m); });
  }
}
void RobotNode::PublishBumpers(const BumperState& state) {
  Post([this, m = dds::ToIdl(state)] { bumpers_->Write(m); });
}
void RobotNode::PublishHealth(const RobotHealth& health) {
  Post([this, m = dds::ToIdl(health)] { health_->Write(m); });
}
void RobotNode::PublishLease(const ControlLease& lease) {
  {
    // A new holder starts with a fresh clock offset (and the old one's is dropped).
    std::lock_guard<std::mutex> lock(lease_mutex_);
    if (lease.holder_id != lease_holder_) {
      clock_responder_->Forget(lease_holder_);
      clock_responder_->Forget(lease.holder_id);
      lease_holder_ = lease.holder_id;
    }
  }
  Post([this, m = dds::ToIdl(lease)] { lease_->Write(m); });
}

void RobotNode::Post(std::function<void()> write) {
  {
    std::lock_guard<std::mutex> lock(outbox_mutex_);
    if (outbox_.size() >= kOutboxCapacity) {
      outbox_.pop_front();
      ++outbox_dropped_;
    }
    outbox_.push_back(std::move(write));
  }
  outbox_cv_.notify_all();
}

void RobotNode::PublisherLoop() {
  std::unique_lock<std::mutex> lock(outbox_mutex_);
  while (true) {
    outbox_cv_.wait(lock, [this] { return stop_ || !outbox_.empty(); });
    if (outbox_.empty()) return;  // stopping and nothing left
    std::function<void()> write = std::move(outbox_.front());
    outbox_.pop_front();
    writing_ = true;
    lock.unlock();
    outbox_write_since_ns_ = clock_->SteadyNow().time_since_epoch().count();
    write();  // may block while a link is down; callers keep posting meanwhile
    outbox_write_since_ns_ = 0;
    lock.lock();
    writing_ = false;
    outbox_cv_.notify_all();
  }
}

Duration RobotNode::BlockedWriteDuration(SteadyTime now) const {
  Duration longest = Duration::zero();
  for (int64_t since : {outbox_write_since_ns_.load(), video_write_since_ns_.load()}) {
    if (since == 0) continue;
    longest = std::max(longest, now - SteadyTime(std::chrono::nanoseconds(since)));
  }
  return longest;
}

bool RobotNode::FlushOutbox(Duration timeout) {
  std::unique_lock<std::mutex> lock(outbox_mutex_);
  return outbox_cv_.wait_for(lock, timeout, [this] { return outbox_.empty() && !writing_; });
}

RobotNode::~RobotNode() {
  if (publisher_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(outbox_mutex_);
      stop_ = true;
    }
    outbox_cv_.notify_all();
    publisher_.join();
  }
}

}  // namespace mostar::server
