// Simulated sonar: the first echo of an ultrasonic cone (SRF08) against the World.
//
// The cone is sampled by a grid of rays: `azimuth_rays` across the full beam angle and
// `elevation_rays` across the vertical beam angle, around the sensor's axis (horizontal, along
// the mount's yaw in the base frame, at `height_m` above the floor). The echo is the slant
// distance of the nearest obstacle any ray meets. Every obstacle echoes, whatever its laser
// response: sound does not care that glass is transparent or a cabinet black. The floor and the
// ceiling give no echo (a smooth surface at grazing incidence reflects the burst away). Closer
// than min_range_m the echo is lost in the transducer's ringing and reads min_range_m; nothing
// within max_range_m reads +Inf. Pure; the World is read-only.
#pragma once

#include "common/types/odometry.h"
#include "common/types/sonar.h"
#include "robot_server/sim/world.h"

namespace mostar::sim {

struct SonarCone {
  double height_m = 0.30;           // of the sensor's axis above the floor
  double field_of_view_rad = 0.96;  // full beam angle across, about 55 degrees (SRF08)
  double vertical_fov_rad = 0.35;   // full beam angle up-down that still echoes, about 20 degrees
  double min_range_m = 0.03;
  double max_range_m = 6.0;
  int azimuth_rays = 11;   // >= 1
  int elevation_rays = 3;  // >= 1
};

// Metres from the sensor to the first echo (see above).
float SonarFirstEcho(const World& world, const Pose2D& world_from_base, const SonarMount& mount,
                     const SonarCone& cone);

}  // namespace mostar::sim
