// robot_server: the daemon on the robot. Wiring only: flags and configuration, the devices of
// the configured source (robot_server/devices), the camera pipeline, the DDS node and the
// control loop (robot_server/control), run until SIGINT/SIGTERM; or a recording published as
// the robot would (robot_server/replay).
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <thread>

#include "common/config/config_loader.h"
#include "common/config/config_paths.h"
#include "common/config/config_report.h"
#include "common/dds/domain.h"
#include "common/dds/network_check.h"
#include "common/dds/participant.h"
#include "common/log/log.h"
#include "common/log/stamp_trace.h"
#include "common/process/exit_deadline.h"
#include "common/process/restart_in_place.h"
#include "common/process/stop_signals.h"
#include "common/record/recording_writer.h"
#include "common/service/service_notifier.h"
#include "robot_server/camera/camera_pipeline.h"
#include "robot_server/control/robot_controller.h"
#include "robot_server/devices/robot_devices.h"
#include "robot_server/drive/drive_config.h"
#include "robot_server/node/robot_node.h"
#include "robot_server/replay/replay_publisher.h"
#include "robot_server/server_check.h"
#include "robot_server/server_config.pb.h"
#include "robot_server/server_options.h"

namespace mostar::server {
namespace {

// How long stopping the camera pipeline and deleting the DDS entities may take after SIGTERM
// (normally well under 1 s; the stop must be complete within 2 s).
constexpr Duration kDdsTeardownDeadline = std::chrono::milliseconds(1500);

int Fail(int status, const std::string& message) {
  std::cerr << "robot_server: " << message << "\n";
  return status;
}

int Run(int argc, char** argv) {
  CLI::App app{
      "robot_server: publishes the robot's stereo frames, laser scans, odometry and "
      "health over DDS and drives it from one pilot's velocity commands."};
  ServerFlags flags;
  AddServerFlags(&app, &flags);
  CLI11_PARSE(app, argc, argv);
  LogLevel level;
  ParseLogLevel(flags.log_level, &level);
  SetLogLevel(level);

  ServerConfig config;
  std::string error;
  if (!flags.config_path.empty() && !LoadTextConfig(flags.config_path, &config, &error)) {
    if (flags.check_config) {
      ConfigReport report;
      report.Fail("the configuration does not load: " + error,
                  "correct the line named (schema: robot_server/server_config.proto; examples "
                  "in " +
                      InstalledConfigDir() + ")");
      return report.Print("robot_server", std::cout);
    }
    return Fail(2, "bad configuration: " + error);
  }
  const std::string config_dir = flags.config_path.empty() ? "" : DirectoryOf(flags.config_path);
  ApplyFlags(flags, &config);
  dds::ParticipantOptions dds_options;
  dds_options.domain_id =
      flags.domain >= 0 ? flags.domain : dds::DomainIdFromEnvironment(config.dds().domain_id());
  dds_options.profile = flags.dds_profile.empty() ? config.dds().profile() : flags.dds_profile;
  dds_options.name = "robot";
  dds_options.tcp_user_timeout_ms = config.dds().tcp_user_timeout_ms();
  dds_options.insecure = config.dds().insecure();
  if (flags.check_config) {
    ConfigReport report;
    if (!flags.config_path.empty()) report.Ok("configuration " + flags.config_path + " loads");
    CheckServerConfig(config, config_dir, dds_options, &report);
    return report.Print("robot_server", std::cout);
  }
  drive::DriveSettings settings;
  if (!drive::DriveSettingsFromProto(config.drive(), &settings, &error)) {
    return Fail(2, "bad configuration: drive: " + error);
  }
  std::string state_dir;
  if (!EstopStateDirectory(config, config_dir, &state_dir, &error)) {
    return Fail(2, "bad configuration: " + error);
  }
  StampTrace trace;
  if (!trace.Open(flags.trace_path)) return Fail(2, "cannot write " + flags.trace_path);
  const Clock* clock = &SystemClock::Instance();
  RobotDevices devices;
  if (flags.replay_path.empty() &&
      !MakeRobotDevices(config, config_dir, clock, &settings, &devices, &error)) {
    return Fail(2, error);
  }

  // Started before its network (the WireGuard overlay's address) is up: wait for it rather than
  // run undiscoverable; within mostar-robot-server.service's TimeoutStartSec (60 s), after which
  // systemd restarts the server and it waits again.
  dds_options.wait_for_interfaces = std::chrono::seconds(45);
  auto participant = dds::Participant::Create(dds_options, &error);
  if (!participant) return Fail(1, error);

  InstallStopSignals();
  InstallSignalRequest(SIGUSR2);  // a local e-stop release (root on the robot)
  if (!flags.replay_path.empty()) {
    auto node = RobotNode::Create(participant.get(), {}, {}, clock, &error);
    if (!node) return Fail(1, error);
    replay::ReplaySessionOptions replay;
    replay.path = flags.replay_path;
    replay.replay.rate = flags.replay_rate;
    replay.replay.loop = flags.replay_loop;
    replay.replay.start_paused = flags.replay_paused;
    replay.duration = FromSeconds(flags.duration_s);
    return replay::RunReplaySession(replay, node.get(), &trace, &std::cin);
  }

  // The node's callbacks reach the controller once it exists; earlier messages are dropped.
  std::atomic<RobotController*> controller_ptr{nullptr};
  RobotNode::Callbacks callbacks;
  callbacks.on_command = [&](const VelocityCommand& c) {
    if (RobotController* controller = controller_ptr.load()) controller->OnCommand(c);
  };
  callbacks.on_estop = [&](const EmergencyStop& s) {
    if (RobotController* controller = controller_ptr.load()) controller->OnEmergencyStop(s);
  };
  callbacks.on_control_request = [&](const ControlRequest& r) {
    if (RobotController* controller = controller_ptr.load()) controller->OnControlRequest(r);
  };
  callbacks.on_command_stream_lost = [&](const std::string& client_id) {
    if (RobotController* controller = controller_ptr.load()) {
      controller->OnCommandStreamLost(client_id);
    }
  };
  std::atomic<camera::CameraPipeline*> pipeline_ptr{nullptr};
  callbacks.on_keyframe_request = [&](const KeyframeRequest& request) {
    MOSTAR_LOG_EVERY_SEC(INFO, 10) << "keyframe requested (" << request.reason << ")";
    if (camera::CameraPipeline* camera = pipeline_ptr.load()) camera->RequestKeyframe();
  };
  callbacks.on_video_feedback = [&](const VideoFeedback& feedback) {
    if (camera::CameraPipeline* camera = pipeline_ptr.load()) camera->OnVideoFeedback(feedback);
  };
  RobotNode::VideoOptions video;
  video.window_pairs = config.dds().video_window_pairs();
  video.lane_timeout = std::chrono::milliseconds(config.dds().video_lane_timeout_ms());
  video.repair_period = std::chrono::milliseconds(config.dds().video_repair_period_ms());
  video.repair_deadline = std::chrono::milliseconds(config.dds().video_repair_deadline_ms());
  video.h264 = devices.camera_options.codec == camera::VideoCodec::kH264;
  // A repair holds the frames behind a loss for about a repair period: not silence.
  devices.camera_options.video_rate.link.repair_hold = video.repair_period;
  devices.camera_options.video_rate.repair_deadline = video.repair_deadline;
  devices.camera_options.video_rate.auto_repair_deadline =
      config.dds().video_repair_deadline_auto();
  // The role table's clients, each heard in its own partition (RobotNode).
  std::vector<RobotSender> senders;
  for (const auto& role : config.drive().roles()) {
    senders.push_back({role.client_id(), role.role() == drive::PilotRole::PILOT});
  }
  std::unique_ptr<RobotNode> node =
      RobotNode::Create(participant.get(), senders, callbacks, clock, &error, video);
  if (!node) return Fail(1, error);

  std::unique_ptr<record::RecordingWriter> recorder;
  if (!flags.record_path.empty()) {
    record::RecordingInfo info;
    info.robot_id = config.robot_id();
    info.metadata.emplace_back("source", ServerConfig::Source_Name(config.source()));
    info.metadata.emplace_back("scene", config.scene_file());
    recorder = record::RecordingWriter::Open(flags.record_path, {}, info, *clock, &error);
    if (!recorder) return Fail(2, "cannot record: " + error);
    MOSTAR_LOG(INFO) << "recording to " << flags.record_path;
  }
  record::RecordingWriter* rec = recorder.get();
  RobotNode* robot_node = node.get();
  camera::CameraPipeline pipeline(std::move(devices.camera), devices.camera_options,
                                  [robot_node, &trace, rec](const CompressedStereoPair& pair) {
                                    if (!robot_node->PublishStereo(pair))
                                      return camera::Delivery::kSkipped;
                                    if (rec) rec->Write(pair);
                                    trace.Add("left", pair.left.stamp, pair.sequence);
                                    trace.Add("right", pair.right.stamp, pair.sequence);
                                    return camera::Delivery::kSent;
                                  });
  pipeline.SetVideoDelivery([robot_node, &trace](const StereoVideoFrame& frame) {
    if (!robot_node->PublishStereoVideo(frame)) return camera::Delivery::kSkipped;
    trace.Add("left", frame.stamp, frame.sequence);
    trace.Add("right", frame.stamp, frame.sequence);
    return camera::Delivery::kSent;
  });
  if (devices.camera_options.video_rate.auto_repair_deadline && video.h264) {
    pipeline.SetRepairDeadlineSink([robot_node](Duration deadline, std::string* why) {
      return robot_node->SetVideoRepairDeadline(
          std::chrono::ceil<std::chrono::milliseconds>(deadline), why);
    });
  }
  if (rec && devices.camera_options.codec == camera::VideoCodec::kH264) {
    MOSTAR_LOG(WARNING) << "recording without camera images: recordings hold JPEG pairs, and "
                           "the camera codec is H264 (use codec JPEG to record video)";
  }
  pipeline_ptr = &pipeline;
  if (settings.roles.size() == 0) {
    MOSTAR_LOG(WARNING) << "no pilots in the role table (drive.roles): nobody can drive";
  }
  std::unique_ptr<drive::EstopLatchStore> estop_latch;
  if (!state_dir.empty()) {
    estop_latch = std::make_unique<drive::EstopLatchStore>(state_dir);
    MOSTAR_LOG(INFO) << "e-stop latch kept in " << estop_latch->path();
  } else {
    MOSTAR_LOG(INFO) << "e-stop latch not persisted (simulated robot without state_dir)";
  }
  RobotControllerDevices controlled;
  controlled.motors = devices.motors();
  controlled.laser = devices.laser();
  controlled.sonar = devices.sonar();
  controlled.bumpers = devices.bumpers.get();
  controlled.camera_health = [&pipeline] { return pipeline.Health(); };
  controlled.estop_latch = estop_latch.get();
  RobotController controller(ControllerOptionsFrom(config, settings, devices.intrinsics),
                             controlled, node.get(), clock, &trace);
  controller.SetRecorder(rec);
  controller_ptr = &controller;
  pipeline.Start();
  if (!controller.Start(&error)) {
    std::cerr << "robot_server: " << error << "\n";
    RequestStop();
  }
  MOSTAR_LOG(INFO) << "robot_server '" << config.robot_id() << "' running on DDS domain "
                   << dds_options.domain_id << " (" << dds_options.profile << "), source "
                   << ServerConfig::Source_Name(config.source());
  service::ServiceNotifier service;
  service.Ready("running on DDS domain " + std::to_string(dds_options.domain_id));
  const SteadyTime start = clock->SteadyNow();
  SteadyTime next_cycle = start;
  dds::NetworkCheck network_check({participant.get()});
  while (!StopRequested()) {
    next_cycle += settings.control_period;
    const SteadyTime now = clock->SteadyNow();
    service.Alive(now);  // systemd's watchdog: restarts robot_server if this loop stalls
    if (controller.Step(now) == StepResult::kWriteStalled) {
      MOSTAR_LOG(ERROR) << "a DDS write has been blocked for more than "
                        << config.dds().write_stall_exit_s()
                        << " s (DDS deadlock?): robot stopped, exiting with status 3 so that the "
                           "service manager restarts robot_server";
      trace.Flush();
      controller.SetRecorder(nullptr);
      if (recorder) recorder->Close(&error);
      std::fflush(nullptr);
      std::_Exit(3);  // an orderly teardown would wait on the blocked write
    }
    if (const Duration took = clock->SteadyNow() - now; took > 5 * settings.control_period) {
      MOSTAR_LOG_EVERY_SEC(WARNING, 5)
          << "control cycle took " << ToSeconds(took) * 1000 << " ms (period "
          << ToSeconds(settings.control_period) * 1000 << " ms): the robot reacted late";
    }
    if (TakeSignalRequest(SIGUSR2)) controller.ReleaseEstopLocally();
    if (network_check.RestartNeeded(std::chrono::steady_clock::now())) {
      MOSTAR_LOG(WARNING) << "robot_server: restarting in place to be reachable on this "
                             "host's new address (motors stopped, e-stop latch kept)";
      RequestRestart();
      break;
    }
    if (flags.duration_s > 0 && now - start > FromSeconds(flags.duration_s)) break;
    std::this_thread::sleep_until(next_cycle);
  }
  MOSTAR_LOG(INFO) << "robot_server stopping";
  if (!RestartRequested()) service.Stopping("stopping");
  controller.Stop();  // first: motors stopped and the e-stop latch recorded, whatever hangs next
  {
    // The DDS side (a camera write waiting for acknowledgements, entity deletion) can block
    // inside Fast DDS 2.9; SIGTERM must still end the program within 2 s (exit status 4).
    const ExitDeadline deadline(kDdsTeardownDeadline, 4, "robot_server", "DDS teardown");
    pipeline.Stop();
    controller_ptr = nullptr;
    node.reset();  // no callback runs after this
  }
  controller.SetRecorder(nullptr);
  if (recorder) {
    if (!recorder->Close(&error)) MOSTAR_LOG(ERROR) << "recording: " << error;
    const auto stats = recorder->stats();
    MOSTAR_LOG(INFO) << "recording closed: " << stats.records_written << " records, "
                     << stats.frames_dropped << " frames dropped";
  }
  trace.Flush();
  return 0;
}

}  // namespace
}  // namespace mostar::server

int main(int argc, char** argv) {
  mostar::RememberCommandLine(argc, argv);
  const int status = mostar::server::Run(argc, argv);
  return mostar::dds::EndProcess(mostar::RestartIfRequested(status, "robot_server"));
}
