// robot_server: the daemon on the robot. Wiring only: reads the configuration, chooses the
// concrete devices, connects them to the DDS node, runs the control loop until SIGINT/SIGTERM.
#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>
#include <iostream>
#include <memory>
#include <mutex>
#include <thread>

#include "common/config/config_loader.h"
#include "common/dds/domain.h"
#include "common/dds/participant.h"
#include "common/log/log.h"
#include "common/log/stamp_trace.h"
#include "common/time/rate_meter.h"
#include "robot_server/camera/camera_pipeline.h"
#include "robot_server/drive/odometry.h"
#include "robot_server/node/robot_node.h"
#include "robot_server/server_config.pb.h"
#include "robot_server/testpattern/test_pattern.h"

namespace mostar::server {
namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop = true; }

// The latest pilot command and the deadman rule: the robot moves only while valid commands
// keep arriving.
class CommandGate {
 public:
  CommandGate(const Clock* clock, double deadman_s, double max_age_s)
      : clock_(clock), deadman_(FromSeconds(deadman_s)), max_age_(FromSeconds(max_age_s)) {}

  // True when the command was accepted.
  bool OnCommand(const VelocityCommand& cmd) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (cmd.sequence <= last_sequence_ && cmd.sender_id == last_sender_) {
      ++rejected_;
      return false;
    }
    const Duration age = clock_->Now() - cmd.stamp;
    if (age > max_age_) {
      ++rejected_;
      return false;
    }
    last_sender_ = cmd.sender_id;
    last_sequence_ = cmd.sequence;
    latest_ = cmd;
    received_at_ = clock_->SteadyNow();
    have_command_ = true;
    ++accepted_;
    return true;
  }
  // (v, w) to apply now; zero once the deadman period has passed without a command.
  std::pair<double, double> Target(WatchdogState* state) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!have_command_) {
      *state = WatchdogState::kIdle;
      return {0, 0};
    }
    if (clock_->SteadyNow() - received_at_ > deadman_) {
      *state = WatchdogState::kStopping;
      return {0, 0};
    }
    *state = WatchdogState::kDriving;
    if (!latest_.enable) return {0, 0};
    return {latest_.linear_mps, latest_.angular_radps};
  }
  void Fill(RobotHealth* health) {
    std::lock_guard<std::mutex> lock(mutex_);
    health->lease_holder = last_sender_;
    health->last_command_sequence = last_sequence_;
    health->last_command_age_s =
        have_command_ ? static_cast<float>(ToSeconds(clock_->SteadyNow() - received_at_)) : -1.f;
  }

 private:
  const Clock* clock_;
  const Duration deadman_;
  const Duration max_age_;
  std::mutex mutex_;
  VelocityCommand latest_;
  std::string last_sender_;
  uint64_t last_sequence_ = 0;
  SteadyTime received_at_;
  bool have_command_ = false;
  uint64_t accepted_ = 0;
  uint64_t rejected_ = 0;
};

int Run(int argc, char** argv) {
  CLI::App app{"robot_server: publishes the robot's stereo frames, laser scans, odometry and "
               "health over DDS and drives it from one pilot's velocity commands."};
  std::string config_path;
  int domain = -1;
  std::string dds_profile;
  std::string source;
  double duration_s = 0;
  std::string log_level = "info";
  std::string trace_path;
  app.add_option("--trace", trace_path, "write published stamps and accepted commands to this CSV");
  app.add_option("-c,--config", config_path, "server configuration (protobuf text format)")
      ->check(CLI::ExistingFile);
  app.add_option("--domain", domain, "DDS domain id (default: config, then MOSTAR_DDS_DOMAIN)")
      ->check(CLI::Range(0, 232));
  app.add_option("--dds-profile", dds_profile, "'loopback' or a Fast DDS XML profiles file");
  app.add_option("--source", source, "test_pattern | sim | hardware (overrides the config)")
      ->check(CLI::IsMember({"test_pattern", "sim", "hardware"}));
  app.add_option("--duration", duration_s, "stop after this many seconds (0 = run until signal)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--log-level", log_level, "debug | info | warning | error")
      ->check(CLI::IsMember({"debug", "info", "warning", "error"}));
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
  if (source == "test_pattern") config.set_source(ServerConfig::TEST_PATTERN);
  if (source == "sim") config.set_source(ServerConfig::SIM);
  if (source == "hardware") config.set_source(ServerConfig::HARDWARE);
  if (config.source() != ServerConfig::TEST_PATTERN) {
    std::cerr << "robot_server: source " << ServerConfig::Source_Name(config.source())
              << " is not available in this build\n";
    return 2;
  }

  dds::ParticipantOptions dds_options;
  dds_options.domain_id = domain >= 0 ? domain
                                      : dds::DomainIdFromEnvironment(config.dds().domain_id());
  dds_options.profile = dds_profile.empty() ? config.dds().profile() : dds_profile;
  dds_options.name = "robot";
  auto participant = dds::Participant::Create(dds_options, &error);
  if (!participant) {
    std::cerr << "robot_server: " << error << "\n";
    return 1;
  }

  StampTrace trace;
  if (!trace.Open(trace_path)) {
    std::cerr << "robot_server: cannot write " << trace_path << "\n";
    return 2;
  }
  const Clock* clock = &SystemClock::Instance();
  CommandGate gate(clock, config.deadman_s(), config.max_command_age_s());
  RobotNode::Callbacks callbacks;
  callbacks.on_command = [&gate, &trace](const VelocityCommand& cmd) {
    if (gate.OnCommand(cmd)) trace.Add("command", cmd.stamp, cmd.sequence);
  };
  auto node = RobotNode::Create(participant.get(), callbacks, clock, &error);
  if (!node) {
    std::cerr << "robot_server: " << error << "\n";
    return 1;
  }

  // Devices (test pattern source).
  const TestPatternConfig& tp = config.test_pattern();
  auto robot = std::make_unique<testpattern::KinematicRobot>(testpattern::RoomOptions{}, clock);
  auto camera = std::make_unique<testpattern::TestPatternCamera>(
      robot.get(), tp.width_px(), tp.height_px(), tp.frame_rate_hz(), clock);
  camera::CameraPipelineOptions camera_options;
  camera_options.bitrate.initial_quality = tp.jpeg_quality();
  camera::CameraPipeline pipeline(std::move(camera), camera_options,
                                  [&node, &trace](const CompressedStereoPair& pair) {
                                    if (!node->PublishStereo(pair)) {
                                      return camera::Delivery::kSkipped;
                                    }
                                    trace.Add("left", pair.left.stamp, pair.sequence);
                                    trace.Add("right", pair.right.stamp, pair.sequence);
                                    return camera::Delivery::kSent;
                                  });
  drive::OdometryOptions odom_options;
  drive::OdometryIntegrator odometry(odom_options);

  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  pipeline.Start();

  std::thread scan_thread([&] {
    uint64_t sequence = 0;
    const Duration period = FromSeconds(1.0 / tp.scan_rate_hz());
    SteadyTime next = clock->SteadyNow();
    while (!g_stop) {
      next += period;
      const LaserScan scan = testpattern::SyntheticScan(*robot, clock->Now(), ++sequence);
      node->PublishScan(scan);
      trace.Add("scan", scan.stamp, scan.sequence);
      std::this_thread::sleep_until(next);
    }
  });

  MOSTAR_LOG(INFO) << "robot_server '" << config.robot_id() << "' running on DDS domain "
                   << dds_options.domain_id << " (" << dds_options.profile << "), source "
                   << ServerConfig::Source_Name(config.source());
  const SteadyTime start = clock->SteadyNow();
  const Duration control_period = FromSeconds(config.control_period_s());
  const Duration health_period = FromSeconds(config.health_period_s());
  SteadyTime next_health = start;
  SteadyTime next_cycle = start;
  RateMeter control_rate;
  while (!g_stop) {
    next_cycle += control_period;
    WatchdogState state;
    const auto [v, w] = gate.Target(&state);
    robot->SetVelocity(v, w, &error);
    drive::EncoderReading reading;
    if (robot->ReadEncoders(&reading, &error) && odometry.AddReading(reading)) {
      node->PublishOdometry(odometry.odometry());
      trace.Add("odom_x_mm", odometry.odometry().stamp,
                static_cast<uint64_t>(std::max(0.0, odometry.odometry().pose.x_m * 1000)));
    }
    const SteadyTime now = clock->SteadyNow();
    control_rate.Tick(now);
    if (now >= next_health) {
      next_health = now + health_period;
      RobotHealth health;
      health.stamp = clock->Now();
      health.robot_id = config.robot_id();
      health.watchdog_state = state;
      gate.Fill(&health);
      health.devices.push_back(pipeline.Health());
      DeviceHealth drive_health;
      drive_health.name = "drive";
      drive_health.rate_hz = static_cast<float>(control_rate.RateHz(now));
      health.devices.push_back(drive_health);
      node->PublishHealth(health);
    }
    if (duration_s > 0 && now - start > FromSeconds(duration_s)) break;
    std::this_thread::sleep_until(next_cycle);
  }
  g_stop = true;
  MOSTAR_LOG(INFO) << "robot_server stopping";
  robot->Stop(&error);
  scan_thread.join();
  pipeline.Stop();
  trace.Flush();
  return 0;
}

}  // namespace
}  // namespace mostar::server

int main(int argc, char** argv) { return mostar::server::Run(argc, argv); }
