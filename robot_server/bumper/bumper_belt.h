// The belt of bumper switches around the robot's base (the MORDUC has 16, just over the
// wheels). Segment i is centred at i x 360/N degrees counter-clockwise from straight ahead
// around the base's footprint; bit i of a reading is set while segment i is pressed.
#pragma once

#include <cstdint>
#include <string>

#include "common/types/health.h"

namespace mostar::bumper {

inline constexpr int kMaxSegments = 32;

class BumperBelt {
 public:
  BumperBelt() = default;
  BumperBelt(const BumperBelt&) = delete;
  BumperBelt& operator=(const BumperBelt&) = delete;
  virtual ~BumperBelt() = default;

  // The pressed segments now (bit i = segment i). False with `error` when the contacts cannot
  // be read: the caller must treat the belt as unknown (the robot stops). Quick, non-blocking;
  // called from the control loop.
  virtual bool Read(uint32_t* pressed, std::string* error) = 0;
  virtual int segments() const = 0;  // 1..kMaxSegments
  // State, message, counters. Thread-safe.
  virtual DeviceHealth Health() const = 0;
};

// Centre angle of segment `i` of `count`, radians counter-clockwise from straight ahead.
double SegmentAngleRad(int i, int count);

}  // namespace mostar::bumper
