#include "robot_server/node/robot_node.h"

#include <algorithm>

#include "common/dds/conversions.h"
#include "common/dds/topics.h"
#include "common/identity/client_id.h"
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

std::string Hex(const identity::GuidPrefix& prefix) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (const uint8_t b : prefix) {
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
      {"tcp_sockets_guarded", static_cast<uint64_t>(participant_->tcp_sockets_guarded())},
      {"dds_security_off", static_cast<uint64_t>(participant_->security_off())}};
  for (auto& counter : sender_check_->HealthCounters()) network.counters.push_back(counter);
  const dds::PeerIdentityCounters identities = participant_->identity_counters();
  network.counters.emplace_back("certificates_verified", identities.certificates_verified);
  network.counters.emplace_back("certificates_refused", identities.certificates_refused);
  network.counters.emplace_back("clock_clients_evicted", clock_responder_->evicted());
  if (participant_->security_off()) {
    network.state = DeviceState::kWarn;  // every console's HUD lists it
    network.message = "dds security off (--insecure): sender ids unverified";
  } else if (!sender_check_->identities_verified()) {
    network.message = "sender ids unverified: DDS Security is off";
  }
  return network;
}

std::unique_ptr<RobotNode> RobotNode::Create(dds::Participant* participant, Callbacks callbacks,
                                             const Clock* clock, std::string* error,
                                             VideoOptions video) {
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
  std::unique_ptr<RobotNode> node(new RobotNode());
  node->clock_ = clock;
  node->participant_ = participant;
  node->callbacks_ = std::move(callbacks);
  node->sender_check_ = std::make_unique<SenderCheck>(participant->secure());
  node->clock_responder_ = std::make_unique<ClockResponder>(*clock);
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
  node->command_ = std::make_unique<decltype(node->command_)::element_type>(
      p, topics::kCommand, Stream::kCommand, dds::kWithWriter,
      [self](const dds::wire::VelocityCommand& c, const dds::WriterId& from) {
        const VelocityCommand command = dds::FromIdl(c);
        if (!self->Admit(SenderChannel::kCommand, command.sender_id, from)) return;
        self->command_writers_.NoteCommand(from, command.sender_id);
        if (self->callbacks_.on_command) self->callbacks_.on_command(command);
      },
      [self](const dds::LivelinessChange& change) {
        if (change.alive_count_change >= 0) return;
        const std::optional<std::string> lost = self->command_writers_.WriterLost(change.writer);
        if (lost && self->callbacks_.on_command_stream_lost) {
          self->callbacks_.on_command_stream_lost(*lost);
        }
      });
  node->estop_ = std::make_unique<decltype(node->estop_)::element_type>(
      p, topics::kEmergencyStop, Stream::kControl, dds::kWithWriter,
      [self](const dds::wire::EmergencyStop& s, const dds::WriterId& from) {
        const EmergencyStop stop = dds::FromIdl(s);
        if (!self->Admit(SenderChannel::kEmergencyStop, stop.sender_id, from)) return;
        if (self->callbacks_.on_estop) self->callbacks_.on_estop(stop);
      });
  node->request_ = std::make_unique<decltype(node->request_)::element_type>(
      p, topics::kControlRequest, Stream::kControl, dds::kWithWriter,
      [self](const dds::wire::ControlRequest& r, const dds::WriterId& from) {
        const ControlRequest request = dds::FromIdl(r);
        if (!self->Admit(SenderChannel::kControlRequest, request.sender_id, from)) return;
        if (self->callbacks_.on_control_request) self->callbacks_.on_control_request(request);
      });
  node->ping_ = std::make_unique<decltype(node->ping_)::element_type>(
      p, topics::kClockPing, Stream::kControl, dds::kWithWriter,
      [self](const dds::wire::ClockProbe& ping, const dds::WriterId& from) {
        self->OnPing(dds::FromIdl(ping), from);
      });
  for (const VideoLane& lane : node->lanes_) {
    if (!Check(lane.left, error) || !Check(lane.right, error)) return nullptr;
  }
  if (!Check(node->scan_, error) || !Check(node->left_info_, error) ||
      !Check(node->right_info_, error) || !Check(node->odom_, error) ||
      !Check(node->timing_, error) || !Check(node->health_, error) || !Check(node->sonar_, error) ||
      !Check(node->sonar_range_, error) || !Check(node->bumpers_, error) ||
      !Check(node->lease_, error) || !Check(node->pong_, error) || !Check(node->command_, error) ||
      !Check(node->estop_, error) || !Check(node->request_, error) || !Check(node->ping_, error)) {
    return nullptr;
  }
  node->publisher_ = std::thread([self] { self->PublisherLoop(); });
  return node;
}

bool RobotNode::Admit(SenderChannel channel, const std::string& sender_id,
                      const dds::WriterId& from) {
  const std::optional<std::string> writer = participant_->AuthenticatedClientId(from.participant);
  const SenderVerdict verdict = sender_check_->Check(channel, sender_id, writer);
  if (SenderCheck::Admits(verdict)) return true;
  MOSTAR_LOG_EVERY_SEC(WARNING, 5)
      << SenderChannelName(channel) << " from participant " << Hex(from.participant) << " as "
      << Printable(sender_id) << " dropped: " << SenderVerdictName(verdict)
      << (writer ? " (its certificate is '" + *writer + "')" : "");
  return false;
}

void RobotNode::OnPing(const ClockProbe& ping, const dds::WriterId& from) {
  const Time received = clock_->Now();
  if (!Admit(SenderChannel::kClockPing, ping.sender_id, from)) return;
  pong_->Write(dds::ToIdl(clock_responder_->Answer(ping.sender_id, ping, received)));
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
