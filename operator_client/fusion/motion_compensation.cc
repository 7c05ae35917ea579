#include "operator_client/fusion/motion_compensation.h"

#include <algorithm>
#include <cmath>

#include "common/check/check.h"

namespace mostar::fusion {
namespace {

// Twist (vx, vy, w) over unit time whose exponential is `delta` (a child pose in its parent).
struct Twist {
  double vx = 0, vy = 0, w = 0;
};

// (sin w / w, (1 - cos w) / w), with their series near w = 0.
void ArcCoefficients(double w, double* a, double* b) {
  if (std::abs(w) < 1e-6) {
    *a = 1.0 - w * w / 6.0;
    *b = w / 2.0;
  } else {
    *a = std::sin(w) / w;
    *b = (1.0 - std::cos(w)) / w;
  }
}

Pose2D Exp(const Twist& t) {
  double a = 0, b = 0;
  ArcCoefficients(t.w, &a, &b);
  return Pose2D{a * t.vx - b * t.vy, b * t.vx + a * t.vy, t.w};
}

Twist Log(const Pose2D& delta) {
  const double w = WrapAngle(delta.theta_rad);
  double a = 0, b = 0;
  ArcCoefficients(w, &a, &b);
  const double det = a * a + b * b;  // > 0 for |w| <= pi
  return Twist{(a * delta.x_m + b * delta.y_m) / det, (-b * delta.x_m + a * delta.y_m) / det, w};
}

// `from` carried on by its own velocities for `dt` (negative: backwards).
Pose2D Extrapolate(const Odometry& from, Duration dt) {
  const double s = ToSeconds(dt);
  return Compose(from.pose, Exp(Twist{from.linear_mps * s, 0.0, from.angular_radps * s}));
}

Duration Abs(Duration d) { return d < Duration::zero() ? -d : d; }

}  // namespace

Pose2D Compose(const Pose2D& a_from_b, const Pose2D& b_from_c) {
  const double c = std::cos(a_from_b.theta_rad);
  const double s = std::sin(a_from_b.theta_rad);
  return Pose2D{a_from_b.x_m + c * b_from_c.x_m - s * b_from_c.y_m,
                a_from_b.y_m + s * b_from_c.x_m + c * b_from_c.y_m,
                a_from_b.theta_rad + b_from_c.theta_rad};
}

Pose2D Inverse(const Pose2D& a_from_b) {
  const double c = std::cos(a_from_b.theta_rad);
  const double s = std::sin(a_from_b.theta_rad);
  return Pose2D{-(c * a_from_b.x_m + s * a_from_b.y_m), s * a_from_b.x_m - c * a_from_b.y_m,
                -a_from_b.theta_rad};
}

double WrapAngle(double rad) {
  double r = std::remainder(rad, 2.0 * M_PI);  // [-pi, pi]
  if (r <= -M_PI) r += 2.0 * M_PI;
  return r;
}

Pose2D InterpolatePose(const Pose2D& from, const Pose2D& to, double s) {
  const Twist t = Log(Compose(Inverse(from), to));
  return Compose(from, Exp(Twist{t.vx * s, t.vy * s, t.w * s}));
}

bool MotionCompensationOptions::IsValid(std::string* error) const {
  if (max_odometry_gap <= Duration::zero()) {
    *error = "max_odometry_gap must be > 0";
    return false;
  }
  if (max_extrapolation < Duration::zero() || max_extrapolation > std::chrono::seconds(1)) {
    *error = "max_extrapolation must be in [0, 1] s";
    return false;
  }
  if (max_scan_age <= Duration::zero()) {
    *error = "max_scan_age must be > 0";
    return false;
  }
  if (smoothing_window < Duration::zero() || smoothing_window > std::chrono::seconds(1)) {
    *error = "smoothing_window must be in [0, 1] s";
    return false;
  }
  return true;
}

OdometryHistory::OdometryHistory(size_t capacity) : capacity_(capacity) {
  MOSTAR_CHECK(capacity >= 2) << "capacity " << capacity;
}

void OdometryHistory::Add(const Odometry& odometry) {
  const auto at =
      std::lower_bound(samples_.begin(), samples_.end(), odometry.stamp,
                       [](const Odometry& held, Time stamp) { return held.stamp < stamp; });
  if (at != samples_.end() && at->stamp == odometry.stamp) {
    *at = odometry;
    return;
  }
  if (samples_.size() >= capacity_) {
    if (at == samples_.begin()) {
      ++dropped_;
      return;
    }
    const bool at_end = at == samples_.end();
    const size_t index = static_cast<size_t>(at - samples_.begin());
    samples_.pop_front();
    ++dropped_;
    if (at_end) {
      samples_.push_back(odometry);
    } else {
      samples_.insert(samples_.begin() + static_cast<long>(index - 1), odometry);
    }
    return;
  }
  samples_.insert(at, odometry);
}

Pose2D OdometryHistory::PoseAt(Time t, const MotionCompensationOptions& options,
                               PoseCoverage* coverage) const {
  *coverage = PoseCoverage::kNotCovered;
  if (samples_.empty()) return Pose2D{};
  const Odometry& first = samples_.front();
  const Odometry& last = samples_.back();
  if (t >= last.stamp) {
    if (t == last.stamp) {
      *coverage = PoseCoverage::kInterpolated;
      return last.pose;
    }
    if (t - last.stamp > options.max_extrapolation) return last.pose;
    *coverage = PoseCoverage::kExtrapolated;
    return Extrapolate(last, t - last.stamp);
  }
  if (t < first.stamp) {
    if (first.stamp - t > options.max_extrapolation) return first.pose;
    *coverage = PoseCoverage::kExtrapolated;
    return Extrapolate(first, t - first.stamp);
  }
  // first.stamp <= t < last.stamp: `after` is the first sample later than t.
  const auto after =
      std::upper_bound(samples_.begin(), samples_.end(), t,
                       [](Time stamp, const Odometry& held) { return stamp < held.stamp; });
  const Odometry& b = *after;
  const Odometry& a = *(after - 1);
  if (t == a.stamp) {
    *coverage = PoseCoverage::kInterpolated;
    return a.pose;
  }
  if (b.stamp - a.stamp > options.max_odometry_gap) {
    return t - a.stamp < b.stamp - t ? a.pose : b.pose;
  }
  *coverage = PoseCoverage::kInterpolated;
  const double s = ToSeconds(t - a.stamp) / ToSeconds(b.stamp - a.stamp);
  Pose2D pose = InterpolatePose(a.pose, b.pose, s);
  double heading = 0;
  if (options.smoothing_window > Duration::zero() && SmoothedHeadingAt(t, options, &heading)) {
    pose.theta_rad += WrapAngle(heading - pose.theta_rad);
  }
  return pose;
}

bool OdometryHistory::SmoothedHeadingAt(Time t, const MotionCompensationOptions& options,
                                        double* rad) const {
  const auto first =
      std::lower_bound(samples_.begin(), samples_.end(), t - options.smoothing_window,
                       [](const Odometry& held, Time stamp) { return held.stamp < stamp; });
  const auto last =
      std::upper_bound(samples_.begin(), samples_.end(), t + options.smoothing_window,
                       [](Time stamp, const Odometry& held) { return stamp < held.stamp; });
  if (last - first < 3) return false;
  // Least-squares line in s = stamp - t (seconds); its intercept is the value at t.
  double n = 0, ss = 0, sss = 0, sth = 0, ssth = 0;
  double theta = first->pose.theta_rad;  // unwrapped along the window
  for (auto it = first; it != last; ++it) {
    if (it != first) {
      if (it->stamp - (it - 1)->stamp > options.max_odometry_gap) return false;
      theta += WrapAngle(it->pose.theta_rad - (it - 1)->pose.theta_rad);
    }
    const double s = ToSeconds(it->stamp - t);
    n += 1;
    ss += s;
    sss += s * s;
    sth += theta;
    ssth += s * theta;
  }
  const double det = n * sss - ss * ss;
  if (!(det > 0)) return false;
  *rad = (sss * sth - ss * ssth) / det;
  return true;
}

void MoveScanToImageTime(const LaserScan& scan, Time image_stamp, const OdometryHistory& odometry,
                         const MotionCompensationOptions& options, MovedScan* out) {
  std::string error;
  MOSTAR_CHECK(options.IsValid(&error)) << error;
  const size_t n = scan.ranges_m.size();
  out->points.resize(n);
  out->azimuths_rad.resize(n);
  out->moved = false;
  out->extrapolated = false;
  out->reason.clear();
  out->image_minus_scan = image_stamp - scan.stamp;
  for (size_t i = 0; i < n; ++i) {
    const float r = scan.ranges_m[i];
    const float a = scan.AngleOf(i);
    out->points[i] =
        LaserScan::IsValidRange(r) ? PlanarPoint{r * std::cos(a), r * std::sin(a)} : PlanarPoint{};
    out->azimuths_rad[i] = a;
  }
  if (Abs(out->image_minus_scan) > options.max_scan_age) {
    out->reason =
        "scan " +
        std::to_string(
            std::chrono::duration_cast<std::chrono::milliseconds>(out->image_minus_scan).count()) +
        " ms from the image";
    return;
  }
  if (odometry.empty()) {
    out->reason = "no odometry";
    return;
  }
  PoseCoverage coverage;
  const Pose2D odom_from_image = odometry.PoseAt(image_stamp, options, &coverage);
  bool extrapolated = coverage == PoseCoverage::kExtrapolated;
  if (coverage == PoseCoverage::kNotCovered) {
    out->reason = "no odometry at the image time";
    return;
  }
  const Pose2D image_from_odom = Inverse(odom_from_image);
  const float dt = scan.time_increment_s;
  const double beam_dt_s =
      std::isfinite(dt) && dt >= 0.f && dt <= 1e-3f ? static_cast<double>(dt) : 0.0;
  std::vector<PlanarPoint> moved(n);
  std::vector<float> azimuths(n);
  double turn_rad = 0.0;  // of the last beam moved: beams without a point may lie outside odometry
  for (size_t i = 0; i < n; ++i) {
    const bool valid = LaserScan::IsValidRange(scan.ranges_m[i]);
    const Time beam_time = scan.stamp + FromSeconds(beam_dt_s * static_cast<double>(i));
    const Pose2D odom_from_beam = odometry.PoseAt(beam_time, options, &coverage);
    if (coverage == PoseCoverage::kNotCovered) {
      if (!valid) {
        azimuths[i] = static_cast<float>(out->azimuths_rad[i] + turn_rad);
        continue;
      }
      out->reason = "no odometry at the scan time";
      return;
    }
    const Pose2D image_from_beam = Compose(image_from_odom, odom_from_beam);
    turn_rad = image_from_beam.theta_rad;
    azimuths[i] = static_cast<float>(out->azimuths_rad[i] + turn_rad);
    if (!valid) continue;
    extrapolated |= coverage == PoseCoverage::kExtrapolated;
    const double c = std::cos(image_from_beam.theta_rad);
    const double s = std::sin(image_from_beam.theta_rad);
    const double x = out->points[i].x_m;
    const double y = out->points[i].y_m;
    moved[i] = PlanarPoint{static_cast<float>(image_from_beam.x_m + c * x - s * y),
                           static_cast<float>(image_from_beam.y_m + s * x + c * y)};
  }
  out->azimuths_rad.swap(azimuths);
  out->points.swap(moved);
  out->moved = true;
  out->extrapolated = extrapolated;
}

}  // namespace mostar::fusion
