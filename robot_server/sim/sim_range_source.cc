#include "robot_server/sim/sim_range_source.h"

#include <cmath>

namespace mostar::sim {

void SimWorldRangeSource::Sample(SteadyTime time, float angle_min_rad, float angle_increment_rad,
                                 int count, std::vector<float>* ranges_m) {
  world_->SampleRanges(sim_origin_ + (time - steady_origin_), angle_min_rad, angle_increment_rad,
                       count, ranges_m);
}

}  // namespace mostar::sim
