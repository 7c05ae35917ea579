// A planar laser scan in the laser frame (x forward, y left, z up; metres, radians).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "common/time/time.h"

namespace mostar {

struct LaserScan {
  Time stamp;                 // when the first beam was measured
  uint64_t sequence = 0;      // scan counter of the producer, increasing by 1
  float angle_min_rad = 0.f;  // angle of ranges_m[0]; counter-clockwise, 0 = ahead
  float angle_increment_rad = 0.f;
  float time_increment_s = 0.f;  // time between two beams
  float scan_time_s = 0.f;       // time between two scans
  float range_min_m = 0.f;
  float range_max_m = 0.f;
  // unit: metre. The non-finite values follow REP 117 and mean different spaces:
  //   +Inf: nothing hit up to range_max_m (no echo, beyond range): free space along the beam;
  //   NaN:  the beam measured nothing (dazzle, overflow, low signal, read error): unknown space;
  //   -Inf: something closer than range_min_m (not produced by the LMS200).
  // A finite value below range_min_m or not positive is unknown space too. The safety governor
  // counts only +Inf as free (docs/safety.md, G15).
  std::vector<float> ranges_m;
  std::vector<float> intensities;  // optional, empty or ranges_m.size()

  float AngleOf(size_t i) const {
    return angle_min_rad + static_cast<float>(i) * angle_increment_rad;
  }
  float angle_max_rad() const {
    return ranges_m.empty() ? angle_min_rad : AngleOf(ranges_m.size() - 1);
  }
  // A measured distance (finite, positive).
  static bool IsValidRange(float r) { return std::isfinite(r) && r > 0.f; }
  // Nothing hit along the beam up to the maximum range: +Inf.
  static bool IsFreeRange(float r) { return std::isinf(r) && r > 0.f; }
};

}  // namespace mostar
