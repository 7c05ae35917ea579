// operator_client: shows the robot's stereo video with the laser fused over it as AR, and
// drives the robot. Wiring only: flags and configuration choose the pieces and connect them.
#include <CLI/CLI.hpp>
#include <atomic>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <thread>
#include <vector>

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
#include "common/sync/wake_signal.h"
#include "operator_client/client_command_line.h"
#include "operator_client/client_config.pb.h"
#include "operator_client/client_options.h"
#include "operator_client/net/client_inbox.h"
#include "operator_client/net/operator_node.h"
#include "operator_client/net/operator_session.h"
#include "operator_client/net/rejoin_policy.h"
#include "operator_client/net/robot_state.h"
#include "operator_client/net/video_relay_options.h"
#include "operator_client/render/stereo_compositor.h"
#include "operator_client/ui/command_sender.h"
#include "operator_client/ui/operator_console.h"
#include "operator_client/ui/run_end.h"
#include "operator_client/ui/run_report.h"
#include "operator_client/ui/window.h"
#include "operator_client/video/stereo_receiver.h"
#include "operator_client/vision/vision_pipeline.h"

namespace mostar::client {
namespace {

// The render loop's longest sleeps when nothing wakes it (WakeSignal, input events).
constexpr Duration kHeadlessIdle = std::chrono::milliseconds(20);  // run limits, lease
constexpr Duration kVisibleIdle = std::chrono::milliseconds(50);   // HUD clock at 20 Hz
constexpr Duration kGamepadPoll = std::chrono::milliseconds(10);   // sticks at 100 Hz

int Run(int argc, char** argv) {
  CLI::App app{"operator_client: stereoscopic AR view of the robot and driving console."};
  ClientCommandLine line;
  AddClientOptions(&app, &line);
  CLI11_PARSE(app, argc, argv);
  const ClientFlags& flags = line.flags;
  LogLevel level;
  ParseLogLevel(line.log_level, &level);
  SetLogLevel(level);

  std::string error;
  dds::ParticipantOptions dds_options;
  dds_options.domain_id = line.domain >= 0 ? line.domain : dds::DomainIdFromEnvironment(0);
  dds_options.profile = line.dds_profile;
  dds_options.name = "operator";
  dds_options.insecure = flags.insecure;
  // Started before its overlay (a laptop whose WireGuard comes up after the console): wait for
  // the profile's addresses, logged, rather than run unreachable or give up.
  dds_options.wait_for_interfaces = std::chrono::seconds(60);
  dds::ParticipantOptions video_dds_options;
  if (line.video_via_relay &&
      !VideoThroughRelayOptions(dds_options, line.video_domain, &video_dds_options, &error)) {
    std::cerr << "operator_client: " << error << "\n";
    return 2;
  }
  if (line.check_config) {
    ConfigReport report;
    CheckConsoleConfig(line.config_path, flags, dds_options,
                       line.video_via_relay ? &video_dds_options : nullptr, &report);
    return report.Print("operator_client", std::cout);
  }
  ClientConfig config;
  if (!line.config_path.empty() && !LoadTextConfig(line.config_path, &config, &error)) {
    std::cerr << "operator_client: bad configuration: " << error << "\n";
    return 2;
  }
  ui::ConsoleOptions console_options;
  if (!ConsoleOptionsFromConfig(config, DirectoryOf(line.config_path), &console_options, &error)) {
    std::cerr << "operator_client: bad configuration: " << error << "\n";
    return 2;
  }
  if (!ApplyClientFlags(flags, config, &console_options, &error)) {
    std::cerr << "operator_client: " << error << "\n";
    return 2;
  }
  const bool headless = flags.headless;
  StampTrace trace;
  if (!trace.Open(line.trace_path)) {
    std::cerr << "operator_client: cannot write " << line.trace_path << "\n";
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
  if (line.video_via_relay) {
    video_participant = dds::Participant::Create(video_dds_options, &error);
    if (!video_participant) {
      std::cerr << "operator_client: video through the relay: " << error << "\n";
      return 1;
    }
  }
  if (!ResolveClientId(flags, participant->secure(), participant->own_client_id(),
                       &console_options.client_id, &error)) {
    std::cerr << "operator_client: " << line.dds_profile << ": " << error << "\n";
    return 2;
  }
  const std::string& client_id = console_options.client_id;
  console_options.dds_security_off = participant->security_off();
  console_options.keep_last_frame = !line.screenshot.empty() || line.capture();

  const Clock* clock = &SystemClock::Instance();
  std::unique_ptr<record::RecordingWriter> recorder;
  if (!line.record_path.empty()) {
    record::RecordingInfo info;
    info.robot_id = "recorded by " + client_id;
    info.calibration_text = math::ToProto(console_options.calibration, "in force").DebugString();
    recorder = record::RecordingWriter::Open(line.record_path, {}, info, *clock, &error);
    if (!recorder) {
      std::cerr << "operator_client: cannot record: " << error << "\n";
      return 2;
    }
  }
  record::RecordingWriter* rec = recorder.get();
  StereoReceiver video(clock);
  RobotState robot(clock);
  OperatorSession::Options session_options;
  session_options.dds = dds_options;
  if (line.video_via_relay) session_options.video_dds = video_dds_options;
  session_options.node.client_id = client_id;
  session_options.node.pilot = console_options.pilot;
  session_options.callbacks = InboxCallbacks({client_id, clock, &video, &robot, rec, &trace});
  std::unique_ptr<OperatorSession> session = OperatorSession::Create(
      session_options, &error, std::move(participant), std::move(video_participant));
  if (!session) {
    std::cerr << "operator_client: " << error << "\n";
    return 1;
  }
  // Guards `session` while a join replaces it: the command thread writes through it.
  std::mutex session_mutex;
  // The receiver's requests and reports go to the session's video source (its own lock
  // serialises them with setting them).
  const auto connect_video = [&video, &client_id, clock](OperatorNode* video_source) {
    video.SetKeyframeRequester(
        [video_source, &client_id, clock](uint64_t last, const std::string& reason) {
          video_source->SendKeyframeRequest({clock->Now(), client_id, last, reason});
        });
    video.SetFeedbackSender(
        [video_source, &client_id, clock](const std::vector<VideoFrameArrival>& a) {
          video_source->SendVideoFeedback({clock->Now(), client_id, a});
        });
  };
  connect_video(&session->video_source());
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
  sinks.command = [&](const VelocityCommand& c) {
    std::lock_guard<std::mutex> lock(session_mutex);
    return session && session->node().SendCommand(c);
  };
  sinks.ping = [&](const ClockProbe& p) {
    ClockProbe ping = p;
    ping.t3 = robot.PongReceipt(p.sequence - 1);
    std::lock_guard<std::mutex> lock(session_mutex);
    return session && session->node().SendPing(ping);
  };
  sinks.control = [&](const ControlRequest& r) {
    std::lock_guard<std::mutex> lock(session_mutex);
    return session && session->node().SendControlRequest(r);
  };
  sinks.estop = [&](const EmergencyStop& e) {
    std::lock_guard<std::mutex> lock(session_mutex);
    return session && session->node().SendEmergencyStop(e);
  };
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
  // The render loop sleeps until a pair is decoded or an edge result published (a visible
  // window's event wait is ended for it), or a pair's result wait ends.
  WakeSignal wake;
  if (!headless) wake.SetHook([] { ui::Window::WakeUp(); });
  video.SetWakeSignal(&wake);
  console.SetWakeSignal(&wake);
  if (line.capture_stamp_ns >= 0) console.CapturePair(FromUnixNanos(line.capture_stamp_ns));
  if (line.scripted_drive.size() == 2) {
    console.SetScriptedDrive({line.scripted_drive[0], line.scripted_drive[1], true});
  }
  MOSTAR_LOG(INFO) << "operator_client '" << client_id << "' (" << flags.role << ") on DDS domain "
                   << dds_options.domain_id
                   << (line.video_via_relay ? ", video through the relay on domain " +
                                                  std::to_string(video_dds_options.domain_id)
                                            : std::string())
                   << ", " << window->renderer() << ", display "
                   << render::DisplayModeName(console_options.mode);
  commands.Start();
  InstallStopSignals();
  const ui::RunLimits limits{static_cast<uint64_t>(line.max_frames), FromSeconds(line.duration_s)};
  const SteadyTime start = clock->SteadyNow();
  // The overlay's address gone and back is logged; a new address means restarting in place.
  std::optional<dds::NetworkCheck> network_check;
  network_check.emplace(
      std::vector<const dds::Participant*>{&session->participant(), session->video_participant()});
  RejoinPolicy rejoin(RejoinOptionsAfter(line.rejoin_after_s));
  while (!StopRequested() && !window->ShouldClose()) {
    if (line.rejoin_after_s > 0 &&
        rejoin.Update(session != nullptr && session->robot_seen(), clock->SteadyNow())) {
      // Nothing of the robot matched for that long: join again as a new participant (a
      // handshake that never ends, or a robot that is not there: it costs a participant).
      MOSTAR_LOG(WARNING) << "operator_client: nothing of the robot matched for "
                          << ToSeconds(rejoin.wait())
                          << " s; joining DDS again as a new participant";
      rejoin.Rejoined(clock->SteadyNow());
      video.SetKeyframeRequester(nullptr);
      video.SetFeedbackSender(nullptr);
      network_check.reset();
      {
        std::lock_guard<std::mutex> lock(session_mutex);
        const ExitDeadline deadline(FromMilliseconds(5000), 4, "operator_client",
                                    "DDS teardown to join again");
        session.reset();
      }
      std::unique_ptr<OperatorSession> joined = OperatorSession::Create(session_options, &error);
      if (!joined) MOSTAR_LOG(ERROR) << "operator_client: cannot join DDS again: " << error;
      std::lock_guard<std::mutex> lock(session_mutex);
      session = std::move(joined);
      if (session) {
        connect_video(&session->video_source());
        network_check.emplace(std::vector<const dds::Participant*>{&session->participant(),
                                                                   session->video_participant()});
      }
    }
    if (network_check && network_check->RestartNeeded(std::chrono::steady_clock::now())) {
      MOSTAR_LOG(WARNING) << "operator_client: restarting in place to be reachable on this "
                             "computer's new address";
      RequestRestart();
      break;
    }
    if (ui::CaptureAfterDue(line.capture_after, console.capturing(), video.Stats().pairs_decoded)) {
      console.CapturePair(std::nullopt);
    }
    const bool drawn = console.Frame();
    if (headless) {
      // Nothing new was drawn: sleep until something is (the HUD needs no refresh headless).
      if (!drawn) wake.WaitFor(console.IdleWait(kHeadlessIdle));
    } else {
      // Input events wake the window too; the HUD refreshes at least every kVisibleIdle, a
      // gamepad (polled, it sends no events) every kGamepadPoll.
      wake.TakePending();
      ui::Window::WaitEvents(
          console.IdleWait(ui::Window::GamepadPresent() ? kGamepadPoll : kVisibleIdle));
    }
    if (ui::CheckRunEnd(limits, console.captured(), console.rendered_pairs(),
                        clock->SteadyNow() - start) != ui::RunEnd::kRunning) {
      break;
    }
  }
  {  // Fast DDS 2.9 can block here; end within 2 s of SIGTERM anyway (status 4, no report)
    const ExitDeadline deadline(FromMilliseconds(1500), 4, "operator_client", "DDS teardown");
    video.SetWakeSignal(nullptr);
    wake.SetHook(nullptr);
    commands.Stop();
    video.SetKeyframeRequester(nullptr);  // they write through the node
    video.SetFeedbackSender(nullptr);
    std::lock_guard<std::mutex> lock(session_mutex);
    if (session) session->CloseNodes();  // no more callbacks into the recorder
  }
  if (recorder && !recorder->Close(&error)) {
    std::cerr << "operator_client: recording: " << error << "\n";
  }
  trace.Flush();
  const ui::ScreenshotPlan shot =
      ui::PlanScreenshot(line.screenshot, line.capture(), console.captured(),
                         console.captured_stamp().has_value(), !console.last_frame().empty());
  if (!shot.problem.empty()) std::cerr << "operator_client: " << shot.problem << "\n";
  if (shot.write && !cv::imwrite(line.screenshot, console.last_frame())) {
    std::cerr << "operator_client: cannot write " << line.screenshot << "\n";
  }
  std::cout << ui::FormatRunReport(console.RunTotals(clock->SteadyNow() - start), video.Stats());
  return shot.exit_status;
}

}  // namespace
}  // namespace mostar::client

int main(int argc, char** argv) {
  mostar::RememberCommandLine(argc, argv);
  const int status = mostar::client::Run(argc, argv);
  return mostar::dds::EndProcess(mostar::RestartIfRequested(status, "operator_client"));
}
