// net_probe: a measuring DDS observer for network tests and the network bench.
//
// Subscribes to the robot's streams with the same QoS as operator_client (common/dds), and for
// every sample records the receive time next to the sample's stamp; it also sends clock pings
// (1 per 200 ms) that robot_server answers, which measure the operator -> robot one-way latency
// (t1 - t0) of the reliable control path that commands share. Both clocks are this machine's
// when probe and robot run on one computer (network namespaces), so ages are exact.
//
// Output: one summary line on stdout,
//   probe: left=N right=N scan=N odom=N health=N lease=N left_age_p50_ms=.. left_age_p95_ms=..
//          scan_age_p50_ms=.. scan_age_p95_ms=.. ping_oneway_p50_ms=.. ping_rtt_p50_ms=..
//          pongs=N command_writer=ok|refused|none measured_s=.. estops_sent=N
//          estop_seen_after_s=S|no releases_sent=N robot_estop=engaged|clear
//          scan_beams=MIN..MAX (beams per scan received; -1 before the first)
//          video_frames=N video_gaps=N (the H.264 stream: its frames count as left and right)
// and with --samples FILE one line per sample: topic,receive_ns,stamp_ns (clock ping replies as
// topic pong, stamped with the ping's send time).
//
// --try-command-writer asks DDS for a cmd_vel writer (without publishing), to check that DDS
// Security permissions refuse it for observers. --estop-at S engages the e-stop S seconds after
// start, as an observer's console does (repeated until the robot's health reports it), then
// sends releases from 1 s later, which the robot must refuse from an observer. Exit code 0
// unless setup failed.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/dds/conversions.h"
#include "common/dds/endpoint.h"
#include "common/dds/participant.h"
#include "common/dds/topics.h"
#include "common/identity/client_id.h"
#include "common/identity/sender_partition.h"
#include "common/process/stop_signals.h"
#include "common/stats/percentile.h"
#include "common/time/time.h"
#include "mostar_msgsPubSubTypes.h"
#include "ros2_msgsPubSubTypes.h"

namespace mostar::network {
namespace {

// Counts and ages per topic. With a warm-up, samples received in the first `warmup` after the
// first sample of any topic (discovery, start-up bursts) are written to the samples file but
// left out of counts and percentiles: they measure the steady state.
class Recorder {
 public:
  explicit Recorder(double warmup_s) : warmup_ns_(static_cast<int64_t>(warmup_s * 1e9)) {}
  void Add(const std::string& topic, Time stamp) {
    const int64_t now_ns = ToUnixNanos(clock_.Now());
    std::lock_guard<std::mutex> lock(mutex_);
    if (first_ns_ == 0) first_ns_ = now_ns;
    if (samples_.is_open()) samples_ << topic << ',' << now_ns << ',' << ToUnixNanos(stamp) << '\n';
    if (now_ns - first_ns_ < warmup_ns_) return;
    ++counts_[topic];
    ages_ms_[topic].push_back(static_cast<double>(now_ns - ToUnixNanos(stamp)) * 1e-6);
  }
  void AddValue(const std::string& name, double value_ms) {
    const int64_t now_ns = ToUnixNanos(clock_.Now());
    std::lock_guard<std::mutex> lock(mutex_);
    if (first_ns_ == 0 || now_ns - first_ns_ < warmup_ns_) return;
    ages_ms_[name].push_back(value_ms);
    ++counts_[name];
  }
  bool OpenSamples(const std::string& path) {
    if (path.empty()) return true;
    samples_.open(path, std::ios::trunc);
    return samples_.good();
  }
  int Count(const std::string& topic) {
    std::lock_guard<std::mutex> lock(mutex_);
    return counts_[topic];
  }
  // Percentile `q` in [0, 1] of the values recorded under `topic`; -1 when none.
  double Percentile(const std::string& topic, double q) {
    std::lock_guard<std::mutex> lock(mutex_);
    return mostar::Percentile(ages_ms_[topic], q).value_or(-1);
  }

  // Seconds of steady state measured so far (after the warm-up); 0 before it ends.
  double MeasuredSeconds() {
    const int64_t now_ns = ToUnixNanos(clock_.Now());
    std::lock_guard<std::mutex> lock(mutex_);
    if (first_ns_ == 0) return 0;
    return std::max<double>(0.0, static_cast<double>(now_ns - first_ns_ - warmup_ns_) * 1e-9);
  }

 private:
  const int64_t warmup_ns_;
  int64_t first_ns_ = 0;  // receive time of the first sample, ns since the epoch
  SystemClock clock_;
  std::mutex mutex_;
  std::map<std::string, int> counts_;
  std::map<std::string, std::vector<double>> ages_ms_;
  std::ofstream samples_;
};

int Main(int argc, char** argv) {
  CLI::App app("net_probe: measure delivery and age of mostar streams");
  dds::ParticipantOptions options;
  options.name = "operator";
  double duration_s = 10;
  std::string id = "net_probe";
  std::string samples_path;
  bool try_command_writer = false;
  bool ping = true;
  double warmup_s = 0;
  app.add_option("--domain", options.domain_id, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--dds-profile", options.profile, "'loopback' or a Fast DDS XML profiles file");
  app.add_option("--profile-name", options.name, "participant profile in the XML file");
  app.add_flag("--insecure", options.insecure,
               "allow a network DDS profile without DDS Security (as the programs do)");
  app.add_option("--id", id, "sender id of the clock pings");
  app.add_option("--duration-s", duration_s, "measure for this long")
      ->check(CLI::Range(0.5, 3600.0));
  app.add_option("--samples", samples_path, "write topic,receive_ns,stamp_ns per sample");
  app.add_flag("--try-command-writer", try_command_writer, "ask DDS for a cmd_vel writer");
  double estop_at_s = -1;
  app.add_option("--estop-at", estop_at_s,
                 "engage the e-stop this many seconds after start, then try to release it 1 s "
                 "later (an observer's e-stop; the release must be refused)")
      ->check(CLI::Range(0.0, 3600.0));
  app.add_flag("!--no-ping", ping, "do not send clock pings");
  app.add_option("--warmup-s", warmup_s,
                 "leave the first seconds after the first sample out of the statistics")
      ->check(CLI::Range(0.0, 3600.0));
  CLI11_PARSE(app, argc, argv);

  Recorder recorder(warmup_s);
  if (!recorder.OpenSamples(samples_path)) {
    std::cerr << "net_probe: cannot write " << samples_path << "\n";
    return 2;
  }
  std::string error;
  std::unique_ptr<dds::Participant> participant = dds::Participant::Create(options, &error);
  if (!participant) {
    std::cerr << "net_probe: " << error << "\n";
    return 2;
  }
  namespace topics = dds::topics;
  using dds::Stream;
  auto& p = *participant;
  // Pings and e-stops go out in this client's partition: its certificate's CN, or --id.
  const std::string own_id =
      participant->own_client_id().empty() ? id : participant->own_client_id();
  if (!identity::IsValidClientId(own_id)) {
    std::cerr << "net_probe: --id '" << own_id << "' is not a valid client id\n";
    return 2;
  }
  const std::string partition = identity::SenderPartition(own_id);
  std::atomic<bool> robot_estop{false};                     // as the robot's last health said
  std::atomic<int> scan_beams_min{-1}, scan_beams_max{-1};  // beams per scan (one DDS thread)
  dds::Reader<sensor_msgs::msg::dds_::CompressedImage_PubSubType> left(
      p, topics::kCameraLeft, Stream::kVideo, [&](const dds::wire::CompressedImage& m) {
        recorder.Add("left", dds::FromIdl(m.header().stamp()));
      });
  dds::Reader<sensor_msgs::msg::dds_::CompressedImage_PubSubType> right(
      p, topics::kCameraRight, Stream::kVideo, [&](const dds::wire::CompressedImage& m) {
        recorder.Add("right", dds::FromIdl(m.header().stamp()));
      });
  // The H.264 stream (a robot whose camera codec is H264): each frame is a pair, recorded as
  // "left" and "right" like the JPEG eyes; AU numbers that jump are gaps.
  std::atomic<uint64_t> video_frames{0}, video_gaps{0}, last_video_sequence{0};
  dds::Reader<mostar_msgs::msg::dds_::StereoVideoFrame_PubSubType> video(
      p, topics::kCameraStereoVideo, dds::VideoStreamReaderQos(dds::kVideoStreamDepth),
      dds::kWithWriter, [&](const dds::wire::StereoVideoFrame& m, const dds::WriterId&) {
        const Time stamp = dds::FromIdl(m.stamp());
        recorder.Add("left", stamp);
        recorder.Add("right", stamp);
        ++video_frames;
        const uint64_t last = last_video_sequence.exchange(m.sequence_number());
        if (last != 0 && m.sequence_number() != last + 1) ++video_gaps;
      });
  dds::Reader<sensor_msgs::msg::dds_::LaserScan_PubSubType> scan(
      p, topics::kScan, Stream::kSensor, [&](const dds::wire::LaserScan& m) {
        recorder.Add("scan", dds::FromIdl(m.header().stamp()));
        const int beams = static_cast<int>(m.ranges().size());
        if (scan_beams_min.load() < 0 || beams < scan_beams_min.load()) scan_beams_min = beams;
        scan_beams_max = std::max(scan_beams_max.load(), beams);
      });
  dds::Reader<nav_msgs::msg::dds_::Odometry_PubSubType> odom(
      p, topics::kOdometry, Stream::kSensor, [&](const dds::wire::Odometry& m) {
        recorder.Add("odom", dds::FromIdl(m.header().stamp()));
      });
  dds::Reader<mostar_msgs::msg::dds_::RobotHealth_PubSubType> health(
      p, topics::kHealth, Stream::kState, [&](const dds::wire::RobotHealth& m) {
        recorder.Add("health", dds::FromIdl(m.stamp()));
        robot_estop = m.estop_engaged();
      });
  dds::Reader<mostar_msgs::msg::dds_::ControlLease_PubSubType> lease(
      p, topics::kControlLease, Stream::kState,
      [&](const dds::wire::ControlLease& m) { recorder.Add("lease", dds::FromIdl(m.stamp())); });
  SystemClock clock;
  dds::Reader<mostar_msgs::msg::dds_::ClockProbe_PubSubType> pong(
      p, topics::kClockPong, Stream::kControl, [&](const dds::wire::ClockProbe& m) {
        if (m.sender_id() != id) return;
        const ClockProbe probe = dds::FromIdl(m);
        const double oneway_ms =
            static_cast<double>(ToUnixNanos(probe.t1) - ToUnixNanos(probe.t0)) * 1e-6;
        const double rtt_ms =
            static_cast<double>(ToUnixNanos(clock.Now()) - ToUnixNanos(probe.t0)) * 1e-6;
        recorder.AddValue("ping_oneway", oneway_ms);
        recorder.AddValue("ping_rtt", rtt_ms);
        recorder.Add("pong", probe.t0);  // a samples line per reply (its age is the round trip)
      });
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::ClockProbe_PubSubType>> ping_writer;
  if (ping) {
    ping_writer = std::make_unique<dds::Writer<mostar_msgs::msg::dds_::ClockProbe_PubSubType>>(
        p, topics::kClockPing, dds::InPartition(dds::WriterQos(Stream::kControl), partition));
  }
  const std::vector<std::pair<const char*, bool>> endpoints = {
      {"left", left.ok()},   {"right", right.ok()}, {"video", video.ok()},
      {"scan", scan.ok()},   {"odom", odom.ok()},   {"health", health.ok()},
      {"lease", lease.ok()}, {"pong", pong.ok()},   {"ping", !ping_writer || ping_writer->ok()}};
  for (const auto& [name, ok] : endpoints) {
    if (!ok) {
      std::cerr << "net_probe: cannot create the " << name << " endpoint\n";
      return 2;
    }
  }
  std::string command_writer = "none";
  if (try_command_writer) {
    dds::Writer<mostar_msgs::msg::dds_::VelocityCommand_PubSubType> command(
        p, topics::kCommand, dds::InPartition(dds::WriterQos(Stream::kCommand), partition));
    command_writer = command.ok() ? "ok" : "refused";
  }

  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::EmergencyStop_PubSubType>> estop_writer;
  if (estop_at_s >= 0) {
    estop_writer = std::make_unique<dds::Writer<mostar_msgs::msg::dds_::EmergencyStop_PubSubType>>(
        p, topics::kEmergencyStop, dds::InPartition(dds::WriterQos(Stream::kControl), partition));
    if (!estop_writer->ok()) {
      std::cerr << "net_probe: cannot create the e-stop writer\n";
      return 2;
    }
  }
  const auto start = std::chrono::steady_clock::now();
  const auto since_start_s = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  // Like the console: the engagement is repeated until the robot reports it (EstopResender);
  // the release is sent a few times, and must be refused.
  int estops_sent = 0, releases_sent = 0;
  std::string estop_seen = "no";

  InstallStopSignals();
  const auto end = std::chrono::steady_clock::now() +
                   std::chrono::milliseconds(static_cast<int64_t>(duration_s * 1000));
  uint64_t sequence = 0, iteration = 0;
  while (!StopRequested() && std::chrono::steady_clock::now() < end) {
    // Pings every 200 ms; the loop runs every 50 ms while an e-stop may be due.
    if (ping_writer && iteration++ % (estop_writer ? 4 : 1) == 0) {
      ClockProbe probe;
      probe.sender_id = id;
      probe.sequence = ++sequence;
      probe.t0 = clock.Now();
      ping_writer->Write(dds::ToIdl(probe));
    }
    if (estop_writer && since_start_s() >= estop_at_s) {
      EmergencyStop stop;
      stop.stamp = clock.Now();
      stop.sender_id = id;
      if (!robot_estop && estop_seen == "no" && estops_sent < 50) {
        stop.engage = true;
        if (estop_writer->Write(dds::ToIdl(stop))) ++estops_sent;
      } else if (robot_estop && estop_seen == "no") {
        estop_seen = std::to_string(since_start_s() - estop_at_s);
      } else if (since_start_s() >= estop_at_s + 1 && releases_sent < 3) {
        stop.engage = false;
        if (estop_writer->Write(dds::ToIdl(stop))) ++releases_sent;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(estop_writer ? 50 : 200));
  }
  char line[1280];
  std::snprintf(line, sizeof(line),
                "probe: left=%d right=%d scan=%d odom=%d health=%d lease=%d "
                "left_age_p50_ms=%.1f left_age_p95_ms=%.1f scan_age_p50_ms=%.1f "
                "scan_age_p95_ms=%.1f ping_oneway_p50_ms=%.1f ping_rtt_p50_ms=%.1f pongs=%d "
                "command_writer=%s measured_s=%.2f estops_sent=%d estop_seen_after_s=%s "
                "releases_sent=%d robot_estop=%s scan_beams=%d..%d video_frames=%llu "
                "video_gaps=%llu",
                recorder.Count("left"), recorder.Count("right"), recorder.Count("scan"),
                recorder.Count("odom"), recorder.Count("health"), recorder.Count("lease"),
                recorder.Percentile("left", 0.5), recorder.Percentile("left", 0.95),
                recorder.Percentile("scan", 0.5), recorder.Percentile("scan", 0.95),
                recorder.Percentile("ping_oneway", 0.5), recorder.Percentile("ping_rtt", 0.5),
                recorder.Count("ping_rtt"), command_writer.c_str(), recorder.MeasuredSeconds(),
                estops_sent, estop_seen.c_str(), releases_sent, robot_estop ? "engaged" : "clear",
                scan_beams_min.load(), scan_beams_max.load(),
                static_cast<unsigned long long>(video_frames.load()),
                static_cast<unsigned long long>(video_gaps.load()));
  std::cout << line << std::endl;
  return 0;
}

}  // namespace
}  // namespace mostar::network

int main(int argc, char** argv) {
  return mostar::dds::EndProcess(mostar::network::Main(argc, argv));
}
