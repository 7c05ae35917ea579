// Motion compensation of a laser scan for the image it is drawn on (thesis 9: delays are the
// source of dynamic registration errors, synchronisation the cure).
//
// Frames and units. Poses are odom_from_base (common/types/odometry.h): metres, radians,
// counter-clockwise; base frame x forward, y left. The base frame's origin lies under the laser
// (robot_server/drive/odometry.h, sim_config.proto), so in the scan plane the laser frame and the
// base frame coincide. All times are on the robot's clock: scan and image stamps, odometry stamps.
//
// SE(2) conventions: a Pose2D p maps a point q of its child frame to p.R(theta) q + (x, y).
// Interpolation between two poses follows the constant-twist arc between them (the exponential
// map of SE(2)), which is what a differential drive describes at constant wheel speeds; it is
// exact for a constant (v, w) and reduces to linear interpolation of x, y, theta at w = 0.
//
// Beam timing (REP 117 / sensor_msgs/LaserScan): beam i is measured at
// stamp + i * time_increment_s; the LMS200 sweeps 180 deg in half a 13.32 ms mirror revolution.
#pragma once

#include <cstddef>
#include <deque>
#include <string>
#include <vector>

#include "common/time/time.h"
#include "common/types/laser_scan.h"
#include "common/types/odometry.h"
#include "operator_client/fusion/vertex_array.h"

namespace mostar::fusion {

// a_from_c = a_from_b * b_from_c.
Pose2D Compose(const Pose2D& a_from_b, const Pose2D& b_from_c);
// b_from_a from a_from_b.
Pose2D Inverse(const Pose2D& a_from_b);
// The pose a fraction `s` along the constant-twist arc from `from` (s = 0) to `to` (s = 1);
// s outside [0, 1] continues the arc. Angles need not be normalised.
Pose2D InterpolatePose(const Pose2D& from, const Pose2D& to, double s);
// Angle wrapped to (-pi, pi].
double WrapAngle(double rad);

struct MotionCompensationOptions {
  // Two consecutive odometry samples further apart than this do not cover the time between
  // them (samples were lost). The robot publishes at 50 Hz: 20 ms apart. > 0.
  Duration max_odometry_gap = FromMilliseconds(100);
  // How far beyond the newest sample (or before the oldest) a pose is extrapolated with that
  // sample's velocities; further is not covered. >= 0, at most 1 s.
  Duration max_extrapolation = FromMilliseconds(60);
  // A scan stamped further than this from the image is not moved (shown faded). > 0.
  Duration max_scan_age = FromMilliseconds(500);
  // Encoder odometry moves in ticks: 1 mm of wheel travel is 2.2 mrad of heading on MORDUC's
  // 0.46 m track, 1 px at f = 440 px, which the interpolation between two samples keeps. With a
  // window w > 0, the heading of a pose between samples is the value at t of a straight line
  // fitted (least squares) to the unwrapped headings of the samples within t +- w, when there
  // are at least 3, none further apart than max_odometry_gap; x and y stay interpolated. Exact
  // for a constant turn rate; lags a little while the turn rate changes. 0: off. In [0, 1 s].
  Duration smoothing_window = FromMilliseconds(60);

  bool IsValid(std::string* error) const;
};

// How a pose at a time was obtained.
enum class PoseCoverage {
  kInterpolated,  // between two samples at most max_odometry_gap apart (or at a sample)
  kExtrapolated,  // within max_extrapolation of the newest or oldest sample
  kNotCovered,    // no odometry, a gap in it, or too far outside it
};

// Odometry samples ordered by stamp, at most `capacity` of them (the oldest go first).
// Not thread-safe: the owner locks (client::RobotState).
class OdometryHistory {
 public:
  explicit OdometryHistory(size_t capacity);

  // Inserts `odometry` at its stamp (out-of-order samples are placed in order). A sample whose
  // stamp equals a held one replaces it. When full, the oldest sample is dropped; a sample older
  // than all held ones is then dropped instead (counted in dropped()).
  void Add(const Odometry& odometry);

  // odom_from_base at `t`, and how it was obtained in `coverage`. When not covered, returns the
  // nearest held pose (or the identity when empty), which the caller must not use to move things.
  Pose2D PoseAt(Time t, const MotionCompensationOptions& options, PoseCoverage* coverage) const;

  size_t size() const { return samples_.size(); }
  size_t capacity() const { return capacity_; }
  size_t dropped() const { return dropped_; }
  bool empty() const { return samples_.empty(); }
  const Odometry& newest() const { return samples_.back(); }   // not empty
  const Odometry& oldest() const { return samples_.front(); }  // not empty

 private:
  // The smoothed heading at t (options.smoothing_window), on any 2 pi branch; false when the
  // window does not qualify.
  bool SmoothedHeadingAt(Time t, const MotionCompensationOptions& options, double* rad) const;

  size_t capacity_;
  std::deque<Odometry> samples_;  // strictly increasing stamps
  size_t dropped_ = 0;
};

// A scan's beams placed for one image.
struct MovedScan {
  // One per beam: the point in the base frame at the image time. Beams without a finite,
  // positive range are (0, 0). When !moved, the points are the scan as measured.
  std::vector<PlanarPoint> points;
  // One per beam, every beam included: its direction (radians, counter-clockwise) in the base
  // frame at the image time, i.e. its angle turned by the robot's turn between the beam's time
  // and the image's. The beam angle as measured when !moved. For beams without a point (NaN,
  // +Inf) this says where their free or unknown space lies (ResampleAtImageTime).
  std::vector<float> azimuths_rad;
  bool moved = false;  // every beam was moved with odometry covering its time and the image's
  bool extrapolated = false;     // moved, and some pose came from extrapolation
  Duration image_minus_scan{0};  // image stamp - scan stamp (first beam)
  std::string reason;            // why not moved (empty when moved)
};

// Moves each beam of `scan` from the base frame at its own time (stamp + i * time_increment_s;
// a time_increment_s that is not finite or outside [0, 1 ms] counts as 0) to the base frame at
// `image_stamp`: image_from_beam = inverse(odom_from_base(image)) * odom_from_base(beam).
// `options` must be valid (asserted). Never fails: when odometry does not cover every time
// needed, or the scan is older than max_scan_age, `out` holds the scan as measured with
// moved = false and the reason.
void MoveScanToImageTime(const LaserScan& scan, Time image_stamp, const OdometryHistory& odometry,
                         const MotionCompensationOptions& options, MovedScan* out);

}  // namespace mostar::fusion
