// The state of the robot's bumper belt, as published on rt/mostar/bumpers.
#pragma once

#include <cstdint>

#include "common/time/time.h"

namespace mostar {

// Segment i is centred at i x 360/segment_count degrees counter-clockwise from straight ahead
// around the base's footprint; bit i of a mask stands for segment i.
struct BumperState {
  Time stamp;
  int segment_count = 0;  // 0: the robot has no bumper belt; at most 32
  uint32_t pressed = 0;   // segments pressed now
  uint32_t latched = 0;   // segments whose contact stopped the robot; cleared by the re-arm
  bool readable = true;   // false: the contacts cannot be read (the robot stops)
};

}  // namespace mostar
