// mostar_relay: forwards the robot's streams to many observers, so the robot's uplink carries
// each stream once however many people watch.
//
// Two DDS participants: one on the robot side (domain --robot-domain, XML participant profile
// --robot-profile-name, default "relay") subscribes to camera left/right, scan, odometry,
// health, control lease and the H.264 stream; one on the observer side (domain --observer-domain,
// profile
// --observer-profile-name, default "relay_observers") re-publishes every sample unchanged, with
// the same QoS (common/dds/qos.h). Towards the robot only three things go: observers'
// emergency-stop engagements, under the relay's own id and thinned (estop_forwarding.h), so
// anyone watching can stop the robot; their H.264 keyframe requests; and the relay's own
// receive reports of the H.264 stream (arrival_report.h), so that the robot's rate control
// follows its uplink to the relay, which carries the video once for every viewer behind it
// (pilots with operator_client --video-via-relay included), and the lease holder's reports
// (the pilot's path through the hub); other viewers' reports stay here.
// Commands, control requests, clock pings and e-stop releases are never forwarded: observers behind
// the relay cannot drive the robot or release a stop, and with DDS Security the relay's permissions
// (deploy/security/make_pki.sh --relay) allow it no other writer on the robot side.
//
// The two sides must not share a DDS network: give them different domain ids (the default
// observer domain is the robot domain + 1), or the relay would hear its own output.
// Fast DDS refuses two XML files that define the same profile names in one process, so both
// sides use one profiles file (--dds-profile; deploy/dds/{lan,wan}.xml define both profiles),
// or "loopback".
//
// Threading: samples are forwarded on the DDS receive threads of the readers (the e-stop
// forwarding under its own mutex); the main thread only prints statistics every
// --stats-period-s and waits for a signal or --duration-s.
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <functional>
#include <iostream>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/config/config_report.h"
#include "common/dds/conversions.h"
#include "common/dds/endpoint.h"
#include "common/dds/network_check.h"
#include "common/dds/participant.h"
#include "common/dds/profile_check.h"
#include "common/dds/topics.h"
#include "common/identity/client_id.h"
#include "common/identity/sender_partition.h"
#include "common/log/log.h"
#include "common/process/restart_in_place.h"
#include "common/process/stop_signals.h"
#include "common/time/time.h"
#include "mostar_msgsPubSubTypes.h"
#include "operator_client/relay/estop_forwarding.h"
#include "operator_client/video/arrival_report.h"
#include "ros2_msgsPubSubTypes.h"

namespace mostar::relay {
namespace {

// One forwarded topic: a reader on the robot side feeding a writer on the observer side.
class ForwarderBase {
 public:
  virtual ~ForwarderBase() = default;
  virtual bool ok(std::string* error) const = 0;
  virtual std::string Stats() const = 0;
};

template <class PubSubType>
class Forwarder final : public ForwarderBase {
 public:
  Forwarder(dds::Participant& robot_side, dds::Participant& observer_side, const char* topic,
            dds::Stream stream)
      : Forwarder(robot_side, observer_side, topic, dds::WriterQos(stream),
                  dds::ReaderQos(stream)) {}
  // From `from` to `to` with the given QoS (the H.264 stream's depth; keyframe requests go the
  // other way, observers to robot).
  // `on_sample`, if set, sees each sample first (on the DDS receive thread).
  Forwarder(dds::Participant& from, dds::Participant& to, const char* topic,
            const eprosima::fastdds::dds::DataWriterQos& writer_qos,
            const eprosima::fastdds::dds::DataReaderQos& reader_qos,
            std::function<void(const typename PubSubType::type&)> on_sample = nullptr)
      : topic_(topic),
        on_sample_(std::move(on_sample)),
        writer_(to, topic, writer_qos),
        reader_(from, topic, reader_qos, dds::kWithWriter,
                [this](const typename PubSubType::type& sample, const dds::WriterId&) {
                  if (on_sample_) on_sample_(sample);
                  if (!writer_.Write(sample)) ++dropped_;
                }) {}

  bool ok(std::string* error) const override {
    if (!writer_.ok()) *error = writer_.error();
    if (!reader_.ok()) *error = reader_.error();
    return writer_.ok() && reader_.ok();
  }
  std::string Stats() const override {
    return std::string(topic_) + ": in=" + std::to_string(reader_.received()) +
           " out=" + std::to_string(writer_.written()) +
           " refused=" + std::to_string(dropped_.load()) +
           " observers=" + std::to_string(writer_.matched());
  }

 private:
  const char* topic_;
  const std::function<void(const typename PubSubType::type&)> on_sample_;
  std::atomic<uint64_t> dropped_{0};
  dds::Writer<PubSubType> writer_;  // constructed before the reader that feeds it
  dds::Reader<PubSubType> reader_;
};

// Observers' e-stops (observer side) to the robot (robot side), engagements only.
class EstopForwarder final : public ForwarderBase {
 public:
  EstopForwarder(dds::Participant& robot_side, dds::Participant& observer_side,
                 const std::string& relay_id)
      : forwarding_(relay_id, std::chrono::milliseconds(50)),
        // To the robot in the relay's own partition (its permissions allow no other); from
        // every observer's partition.
        writer_(robot_side, dds::topics::kEmergencyStop,
                dds::InPartition(dds::WriterQos(dds::Stream::kControl),
                                 identity::SenderPartition(relay_id))),
        reader_(
            observer_side, dds::topics::kEmergencyStop,
            dds::InPartition(dds::ReaderQos(dds::Stream::kControl), identity::kAnySenderPartition),
            dds::kWithWriter, [this](const dds::wire::EmergencyStop& sample, const dds::WriterId&) {
              const EmergencyStop received = dds::FromIdl(sample);
              std::lock_guard<std::mutex> lock(mutex_);
              const std::optional<EmergencyStop> out =
                  forwarding_.OnObserverEstop(received, clock_.Now(), clock_.SteadyNow());
              if (!out) return;
              MOSTAR_LOG(WARNING) << "emergency stop from observer "
                                  << received.sender_id.substr(0, 64) << " forwarded to the robot";
              if (!writer_.Write(dds::ToIdl(*out))) ++write_failures_;
            }) {}

  bool ok(std::string* error) const override {
    if (!writer_.ok()) *error = writer_.error();
    if (!reader_.ok()) *error = reader_.error();
    return writer_.ok() && reader_.ok();
  }
  std::string Stats() const override {
    std::lock_guard<std::mutex> lock(mutex_);
    const EstopForwardingStats& s = forwarding_.stats();
    return std::string(dds::topics::kEmergencyStop) +
           " (to the robot): in=" + std::to_string(s.received) +
           " out=" + std::to_string(s.forwarded) +
           " releases_refused=" + std::to_string(s.releases_refused) +
           " thinned=" + std::to_string(s.rate_limited) +
           " refused=" + std::to_string(write_failures_) +
           " robots=" + std::to_string(writer_.matched());
  }

 private:
  SystemClock clock_;
  mutable std::mutex mutex_;
  EstopForwarding forwarding_;
  uint64_t write_failures_ = 0;
  dds::Writer<mostar_msgs::msg::dds_::EmergencyStop_PubSubType> writer_;
  dds::Reader<mostar_msgs::msg::dds_::EmergencyStop_PubSubType> reader_;
};

int Main(int argc, char** argv) {
  CLI::App app(
      "mostar_relay: forwards the robot's sensor streams to many observers, and their e-stops "
      "to the robot");
  std::string profile = "loopback";
  dds::ParticipantOptions robot_options, observer_options;
  robot_options.name = "relay";
  robot_options.xml_participant_profile = "relay";
  observer_options.name = "relay";
  observer_options.xml_participant_profile = "relay_observers";
  // A service on the hub: wait for its overlay address rather than run undiscoverable.
  robot_options.wait_for_interfaces = std::chrono::seconds(45);
  observer_options.wait_for_interfaces = std::chrono::seconds(45);
  int observer_domain = -1;
  double duration_s = 0;
  double stats_period_s = 5;
  std::string log_level = "info";
  std::string relay_id = "relay";
  app.add_option("--id", relay_id,
                 "client id of the relay's forwarded e-stops (with DDS Security: its certificate "
                 "name, which is used whatever this says)");
  app.add_option("--dds-profile", profile, "'loopback' or a Fast DDS XML profiles file");
  app.add_option("--robot-domain", robot_options.domain_id, "DDS domain of the robot")
      ->check(CLI::Range(0, 232));
  app.add_option("--observer-domain", observer_domain,
                 "DDS domain of the observers (default: robot domain + 1)")
      ->check(CLI::Range(0, 232));
  app.add_option("--robot-profile-name", robot_options.xml_participant_profile,
                 "participant profile for the robot side");
  app.add_option("--observer-profile-name", observer_options.xml_participant_profile,
                 "participant profile for the observer side");
  app.add_option("--duration", duration_s, "stop after this many seconds (0 = until signal)")
      ->check(CLI::Range(0.0, 1e7));
  app.add_option("--stats-period-s", stats_period_s, "print forwarding statistics this often")
      ->check(CLI::Range(0.1, 3600.0));
  int video_repair_period_ms = static_cast<int>(dds::kDefaultVideoRepairPeriod.count());
  app.add_option("--video-repair-period-ms", video_repair_period_ms,
                 "heartbeat period of the forwarded H.264 stream towards viewers: about their "
                 "round trip (the Internet recipe: 250), as the robot's dds.video_repair_period_ms")
      ->check(CLI::Range(10, 2000));
  int video_repair_deadline_ms = 0;
  app.add_option("--video-repair-deadline-ms", video_repair_deadline_ms,
                 "the forwarded H.264 stream: an AU is repaired for at most this long after the "
                 "relay wrote it, then viewers skip it and ask for an IDR (0: until 30 newer AUs "
                 "push it out), as the robot's dds.video_repair_deadline_ms")
      ->check(CLI::Range(0, 10000));
  bool insecure = false;
  app.add_flag("--insecure", insecure,
               "allow a network DDS profile without DDS Security (docs/security.md)");
  app.add_option("--log-level", log_level, "debug | info | warning | error")
      ->check(CLI::IsMember({"debug", "info", "warning", "error"}));
  bool check_config = false;
  app.add_flag("--check-config", check_config,
               "check the DDS profile of both sides (participant profiles, certificates, "
               "addresses), print each problem with its fix, and exit: 0 when all is well");
  CLI11_PARSE(app, argc, argv);
  LogLevel level = LogLevel::kINFO;
  ParseLogLevel(log_level, &level);
  SetLogLevel(level);

  robot_options.profile = profile;
  observer_options.profile = profile;
  robot_options.insecure = insecure;
  observer_options.insecure = insecure;
  observer_options.domain_id = observer_domain >= 0 ? observer_domain : robot_options.domain_id + 1;
  if (observer_options.domain_id > 232) {
    std::cerr << "mostar_relay: --observer-domain is required when the robot domain is 232\n";
    return 2;
  }
  if (observer_options.domain_id == robot_options.domain_id) {
    std::cerr << "mostar_relay: robot and observer domains must differ (the relay would hear "
                 "its own output)\n";
    return 2;
  }
  if (check_config) {
    ConfigReport report;
    dds::CheckDdsProfile(robot_options, "mostar", &report);
    if (profile != "loopback") dds::CheckDdsProfile(observer_options, "mostar", &report);
    return report.Print("mostar_relay", std::cout);
  }
  std::string error;
  auto robot_side = dds::Participant::Create(robot_options, &error);
  if (!robot_side) {
    std::cerr << "mostar_relay: robot side: " << error << "\n";
    return 2;
  }
  auto observer_side = dds::Participant::Create(observer_options, &error);
  if (!observer_side) {
    std::cerr << "mostar_relay: observer side: " << error << "\n";
    return 2;
  }

  namespace topics = dds::topics;
  using dds::Stream;
  std::vector<std::unique_ptr<ForwarderBase>> forwarders;
  using Image = sensor_msgs::msg::dds_::CompressedImage_PubSubType;
  forwarders.push_back(std::make_unique<Forwarder<Image>>(*robot_side, *observer_side,
                                                          topics::kCameraLeft, Stream::kVideo));
  forwarders.push_back(std::make_unique<Forwarder<Image>>(*robot_side, *observer_side,
                                                          topics::kCameraRight, Stream::kVideo));
  forwarders.push_back(std::make_unique<Forwarder<sensor_msgs::msg::dds_::LaserScan_PubSubType>>(
      *robot_side, *observer_side, topics::kScan, Stream::kSensor));
  forwarders.push_back(std::make_unique<Forwarder<nav_msgs::msg::dds_::Odometry_PubSubType>>(
      *robot_side, *observer_side, topics::kOdometry, Stream::kSensor));
  forwarders.push_back(std::make_unique<Forwarder<mostar_msgs::msg::dds_::RobotHealth_PubSubType>>(
      *robot_side, *observer_side, topics::kHealth, Stream::kState));
  // The lease holder's id: its receive reports are passed to the robot (below).
  std::mutex holder_mutex;
  std::string holder_id;
  forwarders.push_back(std::make_unique<Forwarder<mostar_msgs::msg::dds_::ControlLease_PubSubType>>(
      *robot_side, *observer_side, topics::kControlLease, dds::WriterQos(Stream::kState),
      dds::ReaderQos(Stream::kState),
      [&holder_mutex, &holder_id](const dds::wire::ControlLease& l) {
        std::lock_guard<std::mutex> lock(holder_mutex);
        holder_id = l.holder_id();
      }));
  forwarders.push_back(std::make_unique<Forwarder<mostar_msgs::msg::dds_::FrameTiming_PubSubType>>(
      *robot_side, *observer_side, topics::kCameraTiming, Stream::kSensor));
  forwarders.push_back(std::make_unique<Forwarder<mostar_msgs::msg::dds_::SonarRing_PubSubType>>(
      *robot_side, *observer_side, topics::kSonar, Stream::kSensor));
  forwarders.push_back(std::make_unique<Forwarder<sensor_msgs::msg::dds_::Range_PubSubType>>(
      *robot_side, *observer_side, topics::kSonarRange, Stream::kSensor));
  forwarders.push_back(std::make_unique<Forwarder<mostar_msgs::msg::dds_::BumperState_PubSubType>>(
      *robot_side, *observer_side, topics::kBumpers, Stream::kState));
  // The H.264 stream goes through unchanged: its AU numbers stay the robot's, so an observer
  // sees every frame lost upstream of it as a gap and asks for an IDR. The relay records each
  // frame's arrival for its own receive reports to the robot.
  std::mutex arrivals_mutex;
  client::ArrivalReport arrivals;
  forwarders.push_back(
      std::make_unique<Forwarder<mostar_msgs::msg::dds_::StereoVideoFrame_PubSubType>>(
          *robot_side, *observer_side, topics::kCameraStereoVideo,
          dds::VideoStreamWriterQos(std::chrono::milliseconds(video_repair_period_ms),
                                    dds::kVideoStreamDepth,
                                    std::chrono::milliseconds(video_repair_deadline_ms)),
          dds::VideoStreamReaderQos(dds::kVideoStreamDepth),
          [&arrivals_mutex, &arrivals](const dds::wire::StereoVideoFrame& frame) {
            const SteadyTime now = SystemClock::Instance().SteadyNow();
            std::lock_guard<std::mutex> lock(arrivals_mutex);
            arrivals.Add(frame.sequence_number(), now, frame.left().size() + frame.right().size());
          }));
  // Observers' keyframe requests go to the robot (which acts on one per 300 ms). Permissions
  // signed before the topic existed refuse it: the relay then runs without.
  auto keyframes = std::make_unique<Forwarder<mostar_msgs::msg::dds_::KeyframeRequest_PubSubType>>(
      *observer_side, *robot_side, topics::kKeyframeRequest, dds::WriterQos(Stream::kControl),
      dds::ReaderQos(Stream::kControl));
  if (std::string why; !keyframes->ok(&why)) {
    MOSTAR_LOG(WARNING) << why << ": observers' keyframe requests are not forwarded; re-sign the "
                        << "permissions (make_pki.sh --update-permissions)";
  } else {
    forwarders.push_back(std::move(keyframes));
  }
  if (!robot_side->own_client_id().empty()) relay_id = robot_side->own_client_id();
  if (std::string why; !identity::IsValidClientId(relay_id, &why)) {
    std::cerr << "mostar_relay: --id '" << relay_id << "' is not a valid client id: " << why
              << "\n";
    return 2;
  }
  forwarders.push_back(std::make_unique<EstopForwarder>(*robot_side, *observer_side, relay_id));
  // The relay's receive reports (robot side, default partition); permissions signed before
  // the topic existed refuse the writer: the robot's rate control then cannot hear the relay.
  auto feedback = std::make_unique<dds::Writer<mostar_msgs::msg::dds_::VideoFeedback_PubSubType>>(
      *robot_side, topics::kVideoFeedback, dds::WriterQos(Stream::kControl));
  if (!feedback->ok()) {
    MOSTAR_LOG(WARNING) << feedback->error()
                        << ": the robot's video rate control cannot hear the relay; re-sign the "
                           "permissions (make_pki.sh --update-permissions)";
    feedback.reset();
  }
  std::atomic<uint64_t> reports_sent{0}, pilot_reports{0};
  // The pilot's own receive reports (the lease holder's id; other viewers' stay here): the
  // robot's rate control then also follows the hub-to-pilot path, the one the pilot drives by.
  // The id is a claim, as on any report (docs/security.md, "Video requests and receive
  // reports").
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::VideoFeedback_PubSubType>> viewer_reports;
  if (feedback) {
    viewer_reports =
        std::make_unique<dds::Reader<mostar_msgs::msg::dds_::VideoFeedback_PubSubType>>(
            *observer_side, topics::kVideoFeedback, dds::ReaderQos(Stream::kControl),
            dds::kWithWriter, [&](const dds::wire::VideoFeedback& report, const dds::WriterId&) {
              {
                std::lock_guard<std::mutex> lock(holder_mutex);
                if (holder_id.empty() || report.sender_id() != holder_id) return;
              }
              if (feedback->Write(report)) ++pilot_reports;
            });
    if (!viewer_reports->ok()) {
      MOSTAR_LOG(WARNING) << viewer_reports->error()
                          << ": the pilot's receive reports are not passed to the robot";
      viewer_reports.reset();
    }
  }
  for (const auto& f : forwarders) {
    if (!f->ok(&error)) {
      std::cerr << "mostar_relay: " << error << "\n";
      return 2;
    }
  }
  MOSTAR_LOG(INFO) << "mostar_relay: robot domain " << robot_options.domain_id
                   << " -> observer domain " << observer_options.domain_id << " (" << profile
                   << "); observers' e-stops go to the robot as '" << relay_id << "'";

  InstallStopSignals();
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  Clock::time_point next_stats = start + std::chrono::duration_cast<Clock::duration>(
                                             std::chrono::duration<double>(stats_period_s));
  dds::NetworkCheck network_check({robot_side.get(), observer_side.get()});
  while (!StopRequested()) {
    const Clock::time_point now = Clock::now();
    if (duration_s > 0 && now - start >= std::chrono::duration<double>(duration_s)) break;
    std::vector<VideoFrameArrival> due;
    {
      std::lock_guard<std::mutex> lock(arrivals_mutex);
      due = arrivals.TakeDue(SystemClock::Instance().SteadyNow());
    }
    if (feedback && !due.empty() &&
        feedback->Write(
            dds::ToIdl(VideoFeedback{SystemClock::Instance().Now(), relay_id, std::move(due)}))) {
      ++reports_sent;
    }
    // The overlay's address gone and back is logged; a new address means restarting in place.
    if (network_check.RestartNeeded(now)) {
      MOSTAR_LOG(WARNING) << "mostar_relay: restarting in place to be reachable on this host's "
                             "new address";
      RequestRestart();
      break;
    }
    if (now >= next_stats) {
      for (const auto& f : forwarders) MOSTAR_LOG(INFO) << "relay " << f->Stats();
      MOSTAR_LOG(INFO) << "relay " << topics::kVideoFeedback
                       << " (to the robot): reports=" << reports_sent
                       << " pilot_reports=" << pilot_reports;
      next_stats += std::chrono::duration_cast<Clock::duration>(
          std::chrono::duration<double>(stats_period_s));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  // Final statistics on stdout, one line per topic, for scripts.
  for (const auto& f : forwarders) std::cout << "relay " << f->Stats() << "\n";
  viewer_reports.reset();  // before the writer it uses
  std::cout << "relay " << topics::kVideoFeedback << " (to the robot): reports=" << reports_sent
            << " pilot_reports=" << pilot_reports << "\n";
  forwarders.clear();  // stop callbacks before the participants go
  return 0;
}

}  // namespace
}  // namespace mostar::relay

int main(int argc, char** argv) {
  mostar::RememberCommandLine(argc, argv);
  const int status = mostar::relay::Main(argc, argv);
  return mostar::dds::EndProcess(mostar::RestartIfRequested(status, "mostar_relay"));
}
