// Sonar ranges: one value per sensor of the belt, as ROS 2's sensor_msgs/Range (ULTRASOUND).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/time/time.h"

namespace mostar {

// Where a sonar sits on the robot: in the base frame (REP-103: x forward, y left, metres), its
// axis `yaw_rad` from x, counter-clockwise.
struct SonarMount {
  std::string frame_id;  // e.g. "sonar_0"
  double x_m = 0;
  double y_m = 0;
  double yaw_rad = 0;
};

struct SonarRange {
  SonarMount mount;
  Time stamp;                   // end of this sensor's ranging
  float range_m = 0;            // first echo; +Inf = no echo within max_range_m, NaN = failed
  float min_range_m = 0;        // closer objects read as min_range_m or are missed (ringing)
  float max_range_m = 0;        // of the configured ranging window
  float field_of_view_rad = 0;  // full cone angle
};

// One cycle of the whole belt (every ping group once).
struct SonarRanges {
  uint64_t cycle = 0;
  std::vector<SonarRange> ranges;  // in the configured sensor order
};

}  // namespace mostar
