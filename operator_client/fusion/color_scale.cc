#include "operator_client/fusion/color_scale.h"

#include <algorithm>
#include <cmath>

namespace mostar::fusion {

Rgba DistanceColor(float distance_m, float min_distance_m, float max_distance_m, float alpha) {
  if (std::isnan(distance_m)) return Rgba{0.5f, 0.5f, 0.5f, alpha};
  const float s =
      std::clamp((distance_m - min_distance_m) / (max_distance_m - min_distance_m), 0.f, 1.f);
  return Rgba{std::min(1.f, 2.f * (1.f - s)), std::min(1.f, 2.f * s), 0.f, alpha};
}

}  // namespace mostar::fusion
