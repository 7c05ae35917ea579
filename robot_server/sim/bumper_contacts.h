// Simulated bumper switches: which segments of the base's footprint circle touch an obstacle.
//
// Segment i of `count` is centred at SegmentAngleRad(i) around the footprint circle (centre
// `footprint_center_x_m` on the base x axis, radius `footprint_radius_m`) and spans
// 360/count degrees. It is pressed when an obstacle comes within `contact_margin_m` outside the
// circle along that arc: a probe circle of the arc's half-chord, set inside the footprint so
// that it reaches exactly `contact_margin_m` beyond it, overlaps an obstacle's footprint (all
// heights: the switches sit just over the wheels, and every simulated obstacle stands on the
// floor). Pure; the World is read-only.
#pragma once

#include <cstdint>

#include "common/types/odometry.h"
#include "robot_server/sim/diff_drive.h"
#include "robot_server/sim/world.h"

namespace mostar::sim {

uint32_t BumperContacts(const World& world, const Pose2D& world_from_base, const DriveParams& drive,
                        int count, double contact_margin_m = 0.01);

}  // namespace mostar::sim
