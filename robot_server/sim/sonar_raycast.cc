#include "robot_server/sim/sonar_raycast.h"

#include <cmath>
#include <limits>

namespace mostar::sim {
namespace {

// Angle of ray i of n spread evenly across `span` around 0 (0 for a single ray).
double Spread(int i, int n, double span) { return n <= 1 ? 0.0 : -span / 2 + span * i / (n - 1); }

}  // namespace

float SonarFirstEcho(const World& world, const Pose2D& world_from_base, const SonarMount& mount,
                     const SonarCone& cone) {
  const double c = std::cos(world_from_base.theta_rad), s = std::sin(world_from_base.theta_rad);
  const double ox = world_from_base.x_m + c * mount.x_m - s * mount.y_m;
  const double oy = world_from_base.y_m + s * mount.x_m + c * mount.y_m;
  const double axis = world_from_base.theta_rad + mount.yaw_rad;
  double nearest = std::numeric_limits<double>::infinity();
  for (int e = 0; e < cone.elevation_rays; ++e) {
    const double elevation = Spread(e, cone.elevation_rays, cone.vertical_fov_rad);
    const double tan_el = std::tan(elevation);
    const double slant_per_h = std::sqrt(1 + tan_el * tan_el);
    for (int a = 0; a < cone.azimuth_rays; ++a) {
      const double azimuth = axis + Spread(a, cone.azimuth_rays, cone.field_of_view_rad);
      const RayHit hit = world.Trace(ox, oy, cone.height_m, azimuth, tan_el,
                                     cone.max_range_m / slant_per_h, /*skip_transparent=*/false);
      if (hit.kind != RayHit::kObstacle) continue;
      nearest = std::min(nearest, hit.h_m * slant_per_h);
    }
  }
  if (nearest > cone.max_range_m) return std::numeric_limits<float>::infinity();
  return static_cast<float>(std::max(nearest, cone.min_range_m));
}

}  // namespace mostar::sim
