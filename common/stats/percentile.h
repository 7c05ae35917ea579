// Percentiles of measured samples (latencies, ages, errors), one definition for the whole code
// base: the nearest-rank percentile, i.e. the smallest sample such that at least `fraction` of
// the samples are less than or equal to it (rank ceil(fraction * n), 1-based). Always one of the
// samples, never interpolated. `fraction` in [0, 1] (clamped); 0 gives the minimum, 1 the maximum.
#pragma once

#include <optional>
#include <vector>

namespace mostar {

// nullopt when `samples` is empty. O(n) (selection, no full sort).
std::optional<double> Percentile(std::vector<double> samples, double fraction);

}  // namespace mostar
