#include "robot_server/sim/lms200_emulator/range_source.h"

#include <cmath>
#include <limits>

namespace mostar::sim {

void RoomRangeSource::Sample(SteadyTime, float angle_min_rad, float angle_increment_rad, int count,
                             std::vector<float>* ranges_m) {
  ranges_m->resize(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) {
    const double a = angle_min_rad + i * angle_increment_rad;
    const double dx = std::cos(a), dy = std::sin(a);
    double t = std::numeric_limits<double>::infinity();
    if (dx > 1e-9) t = std::min(t, (length_m_ - x_m_) / dx);
    if (dx < -1e-9) t = std::min(t, -x_m_ / dx);
    if (dy > 1e-9) t = std::min(t, (width_m_ - y_m_) / dy);
    if (dy < -1e-9) t = std::min(t, -y_m_ / dy);
    (*ranges_m)[static_cast<size_t>(i)] =
        t > 0 ? static_cast<float>(t) : std::numeric_limits<float>::infinity();
  }
}

}  // namespace mostar::sim
