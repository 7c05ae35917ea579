// The simulated world as the distance source of the LMS200 protocol emulator.
#pragma once

#include <vector>

#include "common/time/time.h"
#include "robot_server/sim/lms200_emulator/range_source.h"
#include "robot_server/sim/sim_world.h"

namespace mostar::sim {

// Maps the emulator's monotonic clock onto simulated time: sim time = sim_origin +
// (steady - steady_origin). The ranges are those of the simulated scan: +Inf where nothing
// echoes within the maximum range (an absorbing surface, or nothing there; the emulator sends
// "no echo"), NaN where the scanner is dazzled (the emulator sends the dazzle code). Thread-safe
// (SimWorld is).
class SimWorldRangeSource final : public RangeSource {
 public:
  SimWorldRangeSource(SimWorld* world, SteadyTime steady_origin, Time sim_origin)
      : world_(world), steady_origin_(steady_origin), sim_origin_(sim_origin) {}

  void Sample(SteadyTime time, float angle_min_rad, float angle_increment_rad, int count,
              std::vector<float>* ranges_m) override;

 private:
  SimWorld* world_;  // not owned
  SteadyTime steady_origin_;
  Time sim_origin_;
};

}  // namespace mostar::sim
