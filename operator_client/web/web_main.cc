// mostar_web: lets any number of browsers watch the robot's AR view (docs/web_observer.md).
// Wiring only: DDS readers (never a writer: read-only by construction) feed the eye pairer (or,
// for the H.264 stream, the VideoJpegBridge) and the robot state; a compose thread hands the newest
// pair to edge processing (EdgeRunner), turns it into one encoded frame for every browser
// (FrameComposer) with its own edge result when that comes within --edges-wait-s and before the
// next pair, and the robot state into the HUD four times a second; WebServer sends both to the
// browsers, each at the pace it can take.
//
// Threads: DDS receive threads (pairing under a mutex, the newest pair into a latest-value slot,
// robot state); the compose thread; the edge thread; the web server's network thread; the main
// thread waits for a signal or --duration and prints statistics.
#include <CLI/CLI.hpp>
#include <atomic>
#include <cstdio>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "common/config/config_loader.h"
#include "common/config/config_paths.h"
#include "common/dds/conversions.h"
#include "common/dds/domain.h"
#include "common/dds/endpoint.h"
#include "common/dds/participant.h"
#include "common/dds/topics.h"
#include "common/log/log.h"
#include "common/math/calibration_io.h"
#include "common/process/stop_signals.h"
#include "common/sync/latest_value_slot.h"
#include "common/time/rate_meter.h"
#include "mostar_msgsPubSubTypes.h"
#include "operator_client/client_config.pb.h"
#include "operator_client/client_options.h"
#include "operator_client/net/robot_state.h"
#include "operator_client/ui/motion_overlay.h"
#include "operator_client/web/edge_runner.h"
#include "operator_client/web/eye_pairer.h"
#include "operator_client/web/frame_composer.h"
#include "operator_client/web/hud_state.h"
#include "operator_client/web/video_jpeg_bridge.h"
#include "operator_client/web/web_server.h"
#include "ros2_msgsPubSubTypes.h"

namespace mostar::web {
namespace {

namespace topics = dds::topics;
using dds::Stream;

// The robot's streams, read only.
struct Readers {
  std::unique_ptr<dds::Reader<sensor_msgs::msg::dds_::CompressedImage_PubSubType>> left, right;
  std::unique_ptr<dds::Reader<sensor_msgs::msg::dds_::CameraInfo_PubSubType>> left_info;
  std::unique_ptr<dds::Reader<sensor_msgs::msg::dds_::LaserScan_PubSubType>> scan;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::RobotHealth_PubSubType>> health;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::ControlLease_PubSubType>> lease;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::SonarRing_PubSubType>> sonar;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::BumperState_PubSubType>> bumpers;
  std::unique_ptr<dds::Reader<nav_msgs::msg::dds_::Odometry_PubSubType>> odometry;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::StereoVideoFrame_PubSubType>> video;

  bool ok(std::string* error) const {
    auto check = [error](const auto& r) {
      if (!r->ok()) *error = r->error();
      return r->ok();
    };
    return check(left) && check(right) && check(left_info) && check(scan) && check(health) &&
           check(lease) && check(sonar) && check(bumpers) && check(odometry) && check(video);
  }
};

int Main(int argc, char** argv) {
  CLI::App app{"mostar_web: the robot's AR view in any browser (HTTPS + WebSocket), read-only."};
  int domain = -1;
  dds::ParticipantOptions dds_options;
  dds_options.name = "web";
  std::string config_path;
  WebServerOptions web;
  std::string tokens_path;
  double write_timeout_s = 5;
  double request_timeout_s = 10;
  double hud_period_s = 0.25;
  std::string edges = "config";
  double edges_wait_s = 0.1;
  double duration_s = 0;
  double stats_period_s = 10;
  std::string log_level = "info";
  app.add_option("--domain", domain, "DDS domain id (default: MOSTAR_DDS_DOMAIN, then 0)")
      ->check(CLI::Range(0, 232));
  app.add_option("--dds-profile", dds_options.profile,
                 "'loopback' or a Fast DDS XML profiles file");
  app.add_option("--profile-name", dds_options.xml_participant_profile,
                 "participant profile in the XML file (default: operator: mostar_web sits where a "
                 "console would)");
  app.add_flag("--insecure", dds_options.insecure,
               "allow a network DDS profile without DDS Security (docs/security.md)");
  app.add_option("-c,--config", config_path,
                 "client configuration: calibration profile and AR options (protobuf text)")
      ->check(CLI::ExistingFile);
  app.add_option("--listen", web.listen_address, "address to serve on (default 127.0.0.1)");
  app.add_option("--port", web.port, "HTTPS port (0: any free port, printed at start)")
      ->check(CLI::Range(0, 65535));
  app.add_option("--cert", web.cert_file, "PEM certificate (chain) of this server")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--key", web.key_file, "PEM private key of --cert")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--tokens", tokens_path, "observers' tokens, one 'NAME TOKEN' per line")
      ->check(CLI::ExistingFile);
  app.add_option("--client-ca", web.client_ca_file,
                 "PEM CA: browsers must present a client certificate it signed")
      ->check(CLI::ExistingFile);
  app.add_option("--max-browsers", web.max_browsers, "WebSocket connections at most")
      ->check(CLI::Range(1, 1000));
  app.add_option("--write-timeout-s", write_timeout_s,
                 "a browser that takes longer to accept one message is disconnected")
      ->check(CLI::Range(0.1, 600.0));
  app.add_option("--request-timeout-s", request_timeout_s,
                 "bound on a TLS handshake, an HTTP request and a WebSocket handshake")
      ->check(CLI::Range(0.1, 600.0));
  app.add_option("--hud-period-s", hud_period_s, "HUD update period")
      ->check(CLI::Range(0.05, 10.0));
  app.add_option("--edges", edges,
                 "edge processing (NEP dots, NEP-corrected scan): on, off, or config (the "
                 "configuration's vision_enabled)")
      ->check(CLI::IsMember({"on", "off", "config"}));
  app.add_option("--edges-wait-s", edges_wait_s,
                 "longest a frame waits for its pair's edge result (it never waits past the "
                 "next pair); then it goes out without NEP dots")
      ->check(CLI::Range(0.001, 1.0));
  app.add_option("--duration", duration_s, "stop after this many seconds (0 = until signal)")
      ->check(CLI::Range(0.0, 1e7));
  app.add_option("--stats-period-s", stats_period_s, "log statistics this often")
      ->check(CLI::Range(0.1, 3600.0));
  app.add_option("--log-level", log_level, "debug | info | warning | error")
      ->check(CLI::IsMember({"debug", "info", "warning", "error"}));
  CLI11_PARSE(app, argc, argv);
  LogLevel level = LogLevel::kINFO;
  ParseLogLevel(log_level, &level);
  SetLogLevel(level);
  web.write_timeout = FromSeconds(write_timeout_s);
  web.request_timeout = FromSeconds(request_timeout_s);

  // The console's configuration: calibration (and its stereo alignment), AR options.
  std::string error;
  client::ClientConfig config;
  if (!config_path.empty() && !LoadTextConfig(config_path, &config, &error)) {
    std::cerr << "mostar_web: bad configuration: " << error << "\n";
    return 2;
  }
  ui::ConsoleOptions console;
  if (!client::ConsoleOptionsFromConfig(config, DirectoryOf(config_path), &console, &error)) {
    std::cerr << "mostar_web: bad configuration: " << error << "\n";
    return 2;
  }
  ComposerOptions composer_options;
  composer_options.calibration = console.calibration;
  composer_options.ar = console.ar;
  composer_options.sonar = console.sonar;
  const bool edges_on = edges == "config" ? console.vision_enabled : edges == "on";
  vision::VisionOptions vision_options = console.vision;
  vision_options.keep_edge_images = false;  // the page shows no edge images
  composer_options.intrinsics_from_robot = console.intrinsics_from_robot;
  composer_options.motion = console.motion;
  std::string why;
  if (!console.calibration_path.empty() &&
      !render::LoadAlignment(console.calibration_path, &composer_options.alignment_model,
                             &composer_options.left_alignment, &composer_options.right_alignment,
                             &why)) {
    MOSTAR_LOG(WARNING) << "stereo alignment not loaded, starting without offsets: " << why;
  }
  if (!composer_options.IsValid(&error)) {
    std::cerr << "mostar_web: " << config_path << ": " << error << "\n";
    return 2;
  }
  if (!tokens_path.empty()) {
    web.tokens = TokenTable::Load(tokens_path, &error);
    if (!web.tokens) {
      std::cerr << "mostar_web: " << error << "\n";
      return 2;
    }
  }
  if (!web.IsValid(&error)) {
    std::cerr << "mostar_web: " << error << "\n";
    return 2;
  }

  dds_options.domain_id = domain >= 0 ? domain : dds::DomainIdFromEnvironment(0);
  if (dds_options.xml_participant_profile.empty()) {
    dds_options.xml_participant_profile = "operator";
  }
  auto participant = dds::Participant::Create(dds_options, &error);
  if (!participant) {
    std::cerr << "mostar_web: " << error << "\n";
    return 2;
  }

  const Clock* clock = &SystemClock::Instance();
  client::RobotState robot(clock);
  LatestValueSlot<CompressedStereoPair> pairs;
  std::mutex pairer_mutex;
  EyePairer pairer;
  auto on_image = [&](Eye eye, const dds::wire::CompressedImage& image) {
    std::optional<CompressedStereoPair> pair;
    {
      std::lock_guard<std::mutex> lock(pairer_mutex);
      pair = pairer.Push(eye, dds::FromIdl(image));
    }
    if (pair) pairs.Put(std::move(*pair));
  };
  // The robot's H.264 stream (camera codec H264), decoded and JPEG-encoded for the browsers.
  web::VideoJpegBridge h264_bridge(
      [&pairs](CompressedStereoPair pair) { pairs.Put(std::move(pair)); });
  Readers readers;
  auto& p = *participant;
  readers.video = std::make_unique<decltype(readers.video)::element_type>(
      p, topics::kCameraStereoVideo, dds::VideoStreamReaderQos(dds::kVideoStreamDepth),
      dds::kWithWriter, [&](const dds::wire::StereoVideoFrame& frame, const dds::WriterId&) {
        h264_bridge.Push(dds::FromIdl(frame));
      });
  readers.left = std::make_unique<decltype(readers.left)::element_type>(
      p, topics::kCameraLeft, Stream::kVideo,
      [&](const dds::wire::CompressedImage& image) { on_image(Eye::kLeft, image); });
  readers.right = std::make_unique<decltype(readers.right)::element_type>(
      p, topics::kCameraRight, Stream::kVideo,
      [&](const dds::wire::CompressedImage& image) { on_image(Eye::kRight, image); });
  readers.left_info = std::make_unique<decltype(readers.left_info)::element_type>(
      p, topics::kCameraInfoLeft, Stream::kState, [&](const dds::wire::CameraInfo& info) {
        robot.SetIntrinsics(Eye::kLeft, dds::FromIdl(info));
      });
  readers.scan = std::make_unique<decltype(readers.scan)::element_type>(
      p, topics::kScan, Stream::kSensor,
      [&](const dds::wire::LaserScan& scan) { robot.AddScan(dds::FromIdl(scan)); });
  readers.health = std::make_unique<decltype(readers.health)::element_type>(
      p, topics::kHealth, Stream::kState,
      [&](const dds::wire::RobotHealth& health) { robot.SetHealth(dds::FromIdl(health)); });
  readers.lease = std::make_unique<decltype(readers.lease)::element_type>(
      p, topics::kControlLease, Stream::kState,
      [&](const dds::wire::ControlLease& lease) { robot.SetLease(dds::FromIdl(lease)); });
  readers.sonar = std::make_unique<decltype(readers.sonar)::element_type>(
      p, topics::kSonar, Stream::kSensor,
      [&](const dds::wire::SonarRing& ring) { robot.SetSonar(dds::FromIdl(ring)); });
  readers.bumpers = std::make_unique<decltype(readers.bumpers)::element_type>(
      p, topics::kBumpers, Stream::kState,
      [&](const dds::wire::BumperState& state) { robot.SetBumpers(dds::FromIdl(state)); });
  readers.odometry = std::make_unique<decltype(readers.odometry)::element_type>(
      p, topics::kOdometry, Stream::kSensor,
      [&](const dds::wire::Odometry& odometry) { robot.SetOdometry(dds::FromIdl(odometry)); });
  if (!readers.ok(&error)) {
    std::cerr << "mostar_web: " << error << "\n";
    return 2;
  }

  std::atomic<uint64_t> frames_composed{0};
  std::atomic<uint64_t> frames_moved{0};  // scan moved to the pair's capture time
  std::atomic<uint64_t> frames_faded{0};  // no odometry covered the gap: drawn faded
  std::atomic<uint64_t> frames_with_edges{0};
  std::unique_ptr<EdgeRunner> edge_runner;
  if (edges_on) edge_runner = std::make_unique<EdgeRunner>(vision_options);
  auto dds_stats = [&]() {
    std::string edge_stats = "\"edges\":" + std::string(edge_runner ? "true" : "false") + ",";
    if (edge_runner) {
      const EdgeRunner::Stats e = edge_runner->stats();
      char ms[64];
      std::snprintf(ms, sizeof ms, "\"edge_decode_ms\":%.1f,\"edge_processing_ms\":%.1f,",
                    ToSeconds(e.decode_time) * 1e3, ToSeconds(e.processing_time) * 1e3);
      edge_stats += "\"edge_jobs\":" + std::to_string(e.submitted) +
                    ",\"edge_jobs_replaced\":" + std::to_string(e.replaced) +
                    ",\"edge_results\":" + std::to_string(e.processed) +
                    ",\"edge_failed\":" + std::to_string(e.failed) +
                    ",\"edge_undecodable\":" + std::to_string(e.broken) + "," + ms;
    }
    EyePairerStats s;
    {
      std::lock_guard<std::mutex> lock(pairer_mutex);
      s = pairer.stats();
    }
    const LatestValueSlot<CompressedStereoPair>::Counters slot = pairs.counters();
    return "\"images\":" + std::to_string(s.images) + ",\"pairs\":" + std::to_string(s.pairs) +
           ",\"unpaired\":" + std::to_string(s.unpaired) + ",\"late\":" + std::to_string(s.late) +
           ",\"pairs_skipped\":" + std::to_string(slot.drops) +
           ",\"frames_composed\":" + std::to_string(frames_composed.load()) +
           ",\"frames_moved\":" + std::to_string(frames_moved.load()) +
           ",\"frames_faded\":" + std::to_string(frames_faded.load()) +
           ",\"frames_with_edges\":" + std::to_string(frames_with_edges.load()) + "," + edge_stats;
  };
  std::unique_ptr<WebServer> server = WebServer::Create(web, dds_stats, &error);
  if (!server) {
    std::cerr << "mostar_web: " << error << "\n";
    return 2;
  }
  server->Start();
  // Scripts read the port from this line (with --port 0).
  std::cout << "mostar_web: serving https://" << web.listen_address << ":" << server->port()
            << "/ on DDS domain " << dds_options.domain_id << " (" << dds_options.profile << ")"
            << std::endl;

  // The compose thread: the newest pair into one frame for every browser; the HUD. With edge
  // processing, a pair is held (at most one) until its own edge result is published, the next
  // pair arrives or --edges-wait-s passes, whichever comes first; so a slow edge thread costs
  // frames their dots, never their rate.
  std::atomic<bool> stop{false};
  std::thread composer_thread([&] {
    FrameComposer composer(composer_options);
    RateMeter pair_rate;
    std::optional<Time> newest_stamp;
    std::optional<SteadyTime> newest_received;
    uint32_t sequence = 0;
    uint64_t hud_sequence = 0;
    SteadyTime next_hud = clock->SteadyNow();
    std::string intrinsics_message;
    struct Held {
      CompressedStereoPair pair;
      uint32_t sequence = 0;
      std::optional<LaserScan> scan;
      SteadyTime deadline;
    };
    std::optional<Held> held;
    auto send = [&](const Held& h, std::shared_ptr<const vision::VisionResult> result) {
      FrameInputs inputs;
      inputs.scan = h.scan;
      inputs.edges = std::move(result);
      const Time pair_stamp = h.pair.left.stamp;
      inputs.move_to_pair_time = [&robot, &composer_options, pair_stamp](const LaserScan& scan,
                                                                         fusion::MovedScan* out) {
        robot.MoveScanToImageTime(scan, pair_stamp, composer_options.motion.compensation, out);
      };
      // As the console: the belt cycles at about 5 Hz, a cycle older than a second no longer
      // shows where things are.
      const client::RobotSnapshot robot_now = robot.Snapshot();
      if (robot_now.sonar &&
          clock->SteadyNow() - robot_now.last_sonar_received < std::chrono::seconds(1)) {
        inputs.sonar = robot_now.sonar;
      }
      const ComposedFrame frame =
          composer.Compose(h.pair, inputs, h.sequence, server->WantsBothEyes());
      server->BroadcastFrame(frame);
      ++frames_composed;
      frames_moved += frame.motion.moved;
      frames_faded += frame.motion.faded;
      if (frame.edges) ++frames_with_edges;
    };
    while (!stop.load()) {
      std::optional<CompressedStereoPair> pair =
          pairs.Take(held ? std::chrono::milliseconds(5) : std::chrono::milliseconds(20));
      const SteadyTime now = clock->SteadyNow();
      if (held) {
        std::shared_ptr<const vision::VisionResult> result = edge_runner->LatestResult();
        if (result && result->sequence == held->sequence) {
          send(*held, std::move(result));
          held.reset();
        } else if (pair || now >= held->deadline) {
          send(*held, nullptr);
          held.reset();
        }
      }
      if (pair) {
        composer.SetRobotIntrinsics(robot.Snapshot().left_intrinsics, &intrinsics_message);
        if (!intrinsics_message.empty()) {
          MOSTAR_LOG_EVERY_SEC(WARNING, 30) << "web: " << intrinsics_message;
        }
        Held h;
        h.sequence = ++sequence;
        h.scan = robot.NearestScan(pair->left.stamp);
        h.pair = std::move(*pair);
        pair_rate.Tick(now);
        newest_stamp = h.pair.left.stamp;
        newest_received = now;
        if (edge_runner && h.scan) {
          EdgeJob job;
          job.sequence = h.sequence;
          job.pair = h.pair;
          // As the console: the scan moved to the pair's time for edge processing.
          fusion::MovedScan moved;
          const bool compensate = composer_options.motion.enabled;
          if (compensate) {
            robot.MoveScanToImageTime(*h.scan, h.pair.left.stamp,
                                      composer_options.motion.compensation, &moved);
          }
          job.placement = ui::PlaceScanForVision(*h.scan, compensate ? &moved : nullptr, &job.scan);
          job.potential_outliers = composer.PotentialOutliers(job.scan);
          job.left_camera = composer.left_model();
          job.right_camera = composer.right_model();
          edge_runner->Submit(std::move(job));
          h.deadline = now + FromSeconds(edges_wait_s);
          held = std::move(h);
        } else {
          send(h, nullptr);
        }
      }
      if (now >= next_hud) {
        next_hud = now + FromSeconds(hud_period_s);
        HudInputs inputs;
        inputs.newest_pair_stamp = newest_stamp;
        inputs.newest_pair_received = newest_received;
        inputs.video_fps = pair_rate.RateHz(now);
        inputs.browsers = server->browsers();
        inputs.dds_security_off = participant->security_off();
        inputs.footprint_radius_m = console.path.half_width_m;
        HudState hud = MakeHud(robot.Snapshot(), inputs, clock->Now(), now);
        hud.sequence = ++hud_sequence;
        server->BroadcastHud(std::make_shared<const std::string>(EncodeHud(hud)));
      }
    }
  });

  InstallStopSignals();
  const SteadyTime start = clock->SteadyNow();
  SteadyTime next_stats = start + FromSeconds(stats_period_s);
  while (!StopRequested()) {
    const SteadyTime now = clock->SteadyNow();
    if (duration_s > 0 && now - start >= FromSeconds(duration_s)) break;
    if (now >= next_stats) {
      MOSTAR_LOG(INFO) << "web stats " << server->StatsJson();
      next_stats += FromSeconds(stats_period_s);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  stop = true;
  pairs.Close();
  composer_thread.join();
  readers = Readers();  // no more DDS callbacks
  std::cout << "report: " << server->StatsJson() << std::endl;
  server.reset();
  return 0;
}

}  // namespace
}  // namespace mostar::web

int main(int argc, char** argv) { return mostar::dds::EndProcess(mostar::web::Main(argc, argv)); }
