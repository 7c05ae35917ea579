// Crafted laser scans for the fusion tests and benchmark: a 2D ray caster over segments and
// circles in the laser frame (x forward, y left; metres). Test-only.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include "common/types/laser_scan.h"

namespace mostar::fusion::testing {

constexpr double kPi = 3.14159265358979323846;

struct Segment {
  double x0, y0, x1, y1;
};
struct Circle {
  double cx, cy, radius;
};

struct Scene {
  std::vector<Segment> segments;
  std::vector<Circle> circles;

  // Distance along the unit ray (cos a, sin a) to the nearest surface, +Inf if none.
  double Cast(double angle_rad) const {
    const double dx = std::cos(angle_rad);
    const double dy = std::sin(angle_rad);
    double best = std::numeric_limits<double>::infinity();
    for (const Segment& s : segments) {
      const double ex = s.x1 - s.x0;
      const double ey = s.y1 - s.y0;
      const double denom = dx * ey - dy * ex;
      if (std::abs(denom) < 1e-12) continue;
      const double t = (s.x0 * ey - s.y0 * ex) / denom;  // along the ray
      const double u = (s.x0 * dy - s.y0 * dx) / denom;  // along the segment
      if (t > 0.0 && u >= 0.0 && u <= 1.0) best = std::min(best, t);
    }
    for (const Circle& c : circles) {
      const double b = dx * c.cx + dy * c.cy;
      const double disc = b * b - (c.cx * c.cx + c.cy * c.cy - c.radius * c.radius);
      if (disc < 0.0) continue;
      const double t = b - std::sqrt(disc);
      if (t > 0.0) best = std::min(best, t);
    }
    return best;
  }
};

// An LMS200-like scan over [-90, +90] degrees with `beams` beams (181: 1 degree, 361: 0.5).
inline LaserScan MakeScan(const Scene& scene, int beams, float range_max_m = 8.0f) {
  LaserScan scan;
  scan.angle_min_rad = static_cast<float>(-kPi / 2);
  scan.angle_increment_rad = static_cast<float>(kPi / (beams - 1));
  scan.range_min_m = 0.01f;
  scan.range_max_m = range_max_m;
  scan.ranges_m.resize(static_cast<size_t>(beams));
  for (int i = 0; i < beams; ++i) {
    const double range = scene.Cast(scan.AngleOf(static_cast<size_t>(i)));
    scan.ranges_m[static_cast<size_t>(i)] =
        range <= range_max_m ? static_cast<float>(range) : std::numeric_limits<float>::infinity();
  }
  return scan;
}

// A corridor end: a wall 3 m ahead and side walls 1.5 m to each side.
inline Scene Room() {
  Scene scene;
  scene.segments.push_back({3.0, -1.5, 3.0, 1.5});
  scene.segments.push_back({-1.0, 1.5, 3.0, 1.5});
  scene.segments.push_back({-1.0, -1.5, 3.0, -1.5});
  return scene;
}

// A wall 3 m ahead with a 0.6 m wide box at 1.5 m in front of it.
inline Scene BoxBeforeWall() {
  Scene scene;
  scene.segments.push_back({3.0, -6.0, 3.0, 6.0});
  scene.segments.push_back({1.5, -0.3, 1.5, 0.3});  // front face
  scene.segments.push_back({1.5, 0.3, 1.9, 0.3});   // sides (hidden)
  scene.segments.push_back({1.5, -0.3, 1.9, -0.3});
  return scene;
}

// A person's legs at 2 m in front of a wall at 4 m.
inline Scene Legs() {
  Scene scene;
  scene.segments.push_back({4.0, -8.0, 4.0, 8.0});
  scene.circles.push_back({2.0, 0.15, 0.06});
  scene.circles.push_back({2.0, -0.15, 0.06});
  return scene;
}

}  // namespace mostar::fusion::testing
