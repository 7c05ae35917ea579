// The thesis' distance colour scale: red (danger) - yellow (caution) - green (safe).
#pragma once

#include "operator_client/fusion/vertex_array.h"

namespace mostar::fusion {

// Colour of an obstacle at `distance_m`: pure red at or below min_distance_m, pure green at or
// above max_distance_m, linear in between through pure yellow at the midpoint (red falls from
// 1 to 0 over the upper half, green rises from 0 to 1 over the lower half). Precondition:
// min_distance_m < max_distance_m. NaN distances give opaque grey.
Rgba DistanceColor(float distance_m, float min_distance_m, float max_distance_m, float alpha = 1.f);

}  // namespace mostar::fusion
