// The robot's DDS face: publishes sensors, state and health, receives commands.
//
// Knows DDS and the wire types; knows nothing of devices. Callbacks run on DDS threads and must
// be quick (hand the data over, do not block). Clock pings are answered here (NTP-style pong
// with receive and send stamps on the robot clock, ClockResponder).
//
// Who sent what: every client of the role table (RobotSender) gets its own readers, in its own
// DDS partition (common/identity/sender_partition.h): e-stop and clock pings for everyone,
// cmd_vel and control requests for pilots too. A sample's client is the partition it arrived
// in: with DDS Security only the certificate of that client may write there (its signed
// permissions; Fast DDS checks them against the certificate that authenticated, whatever GUID
// the participant announces). Each sample then passes SenderCheck (its sender_id must be that
// client) before it is handed on; drops are counted in the "network" health device and logged
// (at most every 5 s). Without DDS Security ids are claims and the health says
// identities_verified = 0. Clients outside the role table may only ping the clock (one more
// reader over every client partition): they get pongs, but are kept apart from the role table's
// clock offsets, which they can neither move nor evict. Clock offsets are kept per client id and
// reset for the old and the new holder when the lease changes hands (seen in PublishLease).
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "common/dds/endpoint.h"
#include "common/dds/qos.h"
#include "common/time/time.h"
#include "common/types/bumper.h"
#include "common/types/commands.h"
#include "common/types/health.h"
#include "common/types/laser_scan.h"
#include "common/types/odometry.h"
#include "common/types/sonar.h"
#include "common/types/stereo_frame.h"
#include "foxglove_msgsPubSubTypes.h"
#include "mostar_msgsPubSubTypes.h"
#include "robot_server/node/clock_responder.h"
#include "robot_server/node/command_writers.h"
#include "robot_server/node/robot_link.h"
#include "robot_server/node/sender_check.h"
#include "ros2_msgsPubSubTypes.h"

namespace mostar::server {

// The robot's video ack-clock (see RobotNode::PublishStereo).
struct RobotVideoOptions {
  // Stereo pairs that may be in flight unacknowledged: that many writer pairs ("lanes") per
  // camera topic; >= 1.
  int window_pairs = 4;
  // A lane whose pair some reader has not acknowledged for this long is used again; > 0.
  Duration lane_timeout = std::chrono::milliseconds(2000);
  // Heartbeat period of the video writers (dds::VideoWriterQos): about the round trip on long
  // links; > 0.
  std::chrono::milliseconds repair_period = dds::kDefaultVideoRepairPeriod;
  // H.264 stream only: an AU is repaired for at most this long after it was written
  // (dds::VideoStreamWriterQos); 0: until the history rolls over.
  std::chrono::milliseconds repair_deadline{0};
  // The camera sends H.264: create the stream's writers (stereo and Foxglove) and the readers of
  // keyframe requests and receive reports. Without it PublishStereoVideo returns false.
  bool h264 = false;
};

// A client of the robot's role table: whose samples the robot reads, in its partition.
struct RobotSender {
  std::string client_id;  // valid (client_id.h)
  bool pilot = false;     // also cmd_vel and control requests
};

class RobotNode final : public RobotLink {
 public:
  struct Callbacks {
    std::function<void(const VelocityCommand&)> on_command;
    std::function<void(const EmergencyStop&)> on_estop;
    std::function<void(const ControlRequest&)> on_control_request;
    // The DDS liveliness of the last live cmd_vel writer of `client_id` was lost (silent for
    // the liveliness lease, or gone): its command stream is gone.
    std::function<void(const std::string& client_id)> on_command_stream_lost;
    // A viewer asked for an IDR (KeyframeRequest_), or a new reader matched the H.264 stream
    // (reason "join"): the camera pipeline decides when (at most one IDR per 300 ms).
    std::function<void(const KeyframeRequest&)> on_keyframe_request;
    // A viewer's receive report of the H.264 frames (VideoFeedback_), for the rate control.
    std::function<void(const VideoFeedback&)> on_video_feedback;
  };

  using VideoOptions = RobotVideoOptions;
  // Creates every endpoint, with readers for each of `senders` (ids distinct and valid); null
  // with `error` when one cannot be created, or `senders` or `video` is invalid. No senders: the
  // robot hears nobody but clock pings (replay).
  static std::unique_ptr<RobotNode> Create(dds::Participant* participant,
                                           const std::vector<RobotSender>& senders,
                                           Callbacks callbacks, const Clock* clock,
                                           std::string* error, VideoOptions video = {});
  // Both eyes, then (through the outbox) their FrameTiming on rt/mostar/camera/timing; false
  // when the pair was not sent: skipped at the source because every lane still
  // has an unacknowledged pair (ack-clock with a window), or refused by DDS.
  //
  // Ack-clock with a window: each camera topic has `window_pairs` reliable keep-last-1 writers.
  // A pair goes out on a lane whose previous pair every reliable reader acknowledged, so at
  // most that many pairs are in flight: enough to fill a long link (one pair in flight caps
  // the rate near 1 / round trip), never an unbounded queue. With no free lane the pair is
  // skipped at the source and the bitrate control lowers the quality.
  //
  // One reader that stops acknowledging (a frozen observer, a vanished link: DDS keeps it
  // matched until its participant lease expires) would hold every lane and starve everyone
  // else; so a lane left unacknowledged for `lane_timeout` is written again (keep-last-1: the
  // stuck reader skips to the newer pair). Such a reader is then offered at most
  // window_pairs / lane_timeout pairs per second.
  bool PublishStereo(const CompressedStereoPair& pair);
  // Both eyes' H.264 access units on rt/mostar/camera/stereo/h264 (reliable, keep last
  // kVideoStreamDepth: never skipped at the source, never blocks), each eye also as
  // foxglove_msgs/CompressedVideo while a reader of that topic is matched, then the
  // FrameTiming. False when DDS refused the sample.
  bool PublishStereoVideo(const StereoVideoFrame& frame);
  // The H.264 writers' repair deadline from now on (dds::SetRepairDeadline; 0: none). From the
  // thread that calls PublishStereoVideo. False with `error` (also without H.264).
  bool SetVideoRepairDeadline(std::chrono::milliseconds deadline, std::string* error);
  // Intrinsics of one eye (transient local: late joiners get them at once).
  void PublishCameraInfo(Eye eye, const CameraIntrinsicsInfo& info) override;
  // One eye, unconditionally (replay).
  void PublishImage(Eye eye, const CompressedImage& image) override;
  // Scans, odometry, health and lease never block the caller (the control loop): they go into
  // an outbox that a publisher thread writes to DDS in order. A DDS write can block for as long
  // as a TCP link is down (the writer's mutex is held by a send into a full socket); the outbox
  // then keeps the newest kOutboxCapacity samples and counts the older ones it drops.
  void PublishScan(const LaserScan& scan) override;
  void PublishOdometry(const Odometry& odometry) override;
  // The ring on rt/mostar/sonar, then one Range per sensor on rt/mostar/sonar/range.
  void PublishSonar(const SonarRanges& ranges) override;
  void PublishBumpers(const BumperState& state) override;
  void PublishHealth(const RobotHealth& health) override;
  void PublishLease(const ControlLease& lease) override;
  static constexpr size_t kOutboxCapacity = 256;
  uint64_t outbox_dropped() const { return outbox_dropped_.load(); }
  // Waits until the outbox is empty (tests, orderly shutdown); false on timeout.
  bool FlushOutbox(Duration timeout);

  ~RobotNode() override;

  // Robot clock minus the client's clock, once enough ping exchanges completed.
  std::optional<Duration> RobotMinusClient(const std::string& client_id) const override;

  // Remote endpoints currently matched (for health: how many viewers and pilots).
  int frame_subscribers() const {
    return std::max(lanes_.front().left->matched(), stereo_video_ ? stereo_video_->matched() : 0);
  }
  // Keyframe requests heard (all viewers), H.264 frames written.
  uint64_t keyframe_requests() const { return keyframe_requests_.load(); }
  uint64_t video_frames_sent() const { return video_frames_sent_.load(); }
  // Pairs written and pairs skipped because no lane was free.
  uint64_t pairs_sent() const { return pairs_sent_.load(); }
  uint64_t pairs_skipped() const { return pairs_skipped_.load(); }
  // How long the DDS write in progress (outbox or video) has been blocked at `now`; zero when
  // no write is in progress. A write blocks while a TCP peer does not read (bounded by the TCP
  // user timeout) and for ever in a Fast DDS deadlock: the caller decides when to give up.
  Duration BlockedWriteDuration(SteadyTime now) const override;
  // Video ack-clock, outbox, TCP guard, sender identity and DDS Security state (dds_security_off
  // with --insecure) as the health device "network".
  DeviceHealth NetworkHealth() const override;
  // Pairs written on a lane that a reader had left unacknowledged for lane_timeout.
  uint64_t lanes_reclaimed() const { return lanes_reclaimed_.load(); }
  // Command writers matched over every pilot's partition.
  int command_writers() const;
  // True with DDS Security: senders are verified against their certificates.
  bool identities_verified() const { return sender_check_->identities_verified(); }
  // Samples dropped by the sender check so far.
  uint64_t sender_drops() const { return sender_check_->dropped(); }

 private:
  RobotNode() = default;

  using CommandReader = dds::Reader<mostar_msgs::msg::dds_::VelocityCommand_PubSubType>;
  using EstopReader = dds::Reader<mostar_msgs::msg::dds_::EmergencyStop_PubSubType>;
  using RequestReader = dds::Reader<mostar_msgs::msg::dds_::ControlRequest_PubSubType>;
  using PingReader = dds::Reader<mostar_msgs::msg::dds_::ClockProbe_PubSubType>;
  // The readers of one client of the role table, in its partition.
  struct SenderReaders {
    std::string client_id;
    std::unique_ptr<CommandReader> command;  // pilots only
    std::unique_ptr<EstopReader> estop;
    std::unique_ptr<RequestReader> request;  // pilots only
    std::unique_ptr<PingReader> ping;
  };
  // Creates the readers of `sender` on `participant`; false with `error`.
  bool AddSender(dds::Participant& participant, const RobotSender& sender, std::string* error);

  // A writer matched a reader of `client`'s partition: logs the first proof per participant.
  void OnSenderMatched(SenderChannel channel, const std::string& client,
                       const dds::WriterId& writer);
  // A ping of role-table client `client` (its partition).
  void OnPing(const ClockProbe& ping, const std::string& client);
  // A ping from the reader over every partition: answered for clients outside the role table.
  void OnUnlistedPing(const ClockProbe& ping, const dds::WriterId& from);
  // SenderCheck of a sample that arrived in `client`'s partition from `from`; logs drops. True
  // when the sample may be handed on.
  bool Admit(SenderChannel channel, const std::string& sender_id, const std::string& client,
             const dds::WriterId& from);
  void Post(std::function<void()> write);
  void PublisherLoop();

  const Clock* clock_ = nullptr;
  const dds::Participant* participant_ = nullptr;
  Callbacks callbacks_;
  std::unique_ptr<SenderCheck> sender_check_;
  std::unique_ptr<ClockResponder> clock_responder_;           // role-table clients
  std::unique_ptr<ClockResponder> unlisted_clock_responder_;  // everyone else (pongs only)
  std::set<std::string> listed_;                              // role-table client ids
  SenderProofLog proofs_;
  CommandWriterTracker command_writers_;
  std::mutex lease_mutex_;
  std::string lease_holder_;  // holder of the lease last published
  using ImageWriter = dds::Writer<sensor_msgs::msg::dds_::CompressedImage_PubSubType>;
  struct VideoLane {
    std::unique_ptr<ImageWriter> left;
    std::unique_ptr<ImageWriter> right;
    std::optional<SteadyTime> written;  // when the lane's pair was written (none yet: free)
  };
  Duration lane_timeout_{};
  std::vector<VideoLane> lanes_;  // >= 1; lane 0 also carries single images (replay)
  std::atomic<uint64_t> pairs_sent_{0};
  std::atomic<uint64_t> pairs_skipped_{0};
  std::atomic<uint64_t> lanes_reclaimed_{0};
  // Steady-clock start (ns) of the outbox / video write in progress; 0 when none.
  std::atomic<int64_t> outbox_write_since_ns_{0};
  std::atomic<int64_t> video_write_since_ns_{0};
  std::mutex outbox_mutex_;
  std::condition_variable outbox_cv_;
  std::deque<std::function<void()>> outbox_;  // DDS writes waiting for the publisher thread
  bool writing_ = false;                      // the publisher thread is inside a write
  bool stop_ = false;
  std::atomic<uint64_t> outbox_dropped_{0};
  std::thread publisher_;  // started last in Create, joined first in the destructor
  std::unique_ptr<dds::Writer<sensor_msgs::msg::dds_::CameraInfo_PubSubType>> left_info_;
  std::unique_ptr<dds::Writer<sensor_msgs::msg::dds_::CameraInfo_PubSubType>> right_info_;
  std::unique_ptr<dds::Writer<sensor_msgs::msg::dds_::LaserScan_PubSubType>> scan_;
  std::unique_ptr<dds::Writer<nav_msgs::msg::dds_::Odometry_PubSubType>> odom_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::FrameTiming_PubSubType>> timing_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::RobotHealth_PubSubType>> health_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::SonarRing_PubSubType>> sonar_;
  std::unique_ptr<dds::Writer<sensor_msgs::msg::dds_::Range_PubSubType>> sonar_range_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::BumperState_PubSubType>> bumpers_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::ControlLease_PubSubType>> lease_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::ClockProbe_PubSubType>> pong_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::StereoVideoFrame_PubSubType>> stereo_video_;
  std::unique_ptr<dds::Writer<foxglove_msgs::msg::dds_::CompressedVideo_PubSubType>> left_video_;
  std::unique_ptr<dds::Writer<foxglove_msgs::msg::dds_::CompressedVideo_PubSubType>> right_video_;
  using KeyframeReader = dds::Reader<mostar_msgs::msg::dds_::KeyframeRequest_PubSubType>;
  std::unique_ptr<KeyframeReader> keyframe_requests_reader_;  // null: permissions refused it
  using FeedbackReader = dds::Reader<mostar_msgs::msg::dds_::VideoFeedback_PubSubType>;
  std::unique_ptr<FeedbackReader> feedback_reader_;  // null: permissions refused it
  std::atomic<uint64_t> keyframe_requests_{0};
  std::atomic<uint64_t> video_frames_sent_{0};
  std::atomic<int> h264_readers_{0};  // matched readers of the stereo H.264 stream
  std::vector<std::unique_ptr<SenderReaders>> senders_;
  std::unique_ptr<PingReader> unlisted_ping_;  // every client partition
};

}  // namespace mostar::server
