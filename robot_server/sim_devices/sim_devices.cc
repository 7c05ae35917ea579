#include "robot_server/sim_devices/sim_devices.h"

#include <algorithm>
#include <map>
#include <thread>

#include "robot_server/sonar/sonar_config.h"
#include "robot_server/sonar/srf08_emulator.h"

namespace mostar::sim {

SimStereoCamera::SimStereoCamera(SimWorld* world, double rate_hz, const Clock* clock)
    : world_(world), rate_hz_(rate_hz), clock_(clock) {}

bool SimStereoCamera::Open(std::string*) {
  open_ = true;
  next_ = clock_->SteadyNow();
  return true;
}

camera::StereoCameraInfo SimStereoCamera::Info() const {
  camera::StereoCameraInfo info;
  info.backend = "sim";
  info.left_device = "sim-left";
  info.right_device = "sim-right";
  info.width_px = world_->calibration().width_px;
  info.height_px = world_->calibration().height_px;
  info.frame_rate_hz = rate_hz_;
  return info;
}

camera::GrabResult SimStereoCamera::Grab(Duration timeout, camera::StereoImagePair* pair) {
  if (!open_) return camera::GrabResult::Error(camera::GrabStatus::kNotOpen, "not open");
  const SteadyTime now = clock_->SteadyNow();
  if (next_ - now > timeout) {
    std::this_thread::sleep_for(timeout);
    return camera::GrabResult::Error(camera::GrabStatus::kTimeout, "no frame due yet");
  }
  if (next_ > now) std::this_thread::sleep_for(next_ - now);
  // Frames that could not be rendered in time are skipped, as a real camera drops them.
  next_ = std::max(next_ + FromSeconds(1.0 / rate_hz_), clock_->SteadyNow());
  const Time stamp = clock_->Now();
  StereoImages images = world_->StereoAt(stamp, /*with_truth=*/false);
  pair->sequence = ++sequence_;
  pair->stamp = stamp;
  pair->left = images.left;
  pair->right = images.right;
  return camera::GrabResult::Ok();
}

SimDriveMotors::SimDriveMotors(SimWorld* world, const Clock* clock)
    : world_(world), clock_(clock) {}

bool SimDriveMotors::SetWheelVelocities(const drive::WheelVelocities& wheels, std::string* error) {
  const double track = world_->drive_params().track_width_m;
  return SetVelocity(0.5 * (wheels.left_mps + wheels.right_mps),
                     (wheels.right_mps - wheels.left_mps) / track, error);
}

bool SimDriveMotors::SetVelocity(double linear_mps, double angular_radps, std::string*) {
  world_->AdvanceTo(clock_->Now());
  world_->SetVelocity(linear_mps, angular_radps);
  return true;
}

bool SimDriveMotors::Stop(std::string* error, bool) { return SetVelocity(0, 0, error); }

drive::MotorStatus SimDriveMotors::Status() const {
  const RobotState state = world_->StateAt(clock_->Now());
  drive::MotorStatus status;
  status.link_ok = true;
  status.driving = state.linear_mps != 0 || state.angular_radps != 0;
  status.fault = state.in_collision;
  return status;
}

DeviceHealth SimDriveMotors::Health() const {
  const RobotState state = world_->StateAt(clock_->Now());
  DeviceHealth health = HealthFromStatus(Status(), "collision");
  health.counters = {{"collisions", state.collision_count}};
  return health;
}

bool SimDriveMotors::ReadEncoders(drive::EncoderReading* reading, std::string*) {
  const Time now = clock_->Now();
  const EncoderTicks ticks = world_->EncodersAt(now);
  reading->stamp = now;
  reading->steady_stamp = clock_->SteadyNow();
  reading->left_count = static_cast<uint32_t>(ticks.left);
  reading->right_count = static_cast<uint32_t>(ticks.right);
  return true;
}

int SimDriveMotors::counter_bits() const { return world_->drive_params().encoder_counter_bits; }

std::unique_ptr<SimulatedLms200> SimulatedLms200::Create(SimWorld* world,
                                                         laser::Lms200Config config,
                                                         const std::string& link_path,
                                                         const Clock* clock, std::string* error,
                                                         const proto::LaserConfig& line) {
  std::unique_ptr<SimulatedLms200> sim(new SimulatedLms200());
  sim->ranges_ = std::make_unique<SimWorldRangeSource>(world, clock->SteadyNow(), clock->Now());
  Lms200EmulatorOptions options;  // factory state: 9600 baud, 180/0.5 deg; the driver sets it up
  options.garbage_rate = line.line_garbage_rate();
  options.crc_error_rate = line.line_crc_error_rate();
  options.truncate_rate = line.line_truncate_rate();
  sim->emulator_ =
      std::make_unique<Lms200Emulator>(options, sim->ranges_.get(), clock->SteadyNow());
  sim->runner_ = std::make_unique<Lms200PtyRunner>(sim->emulator_.get(), link_path);
  if (!sim->runner_->Start(error)) return nullptr;
  config.set_port(sim->runner_->device_path());
  sim->scanner_ = laser::MakeSerialLms200Scanner(config, clock);
  if (!sim->scanner_) {
    *error = "cannot create the LMS200 driver for " + config.port();
    return nullptr;
  }
  return sim;
}

SimulatedLms200::~SimulatedLms200() {
  if (scanner_) scanner_->Stop();
  if (runner_) runner_->Stop();
}

bool SimBumperBelt::Read(uint32_t* pressed, std::string* /*error*/) {
  *pressed = world_->BumpersAt(clock_->Now(), segments_);
  last_ = *pressed;
  ++reads_;
  return true;
}

DeviceHealth SimBumperBelt::Health() const {
  DeviceHealth h;
  h.name = "bumpers";
  h.state = DeviceState::kOk;
  h.counters = {{"reads", reads_.load()}, {"pressed_mask", last_.load()}};
  return h;
}

std::unique_ptr<SimulatedSonar> SimulatedSonar::Create(SimWorld* world,
                                                       const sonar::SonarConfig& config,
                                                       SonarCone cone, const Clock* clock,
                                                       std::string* error) {
  sonar::Srf08RingOptions options;
  if (!sonar::Srf08RingOptionsFromConfig(config, &options, error)) return nullptr;
  cone.field_of_view_rad = options.field_of_view_rad;
  cone.min_range_m = options.min_range_m;
  cone.max_range_m = sonar::Srf08WindowMetres(255);  // the sensor cuts to its own window
  std::map<uint8_t, SonarMount> mounts;
  for (const sonar::Srf08Sensor& s : options.sensors) mounts[s.address] = s.mount;
  auto bus = std::make_unique<sonar::Srf08BusEmulator>(
      *clock, [world, clock, cone, mounts](uint8_t address) {
        return world->SonarEchoAt(clock->Now(), mounts.at(address), cone);
      });
  for (const auto& [address, mount] : mounts) bus->AddSensor(address);
  auto sim = std::unique_ptr<SimulatedSonar>(new SimulatedSonar());
  sim->ring_ = std::make_unique<sonar::Srf08Ring>(std::move(bus), options, *clock);
  return sim;
}

}  // namespace mostar::sim
