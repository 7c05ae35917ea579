#include "operator_client/fusion/scan_resampling.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace mostar::fusion {
namespace {

constexpr double kTwoPi = 2.0 * M_PI;

// `angle` relative to `angle_min`, in [0, 2 pi).
double FromMin(double angle, double angle_min) {
  double d = std::fmod(angle - angle_min, kTwoPi);
  if (d < 0.0) d += kTwoPi;
  return d;
}

}  // namespace

bool ResampleAtImageTime(const LaserScan& scan, const MovedScan& moved, LaserScan* out) {
  *out = scan;
  const size_t n = scan.ranges_m.size();
  const double increment = scan.angle_increment_rad;
  if (!moved.moved || moved.points.size() != n || moved.azimuths_rad.size() != n ||
      !std::isfinite(increment) || increment < kMinIncrementRad ||
      !std::isfinite(scan.angle_min_rad)) {
    return false;
  }
  const double angle_min = scan.angle_min_rad;
  out->stamp = scan.stamp + moved.image_minus_scan;
  out->time_increment_s = 0.f;
  constexpr float kNone = std::numeric_limits<float>::quiet_NaN();
  out->ranges_m.assign(n, kNone);
  const bool with_intensities = scan.intensities.size() == n;
  if (with_intensities) out->intensities.assign(n, 0.f);

  // Azimuth (relative to angle_min) and distance of every moved beam from the new origin.
  std::vector<double> azimuth(n);
  std::vector<double> distance(n, 0.0);
  std::vector<bool> valid(n);
  for (size_t i = 0; i < n; ++i) {
    valid[i] = LaserScan::IsValidRange(scan.ranges_m[i]);
    const PlanarPoint& p = moved.points[i];
    if (valid[i]) {
      distance[i] = std::hypot(static_cast<double>(p.x_m), static_cast<double>(p.y_m));
      valid[i] = distance[i] > 0.0;
    }
    azimuth[i] = FromMin(valid[i] ? std::atan2(p.y_m, p.x_m) : moved.azimuths_rad[i], angle_min);
  }
  // Calls visit(j, shift) for every target beam j whose relative angle j * increment lies in
  // [lo, hi] + shift, shift 0 or +-2 pi (an interval reaching past 0 or 2 pi wraps round).
  // Intervals with a non-finite end (a moved point of NaN odometry) reach no target. The bounds
  // are clamped to the grid before they become integers.
  const auto for_each_target = [&](double lo, double hi, const auto& visit) {
    if (!std::isfinite(lo) || !std::isfinite(hi) || lo > hi) return;
    const double last_index = static_cast<double>(n) - 1.0;
    for (const double shift : {0.0, -kTwoPi, kTwoPi}) {
      if (hi + shift < 0.0 || lo + shift > kTwoPi) continue;
      const double first = std::max(0.0, std::ceil((lo + shift) / increment - 1e-9));
      const double last = std::min(last_index, std::floor((hi + shift) / increment + 1e-9));
      for (double j = first; j <= last; j += 1.0) visit(static_cast<size_t>(j), shift);
    }
  };

  // 1. Crossings with surface segments between neighbouring points; the nearest wins.
  std::vector<bool> set(n, false);
  for (size_t i = 0; i + 1 < n; ++i) {
    if (!valid[i] || !valid[i + 1]) continue;
    const double px = moved.points[i].x_m, py = moved.points[i].y_m;
    const double qx = moved.points[i + 1].x_m, qy = moved.points[i + 1].y_m;
    const double ex = qx - px, ey = qy - py;
    // The azimuth step from p to q, the short way round.
    const double step = std::remainder(azimuth[i + 1] - azimuth[i], kTwoPi);
    const double gap = std::hypot(ex, ey);
    const double joined =
        std::max(kSurfaceGapMinM,
                 kSurfaceGapPerRad * std::min(distance[i], distance[i + 1]) * std::abs(step));
    if (gap > joined) continue;
    const double lo = std::min(azimuth[i], azimuth[i] + step);
    const double hi = std::max(azimuth[i], azimuth[i] + step);
    for_each_target(lo, hi, [&](size_t j, double /*shift*/) {
      const double a = angle_min + static_cast<double>(j) * increment;
      const double ux = std::cos(a), uy = std::sin(a);
      // p + s e = t u: t = (p x e) / (u x e), s = (p x u) / (u x e), 2D cross products.
      const double denominator = ux * ey - uy * ex;
      double t;
      if (std::abs(denominator) < 1e-12) {
        t = std::min(distance[i], distance[i + 1]);  // the segment lies along the ray
      } else {
        t = (px * ey - py * ex) / denominator;
        const double s = (px * uy - py * ux) / denominator;
        if (s < -1e-6 || s > 1.0 + 1e-6) return;
      }
      if (!(t > 0.0)) return;
      float& range = out->ranges_m[j];
      if (!set[j] || t < range) range = static_cast<float>(t);
      set[j] = true;
    });
  }

  // 2. The beam nearest in azimuth, within half an increment (also the intensities).
  std::vector<double> nearest_error(n, std::numeric_limits<double>::infinity());
  std::vector<size_t> nearest(n, n);
  for (size_t i = 0; i < n; ++i) {
    for_each_target(
        azimuth[i] - 0.5 * increment, azimuth[i] + 0.5 * increment, [&](size_t k, double shift) {
          const double error = std::abs(azimuth[i] + shift - static_cast<double>(k) * increment);
          // Equal errors: the nearer point, as the laser would see it.
          const bool better = error < nearest_error[k] - 1e-12 ||
                              (error < nearest_error[k] + 1e-12 && nearest[k] < n && valid[i] &&
                               (!valid[nearest[k]] || distance[i] < distance[nearest[k]]));
          if (!better) return;
          nearest_error[k] = error;
          nearest[k] = i;
        });
  }
  for (size_t j = 0; j < n; ++j) {
    const size_t i = nearest[j];
    if (i == n) continue;  // 3. not looked at: NaN
    if (with_intensities) out->intensities[j] = scan.intensities[i];
    if (set[j]) continue;
    out->ranges_m[j] = valid[i] ? static_cast<float>(distance[i]) : scan.ranges_m[i];
  }
  return true;
}

}  // namespace mostar::fusion
