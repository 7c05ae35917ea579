#include "common/stats/percentile.h"

#include <algorithm>
#include <cmath>

namespace mostar {

std::optional<double> Percentile(std::vector<double> samples, double fraction) {
  if (samples.empty()) return std::nullopt;
  const double f = std::isnan(fraction) ? 0.0 : std::clamp(fraction, 0.0, 1.0);
  const double n = static_cast<double>(samples.size());
  const size_t rank = static_cast<size_t>(std::max(1.0, std::ceil(f * n)));
  const auto nth =
      samples.begin() + static_cast<std::ptrdiff_t>(std::min(rank, samples.size()) - 1);
  std::nth_element(samples.begin(), nth, samples.end());
  return *nth;
}

}  // namespace mostar
