// robot_server: the daemon on the robot. Wiring only: reads the configuration, chooses the
// concrete devices (test pattern, simulator, hardware), connects them to the safety governor,
// the pilot lease and the DDS node, and runs the control loop until SIGINT/SIGTERM.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>

#include "common/config/config_loader.h"
#include "common/dds/domain.h"
#include "common/dds/participant.h"
#include "common/log/log.h"
#include "common/log/stamp_trace.h"
#include "common/record/recording_reader.h"
#include "common/record/recording_writer.h"
#include "common/record/replay_player.h"
#include "common/service/service_notifier.h"
#include "common/time/rate_meter.h"
#include "robot_server/camera/camera_factory.h"
#include "robot_server/camera/camera_intrinsics.h"
#include "robot_server/camera/camera_pipeline.h"
#include "robot_server/drive/drive_config.h"
#include "robot_server/drive/odometry.h"
#include "robot_server/drive/pilot_lease.h"
#include "robot_server/drive/safety_governor.h"
#include "robot_server/drive/serial_drive_motors.h"
#include "robot_server/laser/lms200_scanner.h"
#include "robot_server/node/robot_node.h"
#include "robot_server/replay/replay_laser_scanner.h"
#include "robot_server/replay/replay_stereo_camera.h"
#include "robot_server/replay/replay_timeline.h"
#include "robot_server/server_config.pb.h"
#include "robot_server/sim/scene.h"
#include "robot_server/sim/sim_world.h"
#include "robot_server/sim_devices/sim_devices.h"
#include "robot_server/testpattern/test_pattern.h"

namespace mostar::server {
namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop = true; }

std::string DirectoryOf(const std::string& path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

std::string Resolve(const std::string& path, const std::string& base_dir) {
  if (path.empty() || path[0] == '/' || base_dir.empty()) return path;
  return base_dir + "/" + path;
}

// The devices of one source. Null members are absent.
struct Devices {
  std::unique_ptr<testpattern::KinematicRobot> pattern_robot;
  std::unique_ptr<sim::SimWorld> world;
  std::unique_ptr<sim::SimulatedLms200> sim_laser;
  std::unique_ptr<laser::LaserScanner> laser;  // HARDWARE or replay
  laser::LaserScanner* scanner = nullptr;      // the laser in use, if any
  std::unique_ptr<drive::DriveMotors> motors;
  std::unique_ptr<camera::StereoCamera> camera;
  camera::CameraPipelineOptions camera_options;
  // Intrinsics of each eye, published for the clients; empty when unknown.
  std::vector<CameraIntrinsicsInfo> intrinsics;
};

CameraIntrinsicsInfo InfoFromIntrinsics(const camera::CameraIntrinsics& k, Eye eye) {
  CameraIntrinsicsInfo info;
  info.frame_id = eye == Eye::kLeft ? "camera_left" : "camera_right";
  info.width_px = k.image_size.width;
  info.height_px = k.image_size.height;
  info.fx = k.camera_matrix(0, 0);
  info.fy = k.camera_matrix(1, 1);
  info.cx = k.camera_matrix(0, 2);
  info.cy = k.camera_matrix(1, 2);
  info.distortion = k.distortion;
  return info;
}

bool ReplaysCamera(const ServerConfig& config) {
  return config.camera().backend() == camera::CameraConfig::REPLAY;
}
bool ReplaysLaser(const ServerConfig& config) { return !config.laser().replay().file().empty(); }

// Built-in video sources (test pattern, simulator): the bitrate control of `camera.bitrate` when
// the configuration has one (e.g. a WAN target), else the defaults; JPEG quality starts at
// `initial_quality`.
void UseConfiguredBitrate(const ServerConfig& config, int initial_quality,
                          camera::CameraPipelineOptions* options) {
  if (config.camera().has_bitrate()) {
    const camera::CameraPipelineOptions configured = camera::MakePipelineOptions(config.camera());
    options->bitrate_classes = configured.bitrate_classes;
    options->bitrate = configured.bitrate;
  }
  options->bitrate.initial_quality =
      std::clamp(initial_quality, options->bitrate.min_quality, options->bitrate.max_quality);
}

// The devices of the configured source; a camera or laser that a replay replaces is not made.
bool MakeSourceDevices(const ServerConfig& config, const std::string& config_dir,
                       const Clock* clock, drive::DriveSettings* settings, Devices* devices,
                       std::string* error) {
  switch (config.source()) {
    case ServerConfig::TEST_PATTERN: {
      const TestPatternConfig& tp = config.test_pattern();
      testpattern::RoomOptions room;
      room.wheel_radius_m = settings->odometry.wheel_radius_m;
      room.track_width_m = settings->odometry.track_width_m;
      room.ticks_per_turn = static_cast<int>(settings->odometry.ticks_per_turn);
      settings->odometry.counter_bits = 16;
      auto robot = std::make_unique<testpattern::KinematicRobot>(room, clock);
      devices->camera = std::make_unique<testpattern::TestPatternCamera>(
          robot.get(), tp.width_px(), tp.height_px(), tp.frame_rate_hz(), clock);
      UseConfiguredBitrate(config, tp.jpeg_quality(), &devices->camera_options);
      devices->pattern_robot = std::move(robot);
      return true;
    }
    case ServerConfig::SIM: {
      if (config.scene_file().empty()) {
        *error = "source SIM needs a scene: --sim FILE or scene_file in the configuration";
        return false;
      }
      const std::string scene_path = Resolve(config.scene_file(), config_dir);
      sim::proto::Scene scene;
      if (!sim::LoadScene(scene_path, &scene, error)) return false;
      if (!sim::ValidateSimConfig(config.sim(), "sim", error)) return false;
      devices->world = sim::SimWorld::Create(scene, config.sim(), clock->Now(), error);
      if (!devices->world) return false;
      // Odometry uses the simulated robot's geometry.
      const auto& drive = devices->world->drive_params();
      settings->odometry.wheel_radius_m = drive.wheel_radius_m;
      settings->odometry.track_width_m = drive.track_width_m;
      settings->odometry.ticks_per_turn = drive.encoder_pulses_per_turn;
      settings->odometry.counter_bits = drive.encoder_counter_bits;
      settings->odometry.axle_x_m = drive.axle_x_m;
      devices->motors = std::make_unique<sim::SimDriveMotors>(devices->world.get(), clock);
      if (!ReplaysCamera(config)) {
        devices->camera = std::make_unique<sim::SimStereoCamera>(
            devices->world.get(), config.test_pattern().frame_rate_hz(), clock);
      }
      UseConfiguredBitrate(config, config.test_pattern().jpeg_quality(), &devices->camera_options);
      const sim::LaserCameraCalibration& truth = devices->world->calibration();
      for (const Eye eye : {Eye::kLeft, Eye::kRight}) {
        CameraIntrinsicsInfo info;
        info.frame_id = eye == Eye::kLeft ? "camera_left" : "camera_right";
        info.width_px = truth.width_px;
        info.height_px = truth.height_px;
        info.fx = info.fy = truth.focal_px;
        info.cx = truth.cx_px;
        info.cy = eye == Eye::kLeft ? truth.cy_px : truth.right_cy_px;
        info.distortion = {truth.k1, truth.k2, 0, 0, 0};
        devices->intrinsics.push_back(info);
      }
      if (ReplaysLaser(config)) return true;
      const std::string link =
          config.sim_laser_link() + "-" + std::to_string(static_cast<long>(getpid()));
      devices->sim_laser =
          sim::SimulatedLms200::Create(devices->world.get(), config.laser(), link, clock, error);
      if (!devices->sim_laser) return false;
      devices->scanner = devices->sim_laser->scanner();
      return true;
    }
    case ServerConfig::HARDWARE: {
      if (!ReplaysCamera(config)) {
        devices->camera = camera::MakeStereoCamera(config.camera(), clock, error);
        if (!devices->camera) return false;
      }
      devices->camera_options = camera::MakePipelineOptions(config.camera());
      const std::string files[2] = {config.camera().left_intrinsics_file(),
                                    config.camera().right_intrinsics_file()};
      for (int e = 0; e < 2 && !files[0].empty() && !files[1].empty(); ++e) {
        camera::CameraIntrinsics k;
        if (!camera::LoadCameraIntrinsics(Resolve(files[e], config_dir), &k, error)) return false;
        const camera::StereoCameraInfo camera_info =
            devices->camera ? devices->camera->Info() : camera::StereoCameraInfo{};
        if (camera_info.width_px > 0) k = k.ScaledTo({camera_info.width_px, camera_info.height_px});
        devices->intrinsics.push_back(InfoFromIntrinsics(k, e == 0 ? Eye::kLeft : Eye::kRight));
      }
      if (!ReplaysLaser(config)) {
        devices->laser = laser::MakeSerialLms200Scanner(config.laser(), clock);
        if (!devices->laser) {
          *error = "cannot create the LMS200 driver for " + config.laser().port();
          return false;
        }
        devices->scanner = devices->laser.get();
      }
      auto motors = drive::SerialDriveMotors::Open(*clock, settings->motors, error);
      if (!motors) return false;
      devices->motors = std::move(motors);
      return true;
    }
  }
  *error = "unknown source";
  return false;
}

// The source's devices, then the replay backends (robot_server/replay) in place of its camera
// (camera.backend REPLAY) and laser (laser.replay.file): the live pipeline, scan path, motors
// and odometry run on recorded images and scans. Both replays of one file share a timeline.
bool MakeDevices(const ServerConfig& config, const std::string& config_dir, const Clock* clock,
                 drive::DriveSettings* settings, Devices* devices, std::string* error) {
  if (!MakeSourceDevices(config, config_dir, clock, settings, devices, error)) return false;
  std::map<std::string, std::shared_ptr<replay::ReplayTimeline>> timelines;
  auto timeline_for = [&](const std::string& key, const std::string& path, double rate,
                          bool loop) -> std::shared_ptr<replay::ReplayTimeline> {
    auto it = timelines.find(path);
    if (it != timelines.end()) {
      if (it->second->options().rate != rate || it->second->options().loop != loop) {
        *error = key + ": camera.replay and laser.replay of " + path +
                 " must have the same rate and loop";
        return nullptr;
      }
      return it->second;
    }
    replay::ReplayTimelineOptions options;
    options.rate = rate;
    options.loop = loop;
    auto timeline = replay::ReplayTimeline::ForRecording(path, *clock, options, error);
    if (!timeline) {
      *error = key + ": " + *error;
      return nullptr;
    }
    return timelines[path] = timeline;
  };
  // The options common to the replay devices; false (error set) when the file is unusable.
  auto replay_device = [&](const std::string& key, const std::string& file, double rate, bool loop,
                           replay::ReplayDeviceOptions* options) {
    options->path = Resolve(file, config_dir);
    options->timeline = timeline_for(key, options->path, rate, loop);
    options->clock = clock;
    return options->timeline != nullptr;
  };
  if (ReplaysCamera(config)) {
    if (!camera::ValidateCameraConfig(config.camera(), error)) {
      *error = "camera." + *error;
      return false;
    }
    const camera::ReplayCameraConfig& r = config.camera().replay();
    replay::ReplayStereoCamera::Options options;
    if (!replay_device("camera.replay.file", r.file(), r.rate(), r.loop(), &options)) return false;
    devices->camera = std::make_unique<replay::ReplayStereoCamera>(options);
    devices->camera_options = camera::MakePipelineOptions(config.camera());
    MOSTAR_LOG(INFO) << "camera: replaying " << options.path << " at " << r.rate() << "x"
                     << (r.loop() ? ", looping" : "");
  }
  if (ReplaysLaser(config)) {
    const laser::LaserReplayConfig& r = config.laser().replay();
    replay::ReplayLaserScanner::Options options;
    if (!replay_device("laser.replay.file", r.file(), r.rate(), r.loop(), &options)) return false;
    devices->laser = std::make_unique<replay::ReplayLaserScanner>(options);
    devices->scanner = devices->laser.get();
    MOSTAR_LOG(INFO) << "laser: replaying " << options.path << " at " << r.rate() << "x"
                     << (r.loop() ? ", looping" : "");
  }
  return true;
}

// Publishes a recording on DDS as the robot would, until its end (or forever with `loop`) or a
// signal. Stamps are those of the recording. Velocity commands are not acted on.
// Replay controls read line by line from standard input (when it is open): "p" pause/resume,
// "s [N]" step N records while paused, "r RATE" speed, "q" stop. Unknown lines are reported.
void ReadReplayControls(std::shared_ptr<record::ReplayPlayer> player) {
  std::string line;
  while (!g_stop && std::getline(std::cin, line)) {
    std::istringstream in(line);
    std::string command;
    in >> command;
    if (command == "p") {
      if (player->paused()) {
        player->Resume();
      } else {
        player->Pause();
      }
      MOSTAR_LOG(INFO) << "replay " << (player->paused() ? "paused" : "resumed");
    } else if (command == "s") {
      int count = 1;
      in >> count;
      player->Step(std::max(1, count));
    } else if (command == "r") {
      double rate = 0;
      if (in >> rate && rate > 0) {
        player->SetRate(rate);
        MOSTAR_LOG(INFO) << "replay rate " << rate;
      } else {
        MOSTAR_LOG(WARNING) << "replay control: 'r' needs a positive rate";
      }
    } else if (command == "q") {
      g_stop = true;
    } else if (!command.empty()) {
      MOSTAR_LOG(WARNING) << "replay control: unknown command '" << command
                          << "' (p pause/resume, s [N] step, r RATE, q quit)";
    }
  }
}

int RunReplay(const std::string& path, double rate, bool loop, bool start_paused, RobotNode* node,
              StampTrace* trace, double duration_s) {
  std::string error;
  auto reader = record::RecordingReader::Open(path, &error);
  if (!reader) {
    std::cerr << "robot_server: cannot replay: " << error << "\n";
    return 2;
  }
  record::ReplayOptions options;
  options.rate = rate;
  options.loop = loop;
  options.start_paused = start_paused;
  if (!options.IsValid(&error)) {
    std::cerr << "robot_server: --replay-rate: " << error << "\n";
    return 2;
  }
  const Clock* clock = &SystemClock::Instance();
  // Shared with the stdin reader, which may outlive this function (blocked in getline).
  auto player = std::make_shared<record::ReplayPlayer>(reader.get(), *clock, options);
  std::shared_ptr<record::RecordingReader> reader_keepalive = std::move(reader);
  MOSTAR_LOG(INFO) << "replaying " << path << " (robot '" << reader_keepalive->info().robot_id
                   << "') at " << rate << "x" << (loop ? ", looping" : "");
  const SteadyTime start = clock->SteadyNow();
  uint64_t published = 0;
  // Controls on standard input; detached because getline cannot be interrupted.
  std::thread([player, reader_keepalive] { ReadReplayControls(player); }).detach();
  service::ServiceNotifier service;
  service.Ready("replaying " + path);
  while (!g_stop && !player->finished()) {
    service.Alive(clock->SteadyNow());
    for (const record::RecordedMessage& m : player->PollDue()) {
      ++published;
      std::visit(
          [&](const auto& p) {
            using T = std::decay_t<decltype(p)>;
            if constexpr (std::is_same_v<T, record::RecordedImage>) {
              node->PublishImage(p.eye, p.image);
              trace->Add(p.eye == Eye::kLeft ? "left" : "right", p.image.stamp, p.pair_sequence);
            } else if constexpr (std::is_same_v<T, LaserScan>) {
              node->PublishScan(p);
              trace->Add("scan", p.stamp, p.sequence);
            } else if constexpr (std::is_same_v<T, Odometry>) {
              node->PublishOdometry(p);
            } else if constexpr (std::is_same_v<T, RobotHealth>) {
              node->PublishHealth(p);
            } else if constexpr (std::is_same_v<T, ControlLease>) {
              node->PublishLease(p);
            }
          },
          m.payload);
    }
    if (duration_s > 0 && clock->SteadyNow() - start > FromSeconds(duration_s)) break;
    const std::optional<SteadyTime> next = player->NextDueTime();
    const SteadyTime wake = clock->SteadyNow() + std::chrono::milliseconds(50);
    std::this_thread::sleep_until(next ? std::min(*next, wake) : wake);
  }
  if (reader_keepalive->damage()) {
    MOSTAR_LOG(WARNING) << "recording damaged at byte " << reader_keepalive->damage()->offset
                        << ": " << reader_keepalive->damage()->reason
                        << " (replayed everything before it)";
  }
  MOSTAR_LOG(INFO) << "replay done: " << published << " records published";
  service.Stopping("replay done");
  trace->Flush();
  return 0;
}

// The robot's DDS side as a health device: video ack-clock and outbox counters.
DeviceHealth NetworkHealth(const RobotNode& node, const dds::Participant& participant) {
  DeviceHealth network;
  network.name = "network";
  network.counters = {
      {"video_pairs_sent", node.pairs_sent()},
      {"video_pairs_skipped", node.pairs_skipped()},
      {"video_lanes_reclaimed", node.lanes_reclaimed()},
      {"outbox_dropped", node.outbox_dropped()},
      {"frame_subscribers", static_cast<uint64_t>(node.frame_subscribers())},
      {"tcp_sockets_guarded", static_cast<uint64_t>(participant.tcp_sockets_guarded())}};
  return network;
}

int Run(int argc, char** argv) {
  CLI::App app{
      "robot_server: publishes the robot's stereo frames, laser scans, odometry and "
      "health over DDS and drives it from one pilot's velocity commands."};
  std::string config_path;
  int domain = -1;
  std::string dds_profile;
  std::string source;
  std::string scene;
  double duration_s = 0;
  std::string log_level = "info";
  std::string trace_path;
  std::string record_path;
  std::string replay_path;
  double replay_rate = 1.0;
  bool replay_loop = false;
  bool replay_paused = false;
  std::string replay_sensors;
  app.add_option("--record", record_path, "record everything published (and accepted commands)");
  auto* replay_option =
      app.add_option("--replay", replay_path, "publish this recording instead of live devices")
          ->check(CLI::ExistingFile);
  app.add_option("--replay-sensors", replay_sensors,
                 "camera and laser from this recording (with --replay-rate, --loop), motors "
                 "and odometry from the source: the live pipeline on recorded data")
      ->check(CLI::ExistingFile)
      ->excludes(replay_option);
  app.add_option("--replay-rate", replay_rate, "replay speed factor")->check(CLI::PositiveNumber);
  app.add_flag("--loop", replay_loop, "replay (--replay, --replay-sensors) in a loop");
  app.add_flag("--replay-paused", replay_paused,
               "start the replay paused; control it on stdin: p pause/resume, s [N] step, "
               "r RATE, q quit");
  app.add_option("-c,--config", config_path, "server configuration (protobuf text format)")
      ->check(CLI::ExistingFile);
  app.add_option("--domain", domain, "DDS domain id (default: config, then MOSTAR_DDS_DOMAIN)")
      ->check(CLI::Range(0, 232));
  app.add_option("--dds-profile", dds_profile, "'loopback' or a Fast DDS XML profiles file");
  app.add_option("--source", source, "test_pattern | sim | hardware (overrides the config)")
      ->check(CLI::IsMember({"test_pattern", "sim", "hardware"}));
  app.add_option("--sim", scene, "run the simulated robot in this scene (implies --source sim)")
      ->check(CLI::ExistingFile);
  app.add_option("--duration", duration_s, "stop after this many seconds (0 = run until signal)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--log-level", log_level, "debug | info | warning | error")
      ->check(CLI::IsMember({"debug", "info", "warning", "error"}));
  app.add_option("--trace", trace_path, "write published stamps and accepted commands to this CSV");
  CLI11_PARSE(app, argc, argv);

  LogLevel level;
  ParseLogLevel(log_level, &level);
  SetLogLevel(level);

  ServerConfig config;
  std::string error;
  if (!config_path.empty() && !LoadTextConfig(config_path, &config, &error)) {
    std::cerr << "robot_server: bad configuration: " << error << "\n";
    return 2;
  }
  const std::string config_dir = config_path.empty() ? "" : DirectoryOf(config_path);
  if (source == "test_pattern") config.set_source(ServerConfig::TEST_PATTERN);
  if (source == "sim") config.set_source(ServerConfig::SIM);
  if (source == "hardware") config.set_source(ServerConfig::HARDWARE);
  if (!scene.empty()) {
    config.set_source(ServerConfig::SIM);
    config.set_scene_file(scene);
  }
  if (!replay_sensors.empty()) {
    // Relative to the working directory, like every path on the command line.
    if (replay_sensors[0] != '/') {
      char cwd[4096];
      if (getcwd(cwd, sizeof(cwd)) != nullptr) {
        replay_sensors = std::string(cwd) + "/" + replay_sensors;
      }
    }
    camera::CameraConfig* camera_config = config.mutable_camera();
    camera_config->set_backend(camera::CameraConfig::REPLAY);
    camera_config->mutable_replay()->set_file(replay_sensors);
    camera_config->mutable_replay()->set_rate(replay_rate);
    camera_config->mutable_replay()->set_loop(replay_loop);
    laser::LaserReplayConfig* laser_replay = config.mutable_laser()->mutable_replay();
    laser_replay->set_file(replay_sensors);
    laser_replay->set_rate(replay_rate);
    laser_replay->set_loop(replay_loop);
  }
  const std::string scene_dir = scene.empty() ? config_dir : "";
  drive::DriveSettings settings;
  if (!drive::DriveSettingsFromProto(config.drive(), &settings, &error)) {
    std::cerr << "robot_server: bad configuration: drive: " << error << "\n";
    return 2;
  }
  StampTrace trace;
  if (!trace.Open(trace_path)) {
    std::cerr << "robot_server: cannot write " << trace_path << "\n";
    return 2;
  }

  const Clock* clock = &SystemClock::Instance();
  if (!replay_path.empty()) {
    dds::ParticipantOptions replay_dds;
    replay_dds.domain_id =
        domain >= 0 ? domain : dds::DomainIdFromEnvironment(config.dds().domain_id());
    replay_dds.profile = dds_profile.empty() ? config.dds().profile() : dds_profile;
    replay_dds.name = "robot";
    replay_dds.tcp_user_timeout_ms = config.dds().tcp_user_timeout_ms();
    auto replay_participant = dds::Participant::Create(replay_dds, &error);
    if (!replay_participant) {
      std::cerr << "robot_server: " << error << "\n";
      return 1;
    }
    auto replay_node = RobotNode::Create(replay_participant.get(), {}, clock, &error);
    if (!replay_node) {
      std::cerr << "robot_server: " << error << "\n";
      return 1;
    }
    std::signal(SIGINT, OnSignal);
    std::signal(SIGTERM, OnSignal);
    return RunReplay(replay_path, replay_rate, replay_loop, replay_paused, replay_node.get(),
                     &trace, duration_s);
  }
  Devices devices;
  if (!MakeDevices(config, scene_dir, clock, &settings, &devices, &error)) {
    std::cerr << "robot_server: " << error << "\n";
    return 2;
  }
  drive::DriveMotors* motors =
      devices.pattern_robot ? devices.pattern_robot.get() : devices.motors.get();

  dds::ParticipantOptions dds_options;
  dds_options.domain_id =
      domain >= 0 ? domain : dds::DomainIdFromEnvironment(config.dds().domain_id());
  dds_options.profile = dds_profile.empty() ? config.dds().profile() : dds_profile;
  dds_options.name = "robot";
  dds_options.tcp_user_timeout_ms = config.dds().tcp_user_timeout_ms();
  auto participant = dds::Participant::Create(dds_options, &error);
  if (!participant) {
    std::cerr << "robot_server: " << error << "\n";
    return 1;
  }

  drive::PilotLease lease(*clock, settings.roles);
  drive::SafetyGovernor governor(*clock, settings.safety);
  if (settings.roles.size() == 0) {
    MOSTAR_LOG(WARNING) << "no pilots in the role table (drive.roles): nobody can drive";
  }
  std::mutex command_mutex;
  std::map<std::string, SteadyTime> last_command_from;  // for holder liveliness
  std::unique_ptr<RobotNode> node;
  std::atomic<bool> lease_changed{true};
  std::atomic<record::RecordingWriter*> recorder_ptr{nullptr};  // set once recording starts

  RobotNode::Callbacks callbacks;
  callbacks.on_command = [&](const VelocityCommand& cmd) {
    {
      std::lock_guard<std::mutex> lock(command_mutex);
      last_command_from[cmd.sender_id] = clock->SteadyNow();
    }
    const std::optional<Duration> offset =
        node ? node->RobotMinusClient(cmd.sender_id) : std::nullopt;
    const drive::CommandVerdict verdict = governor.HandleCommand(cmd, offset);
    if (verdict == drive::CommandVerdict::kAccepted) {
      trace.Add("command", cmd.stamp, cmd.sequence);
      trace.Add("command_rx", clock->Now(), cmd.sequence);  // robot clock, on arrival
      if (recorder_ptr != nullptr) recorder_ptr.load()->Write(cmd);
    } else {
      MOSTAR_LOG_EVERY_SEC(DEBUG, 2) << "command " << cmd.sequence << " from " << cmd.sender_id
                                     << ": " << drive::CommandVerdictName(verdict);
    }
  };
  callbacks.on_estop = [&](const EmergencyStop& stop) {
    const bool authorised =
        stop.engage ? lease.MayEngageEstop(stop.sender_id)
                    : lease.MayReleaseEstop(stop.sender_id, governor.status().estop_engaged_by);
    governor.HandleEmergencyStop(stop, authorised);
    MOSTAR_LOG(WARNING) << "emergency stop " << (stop.engage ? "engage" : "release") << " from "
                        << stop.sender_id << (authorised ? "" : " refused (not authorised)");
  };
  callbacks.on_control_request = [&](const ControlRequest& request) {
    const drive::LeaseDecision decision = lease.HandleRequest(request);
    governor.SetLeaseHolder(lease.holder());
    lease_changed = true;
    MOSTAR_LOG(INFO) << "control " << (request.take ? "take" : "release") << " by "
                     << request.sender_id << ": " << drive::LeaseDecisionName(decision)
                     << "; holder now '" << lease.holder() << "'";
  };
  RobotNode::VideoOptions video;
  video.window_pairs = config.dds().video_window_pairs();
  video.lane_timeout = std::chrono::milliseconds(config.dds().video_lane_timeout_ms());
  node = RobotNode::Create(participant.get(), callbacks, clock, &error, video);
  if (!node) {
    std::cerr << "robot_server: " << error << "\n";
    return 1;
  }

  std::unique_ptr<record::RecordingWriter> recorder;
  if (!record_path.empty()) {
    record::RecordingInfo info;
    info.robot_id = config.robot_id();
    info.metadata.emplace_back("source", ServerConfig::Source_Name(config.source()));
    info.metadata.emplace_back("scene", config.scene_file());
    recorder = record::RecordingWriter::Open(record_path, {}, info, *clock, &error);
    if (!recorder) {
      std::cerr << "robot_server: cannot record: " << error << "\n";
      return 2;
    }
    MOSTAR_LOG(INFO) << "recording to " << record_path;
  }
  record::RecordingWriter* rec = recorder.get();
  recorder_ptr = rec;

  camera::CameraPipeline pipeline(std::move(devices.camera), devices.camera_options,
                                  [&node, &trace, rec](const CompressedStereoPair& pair) {
                                    if (!node->PublishStereo(pair)) {
                                      return camera::Delivery::kSkipped;
                                    }
                                    if (rec) rec->Write(pair);
                                    trace.Add("left", pair.left.stamp, pair.sequence);
                                    trace.Add("right", pair.right.stamp, pair.sequence);
                                    return camera::Delivery::kSent;
                                  });
  drive::OdometryIntegrator odometry(settings.odometry);

  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  pipeline.Start();

  auto publish_scan = [&](const LaserScan& scan) {
    governor.SetLaserScan(scan);
    node->PublishScan(scan);
    if (rec) rec->Write(scan);
    trace.Add("scan", scan.stamp, scan.sequence);
  };
  std::thread pattern_scan_thread;
  if (devices.pattern_robot && devices.scanner == nullptr) {
    pattern_scan_thread = std::thread([&] {
      uint64_t sequence = 0;
      const Duration period = FromSeconds(1.0 / config.test_pattern().scan_rate_hz());
      SteadyTime next = clock->SteadyNow();
      while (!g_stop) {
        next += period;
        publish_scan(testpattern::SyntheticScan(*devices.pattern_robot, clock->Now(), ++sequence));
        std::this_thread::sleep_until(next);
      }
    });
  }
  if (devices.scanner != nullptr && !devices.scanner->Start(publish_scan, &error)) {
    std::cerr << "robot_server: laser: " << error << "\n";
    g_stop = true;
  }

  MOSTAR_LOG(INFO) << "robot_server '" << config.robot_id() << "' running on DDS domain "
                   << dds_options.domain_id << " (" << dds_options.profile << "), source "
                   << ServerConfig::Source_Name(config.source());
  service::ServiceNotifier service;
  service.Ready("running on DDS domain " + std::to_string(dds_options.domain_id));
  const SteadyTime start = clock->SteadyNow();
  const Duration write_stall_limit = FromSeconds(config.dds().write_stall_exit_s());
  const Duration control_period = settings.control_period;
  const Duration health_period = FromSeconds(config.health_period_s());
  const Duration lease_period = FromSeconds(config.lease_period_s());
  const Duration holder_timeout = FromSeconds(config.holder_timeout_s());
  SteadyTime next_health = start;
  SteadyTime next_lease = start;
  SteadyTime next_cycle = start;
  RateMeter control_rate;
  uint64_t motor_errors = 0;
  while (!g_stop) {
    next_cycle += control_period;
    const SteadyTime now = clock->SteadyNow();
    service.Alive(now);  // systemd's watchdog: restarts robot_server if this loop stalls
    // A holder that went silent loses the lease: nobody inherits motion.
    const std::string holder = lease.holder();
    if (!holder.empty()) {
      std::lock_guard<std::mutex> lock(command_mutex);
      auto it = last_command_from.find(holder);
      const SteadyTime last = it == last_command_from.end() ? start : it->second;
      if (now - last > holder_timeout && lease.OnLivelinessLost(holder)) {
        governor.OnLinkLost(holder);
        governor.SetLeaseHolder(lease.holder());
        lease_changed = true;
        MOSTAR_LOG(WARNING) << "pilot '" << holder << "' went silent: lease released";
      }
    }
    if (write_stall_limit > Duration::zero() &&
        node->BlockedWriteDuration(now) > write_stall_limit) {
      MOSTAR_LOG(ERROR) << "a DDS write has been blocked for more than "
                        << config.dds().write_stall_exit_s()
                        << " s (DDS deadlock?): stopping the robot and exiting with status 3 so "
                           "that the service manager restarts robot_server";
      motors->Stop(&error);
      trace.Flush();
      recorder_ptr = nullptr;
      if (recorder) recorder->Close(&error);
      std::fflush(nullptr);
      std::_Exit(3);  // orderly teardown would wait on the blocked write
    }
    const drive::GovernorOutput out = governor.Update();
    trace.Add("drive_out_mmps", clock->Now(),
              static_cast<uint64_t>(std::llround(std::abs(out.linear_mps) * 1000)));
    if (!motors->SetVelocity(out.linear_mps, out.angular_radps, &error)) {
      ++motor_errors;
      MOSTAR_LOG_EVERY_SEC(WARNING, 5) << "motors: " << error;
    }
    drive::EncoderReading reading;
    if (motors->ReadEncoders(&reading, &error) && odometry.AddReading(reading)) {
      node->PublishOdometry(odometry.odometry());
      if (rec) rec->Write(odometry.odometry());
      trace.Add("odom_x_mm", odometry.odometry().stamp,
                static_cast<uint64_t>(std::max(0.0, odometry.odometry().pose.x_m * 1000)));
    }
    control_rate.Tick(now);
    if (lease_changed.exchange(false) || now >= next_lease) {
      next_lease = now + lease_period;
      const ControlLease current = lease.lease();
      node->PublishLease(current);
      for (size_t e = 0; e < devices.intrinsics.size(); ++e) {
        CameraIntrinsicsInfo info = devices.intrinsics[e];
        info.stamp = clock->Now();
        node->PublishCameraInfo(e == 0 ? Eye::kLeft : Eye::kRight, info);
      }
      trace.Add(("lease:" + current.holder_id).c_str(), current.stamp, current.lease_sequence);
      if (rec) rec->Write(current);
    }
    if (now >= next_health) {
      next_health = now + health_period;
      RobotHealth health;
      health.stamp = clock->Now();
      health.robot_id = config.robot_id();
      governor.FillRobotHealth(&health);
      health.lease_holder = lease.holder();
      health.devices.push_back(pipeline.Health());
      if (devices.scanner != nullptr) health.devices.push_back(devices.scanner->Health());
      health.devices.push_back(governor.Health());
      const drive::MotorStatus status = motors->Status();
      DeviceHealth drive_health;
      drive_health.name = "drive";
      drive_health.rate_hz = static_cast<float>(control_rate.RateHz(now));
      drive_health.state = !status.link_ok ? DeviceState::kError
                           : status.fault  ? DeviceState::kWarn
                                           : DeviceState::kOk;
      if (status.fault) drive_health.message = devices.world ? "collision" : "motor fault";
      if (!status.link_ok) drive_health.message = "no link to the motor board";
      drive_health.counters = {{"motor_errors", motor_errors},
                               {"odometry_glitches", odometry.stats().glitches}};
      if (devices.world) {
        const sim::RobotState sim_state = devices.world->StateAt(clock->Now());
        drive_health.counters.emplace_back("collisions", sim_state.collision_count);
      }
      health.devices.push_back(drive_health);
      health.devices.push_back(NetworkHealth(*node, *participant));
      node->PublishHealth(health);
      if (rec) rec->Write(health);
    }
    if (duration_s > 0 && now - start > FromSeconds(duration_s)) break;
    std::this_thread::sleep_until(next_cycle);
  }
  g_stop = true;
  MOSTAR_LOG(INFO) << "robot_server stopping";
  service.Stopping("stopping");
  motors->Stop(&error);
  if (pattern_scan_thread.joinable()) pattern_scan_thread.join();
  if (devices.scanner != nullptr) devices.scanner->Stop();
  pipeline.Stop();
  recorder_ptr = nullptr;
  if (recorder) {
    if (!recorder->Close(&error)) {
      MOSTAR_LOG(ERROR) << "recording: " << error;
    }
    const auto stats = recorder->stats();
    MOSTAR_LOG(INFO) << "recording closed: " << stats.records_written << " records, "
                     << stats.frames_dropped << " frames dropped";
  }
  trace.Flush();
  return 0;
}

}  // namespace
}  // namespace mostar::server

int main(int argc, char** argv) { return mostar::dds::EndProcess(mostar::server::Run(argc, argv)); }
