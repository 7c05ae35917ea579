// operator_client: shows the robot's stereo video with the laser fused over it as AR, and
// drives the robot. Wiring only: flags and configuration choose the pieces and connect them.
#include <CLI/CLI.hpp>
#include <atomic>
#include <cstdlib>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "common/config/config_loader.h"
#include "common/config/config_paths.h"
#include "common/dds/domain.h"
#include "common/dds/network_check.h"
#include "common/dds/participant.h"
#include "common/log/log.h"
#include "common/log/stamp_trace.h"
#include "common/math/calibration_io.h"
#include "common/process/exit_deadline.h"
#include "common/process/restart_in_place.h"
#include "common/process/stop_signals.h"
#include "common/record/recording_writer.h"
#include "operator_client/client_config.pb.h"
#include "operator_client/client_options.h"
#include "operator_client/net/client_inbox.h"
#include "operator_client/net/operator_node.h"
#include "operator_client/net/robot_state.h"
#include "operator_client/net/video_relay_options.h"
#include "operator_client/render/stereo_compositor.h"
#include "operator_client/ui/command_sender.h"
#include "operator_client/ui/operator_console.h"
#include "operator_client/ui/run_report.h"
#include "operator_client/ui/window.h"
#include "operator_client/video/stereo_receiver.h"
#include "operator_client/vision/vision_pipeline.h"

namespace mostar::client {
namespace {

int Run(int argc, char** argv) {
  CLI::App app{"operator_client: stereoscopic AR view of the robot and driving console."};
  int domain = -1;
  std::string dds_profile = "loopback";
  ClientFlags flags;
  std::string config_path;
  int max_frames = 0;
  double duration_s = 0;
  std::string screenshot;
  int64_t capture_stamp_ns = -1;
  int capture_after = -1;
  std::vector<double> scripted_drive;
  std::string trace_path;
  std::string record_path;
  std::string log_level = "info";
  bool video_via_relay = false;
  int video_domain = -1;
  app.add_option("--domain", domain, "DDS domain id (default: MOSTAR_DDS_DOMAIN, then 0)")
      ->check(CLI::Range(0, 232));
  app.add_option("--dds-profile", dds_profile, "'loopback' or a Fast DDS XML profiles file");
  auto* via_relay_option = app.add_flag(
      "--video-via-relay", video_via_relay,
      "take the camera streams from mostar_relay (participant profile 'operator_video' of "
      "--dds-profile, on --video-domain), so that the robot's uplink carries the video once; "
      "commands, e-stop, lease, clock, scans and the rest stay direct");
  app.add_option("--video-domain", video_domain,
                 "with --video-via-relay: the relay's observer domain (default --domain + 1)")
      ->check(CLI::Range(0, 232))
      ->needs(via_relay_option);
  auto* id_option = app.add_option(
      "--id", flags.client_id,
      "this client's id (shown in the lease); with DDS Security the CN of its certificate, "
      "which is also the default");
  app.add_flag("--insecure", flags.insecure,
               "allow a network DDS profile without DDS Security (anyone on the network can "
               "watch and drive; docs/security.md)");
  app.add_option("--role", flags.role, "pilot | observer")
      ->check(CLI::IsMember({"pilot", "observer"}));
  int ignored_strength = 0;
  app.add_option("--strength", ignored_strength,
                 "ignored (accepted for old scripts): the robot's role table gives strengths and "
                 "cmd_vel ownership is shared");
  app.add_option("--display", flags.display,
                 "mono-left | mono-right | anaglyph | anaglyph-color | sbs | sbs-half | "
                 "top-bottom | interlaced | quad-buffer");
  app.add_option("-c,--config", config_path, "client configuration (protobuf text format)")
      ->check(CLI::ExistingFile);
  app.add_option("--calibration", flags.calibration_path,
                 "laser-camera calibration profile (protobuf text); the panel saves here");
  app.add_flag("--calibration-panel", flags.calibration_panel,
               "open the calibration panel at start");
  app.add_flag("--headless", flags.headless,
               "hidden window; render to --screenshot (needs an X server, e.g. xvfb-run)");
  app.add_option("--frames", max_frames, "exit after rendering this many video frames")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--duration", duration_s, "exit after this many seconds")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--screenshot", screenshot, "write the last rendered frame to this PNG");
  auto* capture_stamp_option =
      app.add_option("--capture-stamp", capture_stamp_ns,
                     "render only the pair with this capture stamp (ns since the epoch) once its "
                     "scans are in, write it to --screenshot and exit (reproducible screenshots)")
          ->check(CLI::NonNegativeNumber);
  app.add_option("--capture-after", capture_after,
                 "like --capture-stamp for the first pair decoded after this many; the report "
                 "gives its stamp (captured_stamp_ns)")
      ->check(CLI::NonNegativeNumber)
      ->excludes(capture_stamp_option);
  app.add_option("--window-size", flags.window_size,
                 "window size WIDTHxHEIGHT in pixels (default: the image's, doubled in width "
                 "for sbs)")
      ->expected(2)
      ->delimiter('x');
  app.add_flag("--no-hud", flags.no_hud, "hide the HUD (changing rates and ages; H toggles it)");
  app.add_option("--drive", scripted_drive, "scripted command V,W (m/s, rad/s) held throughout")
      ->expected(2)
      ->delimiter(',');
  app.add_option("--trace", trace_path, "write received stamps and sent commands to this CSV");
  app.add_option("--record", record_path,
                 "record everything received (and the commands sent) to this file");
  app.add_option("--log-level", log_level, "debug | info | warning | error")
      ->check(CLI::IsMember({"debug", "info", "warning", "error"}));
  bool check_config = false;
  app.add_flag("--check-config", check_config,
               "check the configuration, calibration, DDS profile (certificates, addresses), "
               "client id and display, print each problem with its fix, and exit: 0 when all is "
               "well");
  CLI11_PARSE(app, argc, argv);
  flags.client_id_given = id_option->count() > 0;
  LogLevel level;
  ParseLogLevel(log_level, &level);
  SetLogLevel(level);

  std::string error;
  dds::ParticipantOptions dds_options;
  dds_options.domain_id = domain >= 0 ? domain : dds::DomainIdFromEnvironment(0);
  dds_options.profile = dds_profile;
  dds_options.name = "operator";
  dds_options.insecure = flags.insecure;
  // Started before its overlay (a laptop whose WireGuard comes up after the console): wait for
  // the profile's addresses, logged, rather than run unreachable or give up.
  dds_options.wait_for_interfaces = std::chrono::seconds(60);
  dds::ParticipantOptions video_dds_options;
  if (video_via_relay &&
      !VideoThroughRelayOptions(dds_options, video_domain, &video_dds_options, &error)) {
    std::cerr << "operator_client: " << error << "\n";
    return 2;
  }
  if (check_config) {
    ConfigReport report;
    CheckConsoleConfig(config_path, flags, dds_options,
                       video_via_relay ? &video_dds_options : nullptr, &report);
    return report.Print("operator_client", std::cout);
  }
  ClientConfig config;
  if (!config_path.empty() && !LoadTextConfig(config_path, &config, &error)) {
    std::cerr << "operator_client: bad configuration: " << error << "\n";
    return 2;
  }
  ui::ConsoleOptions console_options;
  if (!ConsoleOptionsFromConfig(config, DirectoryOf(config_path), &console_options, &error)) {
    std::cerr << "operator_client: bad configuration: " << error << "\n";
    return 2;
  }
  if (!ApplyClientFlags(flags, config, &console_options, &error)) {
    std::cerr << "operator_client: " << error << "\n";
    return 2;
  }
  const bool headless = flags.headless;
  StampTrace trace;
  if (!trace.Open(trace_path)) {
    std::cerr << "operator_client: cannot write " << trace_path << "\n";
    return 2;
  }
  if (!headless && std::getenv("DISPLAY") == nullptr && std::getenv("WAYLAND_DISPLAY") == nullptr) {
    std::cerr << "operator_client: no display; use --headless under xvfb-run\n";
    return 2;
  }

  auto participant = dds::Participant::Create(dds_options, &error);
  if (!participant) {
    std::cerr << "operator_client: " << error << "\n";
    return 1;
  }
  // The camera streams through mostar_relay: a second participant, same identity, on the
  // relay's observer domain.
  std::unique_ptr<dds::Participant> video_participant;
  if (video_via_relay) {
    video_participant = dds::Participant::Create(video_dds_options, &error);
    if (!video_participant) {
      std::cerr << "operator_client: video through the relay: " << error << "\n";
      return 1;
    }
  }
  if (!ResolveClientId(flags, participant->secure(), participant->own_client_id(),
                       &console_options.client_id, &error)) {
    std::cerr << "operator_client: " << dds_profile << ": " << error << "\n";
    return 2;
  }
  const std::string& client_id = console_options.client_id;
  console_options.dds_security_off = participant->security_off();
  console_options.keep_last_frame =
      !screenshot.empty() || capture_stamp_ns >= 0 || capture_after >= 0;

  const Clock* clock = &SystemClock::Instance();
  std::unique_ptr<record::RecordingWriter> recorder;
  if (!record_path.empty()) {
    record::RecordingInfo info;
    info.robot_id = "recorded by " + client_id;
    info.calibration_text = math::ToProto(console_options.calibration, "in force").DebugString();
    recorder = record::RecordingWriter::Open(record_path, {}, info, *clock, &error);
    if (!recorder) {
      std::cerr << "operator_client: cannot record: " << error << "\n";
      return 2;
    }
  }
  record::RecordingWriter* rec = recorder.get();
  StereoReceiver video(clock);
  RobotState robot(clock);
  OperatorNode::Options node_options;
  node_options.client_id = client_id;
  node_options.pilot = console_options.pilot;
  if (video_participant) node_options.streams = OperatorNode::Options::Streams::kAllButVideo;
  const OperatorNode::Callbacks callbacks =
      InboxCallbacks({client_id, clock, &video, &robot, rec, &trace});
  auto node = OperatorNode::Create(participant.get(), node_options, callbacks, &error);
  std::unique_ptr<OperatorNode> video_node;  // through the relay, or null
  if (node && video_participant) {
    node_options.streams = OperatorNode::Options::Streams::kVideoOnly;
    video_node = OperatorNode::Create(video_participant.get(), node_options, callbacks, &error);
  }
  if (!node || (video_participant && !video_node)) {
    std::cerr << "operator_client: " << error << "\n";
    return 1;
  }
  OperatorNode* video_source = video_node ? video_node.get() : node.get();
  video.SetKeyframeRequester(
      [video_source, &client_id, clock](uint64_t last, const std::string& reason) {
        video_source->SendKeyframeRequest({clock->Now(), client_id, last, reason});
      });
  video.SetFeedbackSender(
      [video_source, &client_id, clock](const std::vector<VideoFrameArrival>& a) {
        video_source->SendVideoFeedback({clock->Now(), client_id, a});
      });
  // On every way out, the receiver stops writing through the node before it goes (declared
  // after it).
  struct RequesterReset {
    StereoReceiver& video;
    ~RequesterReset() {
      video.SetKeyframeRequester(nullptr);
      video.SetFeedbackSender(nullptr);
    }
  } requester_reset{video};

  ui::CommandSenderOptions sender_options;
  sender_options.client_id = client_id;
  sender_options.pilot = console_options.pilot;
  ui::CommandSinks sinks;
  sinks.command = [&](const VelocityCommand& c) { return node->SendCommand(c); };
  sinks.ping = [&](const ClockProbe& p) {
    ClockProbe ping = p;
    ping.t3 = robot.PongReceipt(p.sequence - 1);
    return node->SendPing(ping);
  };
  sinks.control = [&](const ControlRequest& r) { return node->SendControlRequest(r); };
  sinks.estop = [&](const EmergencyStop& e) { return node->SendEmergencyStop(e); };
  sinks.robot_estop = [&robot]() -> std::optional<ui::ReportedEstop> {
    ui::ReportedEstop reported;
    const std::optional<bool> engaged = robot.EstopEngaged(&reported.received);
    if (!engaged) return std::nullopt;
    reported.engaged = *engaged;
    return reported;
  };
  sinks.on_sent = [&](const VelocityCommand& c) {
    trace.Add("command", c.stamp, c.sequence);
    if (rec) rec->Write(c);
  };
  ui::CommandSender commands(sender_options, sinks, clock);

  auto window = ui::Window::Create(WindowOptionsFor(flags, console_options), &error);
  if (!window) {
    std::cerr << "operator_client: " << error << "\n";
    return 1;
  }
  if (console_options.mode == render::DisplayMode::kQuadBuffer && !window->quad_buffer()) {
    std::cerr << "operator_client: quad-buffer stereo is not available with " << window->renderer()
              << "; showing the left eye\n";
  }
  ui::OperatorConsole console(console_options, window.get(), &video, &robot, &commands, clock);
  if (!console.Init(&error)) {
    std::cerr << "operator_client: " << error << "\n";
    return 1;
  }
  const bool capture = capture_stamp_ns >= 0 || capture_after >= 0;
  if (capture_stamp_ns >= 0) console.CapturePair(FromUnixNanos(capture_stamp_ns));
  if (scripted_drive.size() == 2) {
    console.SetScriptedDrive({scripted_drive[0], scripted_drive[1], true});
  }
  MOSTAR_LOG(INFO) << "operator_client '" << client_id << "' (" << flags.role << ") on DDS domain "
                   << dds_options.domain_id
                   << (video_participant ? ", video through the relay on domain " +
                                               std::to_string(video_dds_options.domain_id)
                                         : std::string())
                   << ", " << window->renderer() << ", display "
                   << render::DisplayModeName(console_options.mode);
  commands.Start();
  InstallStopSignals();
  const SteadyTime start = clock->SteadyNow();
  // The overlay's address gone and back is logged; a new address means restarting in place.
  dds::NetworkCheck network_check({participant.get(), video_participant.get()});
  while (!StopRequested() && !window->ShouldClose()) {
    if (network_check.RestartNeeded(std::chrono::steady_clock::now())) {
      MOSTAR_LOG(WARNING) << "operator_client: restarting in place to be reachable on this "
                             "computer's new address";
      RequestRestart();
      break;
    }
    if (capture_after >= 0 && !console.capturing() &&
        video.Stats().pairs_decoded >= static_cast<uint64_t>(capture_after)) {
      console.CapturePair(std::nullopt);
    }
    if (!console.Frame() && headless) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    if (console.captured()) break;
    if (max_frames > 0 && console.rendered_pairs() >= static_cast<uint64_t>(max_frames)) break;
    if (duration_s > 0 && clock->SteadyNow() - start > FromSeconds(duration_s)) break;
  }
  {  // Fast DDS 2.9 can block here; end within 2 s of SIGTERM anyway (status 4, no report)
    const ExitDeadline deadline(FromMilliseconds(1500), 4, "operator_client", "DDS teardown");
    commands.Stop();
    video.SetKeyframeRequester(nullptr);  // they write through the node
    video.SetFeedbackSender(nullptr);
    video_node.reset();
    node.reset();  // no more callbacks into the recorder
  }
  if (recorder && !recorder->Close(&error)) {
    std::cerr << "operator_client: recording: " << error << "\n";
  }
  trace.Flush();
  if (capture && !console.captured()) {
    std::cerr << "operator_client: the pair to capture was not rendered"
              << (console.captured_stamp() ? " (its scans or edge result did not arrive)"
                                           : " (it did not arrive)")
              << "; no screenshot written\n";
  } else if (!screenshot.empty()) {
    if (console.last_frame().empty()) {
      std::cerr << "operator_client: no video frame was rendered; no screenshot written\n";
    } else if (!cv::imwrite(screenshot, console.last_frame())) {
      std::cerr << "operator_client: cannot write " << screenshot << "\n";
    }
  }
  ui::ConsoleRunTotals totals;
  totals.rendered_frames = console.rendered_pairs();
  totals.scripted_rearms = console.scripted_rearms();
  totals.scans = robot.Snapshot().scans;
  totals.commands_sent = commands.commands_sent();
  totals.run_s = ToSeconds(clock->SteadyNow() - start);
  totals.display_age_ms_p50 = console.DisplayAgePercentileMs(50);
  totals.display_age_ms_p95 = console.DisplayAgePercentileMs(95);
  totals.frame_time_ms_p50 = console.FrameTimePercentileMs(50);
  totals.frame_time_ms_p95 = console.FrameTimePercentileMs(95);
  if (console.captured()) totals.captured_stamp_ns = ToUnixNanos(*console.captured_stamp());
  totals.sonar_echoes = console.sonar_echoes();
  totals.sonar_unseen = console.sonar_unseen();
  totals.overlays_moved = console.shown().overlays_moved();
  totals.overlays_faded = console.shown().overlays_faded();
  totals.latency = console.latency().Rows();
  std::cout << ui::FormatRunReport(totals, video.Stats());
  return capture && !console.captured() ? 1 : 0;
}

}  // namespace
}  // namespace mostar::client

int main(int argc, char** argv) {
  mostar::RememberCommandLine(argc, argv);
  const int status = mostar::client::Run(argc, argv);
  return mostar::dds::EndProcess(mostar::RestartIfRequested(status, "operator_client"));
}
