#include "robot_server/sim/bumper_contacts.h"

#include <cmath>

namespace mostar::sim {

uint32_t BumperContacts(const World& world, const Pose2D& world_from_base, const DriveParams& drive,
                        int count, double contact_margin_m) {
  const double r = drive.footprint_radius_m;
  const double probe_r = r * std::sin(M_PI / count);  // half the chord of one segment
  const double probe_distance = r + contact_margin_m - probe_r;
  const double c = std::cos(world_from_base.theta_rad), s = std::sin(world_from_base.theta_rad);
  uint32_t pressed = 0;
  for (int i = 0; i < count && i < 32; ++i) {
    const double a = 2 * M_PI * i / count;  // bumper::SegmentAngleRad
    const double bx = drive.footprint_center_x_m + probe_distance * std::cos(a);
    const double by = probe_distance * std::sin(a);
    const double wx = world_from_base.x_m + c * bx - s * by;
    const double wy = world_from_base.y_m + s * bx + c * by;
    if (world.CircleCollides(wx, wy, probe_r)) pressed |= 1u << i;
  }
  return pressed;
}

}  // namespace mostar::sim
