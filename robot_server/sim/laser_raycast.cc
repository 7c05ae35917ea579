#include "robot_server/sim/laser_raycast.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mostar::sim {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Beam i as a traced ray: azimuth in the world and tangent of elevation; `scale` turns the
// horizontal distance into the 3D range.
struct Beam {
  double azimuth_rad;
  double tan_el;
  double scale;
};

Beam BeamAt(const LaserParams& p, const Pose2D& pose, double a) {
  // Beam direction in the base frame: the laser-frame direction pitched down about y.
  const double bx = std::cos(a) * std::cos(p.pitch_rad);
  const double by = std::sin(a);
  const double bz = -std::cos(a) * std::sin(p.pitch_rad);
  const double horiz = std::hypot(bx, by);
  return {pose.theta_rad + std::atan2(by, bx), bz / horiz, 1.0 / horiz};
}

}  // namespace

LaserParams LaserParams::FromProto(const proto::LaserConfig& c) {
  LaserParams p;
  p.height_m = c.height_m();
  p.pitch_rad = c.pitch_rad();
  p.fov_rad = (c.fov() == proto::LaserConfig::FOV_100 ? 100.0 : 180.0) * M_PI / 180.0;
  switch (c.resolution()) {
    case proto::LaserConfig::RES_1_DEG:
      p.increment_rad = M_PI / 180.0;
      break;
    case proto::LaserConfig::RES_0_5_DEG:
      p.increment_rad = M_PI / 360.0;
      break;
    case proto::LaserConfig::RES_0_25_DEG:
      p.increment_rad = M_PI / 720.0;
      break;
  }
  p.range_max_m = c.range_mode() == proto::LaserConfig::CM ? 81.83 : 8.183;
  p.range_min_m = c.range_min_m();
  p.noise_sigma_m = c.noise_sigma_m();
  p.scan_period_s = c.scan_period_s();
  return p;
}

size_t LaserParams::BeamCount() const {
  return static_cast<size_t>(std::lround(fov_rad / increment_rad)) + 1;
}

std::vector<float> TrueRangesAt(const World& world, const LaserParams& p, const Pose2D& pose) {
  std::vector<float> out(p.BeamCount());
  for (size_t i = 0; i < out.size(); ++i) {
    const Beam b = BeamAt(p, pose, p.AngleMin() + static_cast<double>(i) * p.increment_rad);
    const RayHit hit = world.Trace(pose.x_m, pose.y_m, p.height_m, b.azimuth_rad, b.tan_el,
                                   p.range_max_m / b.scale, /*skip_transparent=*/true);
    out[i] = hit.kind == RayHit::kNothing ? kInf : static_cast<float>(hit.h_m * b.scale);
  }
  return out;
}

LaserRaycaster::LaserRaycaster(const World& world, const LaserParams& params, uint64_t seed)
    : world_(world), params_(params), rng_(seed) {}

LaserScan LaserRaycaster::Scan(const Pose2D& pose, Time stamp, std::vector<float>* truth) {
  const size_t n = params_.BeamCount();
  LaserScan scan;
  scan.stamp = stamp;
  scan.sequence = sequence_++;
  scan.angle_min_rad = static_cast<float>(params_.AngleMin());
  scan.angle_increment_rad = static_cast<float>(params_.increment_rad);
  scan.scan_time_s = static_cast<float>(params_.scan_period_s);
  // The LMS200 mirror turns at 75 Hz: one beam per increment of a 360 deg turn.
  scan.time_increment_s = static_cast<float>(params_.increment_rad / (2 * M_PI) / 75.0);
  scan.range_min_m = static_cast<float>(params_.range_min_m);
  scan.range_max_m = static_cast<float>(params_.range_max_m);
  Measure(pose, params_.AngleMin(), params_.increment_rad, static_cast<int>(n), &scan.ranges_m,
          truth);
  return scan;
}

void LaserRaycaster::Measure(const Pose2D& pose, double angle_min, double increment, int count,
                             std::vector<float>* ranges, std::vector<float>* truth) {
  const auto n = static_cast<size_t>(std::max(count, 0));
  ranges->resize(n);
  if (truth) truth->resize(n);
  std::normal_distribution<double> noise(0.0, std::max(params_.noise_sigma_m, 1e-12));
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (size_t i = 0; i < n; ++i) {
    const Beam b = BeamAt(params_, pose, angle_min + static_cast<double>(i) * increment);
    const RayHit hit = world_.Trace(pose.x_m, pose.y_m, params_.height_m, b.azimuth_rad, b.tan_el,
                                    params_.range_max_m / b.scale, true);
    if (hit.kind == RayHit::kNothing) {
      (*ranges)[i] = kInf;
      if (truth) (*truth)[i] = kInf;
      continue;
    }
    const double range = hit.h_m * b.scale;
    if (truth) (*truth)[i] = static_cast<float>(range);
    proto::LaserResponse response = proto::NORMAL;
    if (hit.kind == RayHit::kObstacle) {
      response = hit.obstacle->surface.laser;
      if (response == proto::ABSORB_DARK) {
        bool dark;
        world_.ObstacleAlbedo(hit, &dark);
        response = dark ? proto::NO_ECHO : proto::NORMAL;
      }
    } else if (hit.kind == RayHit::kFloor && world_.scene().floor().black_squares_absorb()) {
      bool inside, dark;
      world_.FloorAlbedo(hit.x_m, hit.y_m, &inside, &dark);
      if (dark) response = proto::NO_ECHO;
    }
    double measured = params_.noise_sigma_m > 0 ? range + noise(rng_) : range;
    switch (response) {
      case proto::NO_ECHO:
        (*ranges)[i] = kInf;
        continue;
      case proto::DAZZLE:
        (*ranges)[i] = kNaN;
        continue;
      case proto::SPURIOUS:
        if (uniform(rng_) < hit.obstacle->surface.spurious_probability) {
          measured = params_.range_min_m + uniform(rng_) * (range - params_.range_min_m);
        }
        break;
      default:
        break;
    }
    (*ranges)[i] = measured > params_.range_max_m
                       ? kInf
                       : static_cast<float>(std::max(measured, params_.range_min_m));
  }
}

}  // namespace mostar::sim
