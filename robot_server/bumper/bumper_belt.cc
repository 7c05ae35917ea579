#include "robot_server/bumper/bumper_belt.h"

#include <cmath>

namespace mostar::bumper {

double SegmentAngleRad(int i, int count) { return 2 * M_PI * i / count; }

}  // namespace mostar::bumper
