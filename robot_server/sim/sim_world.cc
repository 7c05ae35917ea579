#include "robot_server/sim/sim_world.h"

#include <cmath>

#include "common/config/config_loader.h"

namespace mostar::sim {

bool LoadSimConfig(const std::string& path, proto::SimConfig* config, std::string* error) {
  if (!LoadTextConfig(path, config, error)) return false;
  return ValidateSimConfig(*config, path, error);
}

bool ValidateSimConfig(const proto::SimConfig& config, const std::string& name,
                       std::string* error) {
  if (!ValidateRanges(config, name, error)) return false;
  const auto& l = config.laser();
  if (l.resolution() == proto::LaserConfig::RES_0_25_DEG &&
      l.fov() != proto::LaserConfig::FOV_100) {
    *error = name + ": laser.resolution: RES_0_25_DEG needs fov: FOV_100 (as on the LMS200)";
    return false;
  }
  const auto& c = config.camera();
  if (c.cx_px() >= c.width_px() || c.cy_px() >= c.height_px()) {
    *error = name + ": camera.cx_px/cy_px: principal point outside the image";
    return false;
  }
  if (std::abs(c.tilt_rad()) + std::atan(c.height_px() / (2.0 * c.focal_px())) >= M_PI / 2) {
    *error = name + ": camera.tilt_rad: the image would look above the vertical";
    return false;
  }
  return true;
}

std::unique_ptr<SimWorld> SimWorld::Create(const proto::Scene& scene,
                                           const proto::SimConfig& config, Time start,
                                           std::string* error) {
  if (!ValidateSimConfig(config, "sim config", error)) return nullptr;
  auto world = std::make_unique<World>(scene);
  const DriveParams drive = DriveParams::FromProto(config.drive());
  const auto& s = scene.start();
  const double cx = s.x_m() + drive.footprint_center_x_m * std::cos(s.theta_rad());
  const double cy = s.y_m() + drive.footprint_center_x_m * std::sin(s.theta_rad());
  if (world->CircleCollides(cx, cy, drive.footprint_radius_m)) {
    *error = scene.name() + ": start: the robot footprint overlaps an obstacle";
    return nullptr;
  }
  return std::unique_ptr<SimWorld>(new SimWorld(std::move(world), config, start));
}

SimWorld::SimWorld(std::unique_ptr<World> world, const proto::SimConfig& config, Time start)
    : world_(std::move(world)),
      drive_(
          DriveParams::FromProto(config.drive()),
          Pose2D{world_->scene().start().x_m(), world_->scene().start().y_m(),
                 world_->scene().start().theta_rad()},
          [w = world_.get()](double x, double y, double r) { return w->CircleCollides(x, y, r); }),
      laser_(*world_, LaserParams::FromProto(config.laser()), config.laser().seed()),
      renderer_(*world_, CameraParams::FromProto(config.camera()), config.laser().height_m()),
      time_(start) {}

void SimWorld::AdvanceLocked(Time t) {
  if (t <= time_) return;
  drive_.Advance(t - time_);
  time_ = t;
}

void SimWorld::SetVelocity(double linear_mps, double angular_radps) {
  std::lock_guard<std::mutex> lock(mutex_);
  drive_.SetCommand(linear_mps, angular_radps);
}

void SimWorld::AdvanceTo(Time t) {
  std::lock_guard<std::mutex> lock(mutex_);
  AdvanceLocked(t);
}

LaserScan SimWorld::ScanAt(Time t, LaserGroundTruth* truth) {
  std::lock_guard<std::mutex> lock(mutex_);
  AdvanceLocked(t);
  const Pose2D pose = drive_.world_from_base();
  if (truth) truth->world_from_base = pose;
  return laser_.Scan(pose, t, truth ? &truth->true_ranges_m : nullptr);
}

std::vector<float> SimWorld::RangesAt(Time t) { return ScanAt(t).ranges_m; }

void SimWorld::SampleRanges(Time t, double angle_min_rad, double increment_rad, int count,
                            std::vector<float>* ranges_m) {
  std::lock_guard<std::mutex> lock(mutex_);
  AdvanceLocked(t);
  laser_.Measure(drive_.world_from_base(), angle_min_rad, increment_rad, count, ranges_m, nullptr);
}

StereoImages SimWorld::StereoAt(Time t, bool with_truth, Pose2D* world_from_base) {
  Pose2D pose;
  uint64_t frame;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    AdvanceLocked(t);
    pose = drive_.world_from_base();
    frame = frame_index_++;
  }
  if (world_from_base) *world_from_base = pose;
  StereoImages out;
  renderer_.Render(pose, frame, with_truth, &out);
  return out;
}

EncoderTicks SimWorld::EncodersAt(Time t) {
  std::lock_guard<std::mutex> lock(mutex_);
  AdvanceLocked(t);
  return drive_.encoders();
}

float SimWorld::SonarEchoAt(Time t, const SonarMount& mount, const SonarCone& cone) {
  Pose2D pose;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    AdvanceLocked(t);
    pose = drive_.world_from_base();
  }
  return SonarFirstEcho(*world_, pose, mount, cone);  // the World is immutable
}

uint32_t SimWorld::BumpersAt(Time t, int count) {
  Pose2D pose;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    AdvanceLocked(t);
    pose = drive_.world_from_base();
  }
  return BumperContacts(*world_, pose, drive_.params(), count);  // params are const
}

RobotState SimWorld::StateAt(Time t) {
  std::lock_guard<std::mutex> lock(mutex_);
  AdvanceLocked(t);
  RobotState s;
  s.time = time_;
  s.world_from_base = drive_.world_from_base();
  s.linear_mps = drive_.linear_mps();
  s.angular_radps = drive_.angular_radps();
  s.encoders = drive_.encoders();
  s.in_collision = drive_.in_collision();
  s.collision_count = drive_.collision_count();
  return s;
}

}  // namespace mostar::sim
