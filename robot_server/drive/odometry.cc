#include "robot_server/drive/odometry.h"

#include <Eigen/Core>
#include <cmath>

namespace mostar::drive {

bool OdometryOptions::IsValid(std::string* error) const {
  if (!(wheel_radius_m > 0)) {
    *error = "wheel_radius_m must be positive";
    return false;
  }
  if (!(track_width_m > 0)) {
    *error = "track_width_m must be positive";
    return false;
  }
  if (!(ticks_per_turn >= 1)) {
    *error = "ticks_per_turn must be at least 1";
    return false;
  }
  if (counter_bits < 8 || counter_bits > 32) {
    *error = "counter_bits must be in [8, 32]";
    return false;
  }
  if (!(wheel_variance_m2_per_m >= 0)) {
    *error = "wheel_variance_m2_per_m must not be negative";
    return false;
  }
  if (!(max_wheel_speed_mps > 0)) {
    *error = "max_wheel_speed_mps must be positive";
    return false;
  }
  return true;
}

double OdometryOptions::metres_per_tick() const {
  return 2.0 * M_PI * wheel_radius_m / ticks_per_turn;
}

namespace {
// The pose of a point at `x_m` ahead along the heading of `pose`.
Pose2D Ahead(const Pose2D& pose, double x_m) {
  return {pose.x_m + x_m * std::cos(pose.theta_rad), pose.y_m + x_m * std::sin(pose.theta_rad),
          pose.theta_rad};
}
}  // namespace

OdometryIntegrator::OdometryIntegrator(const OdometryOptions& options)
    : options_(options), metres_per_tick_(options.metres_per_tick()) {
  axle_pose_ = Ahead(Pose2D{}, options_.axle_x_m);
}

void OdometryIntegrator::Reset(const Pose2D& pose) {
  previous_.reset();
  odometry_ = Odometry{};
  odometry_.pose = pose;
  axle_pose_ = Ahead(pose, options_.axle_x_m);
  covariance_.fill(0.0);
}

bool OdometryIntegrator::AddReading(const EncoderReading& reading) {
  if (!previous_) {
    previous_ = reading;
    odometry_.stamp = reading.stamp;
    return false;
  }
  const Duration dt = reading.steady_stamp - previous_->steady_stamp;
  if (dt <= Duration::zero()) {
    ++stats_.out_of_order;
    return false;
  }
  const int bits = options_.counter_bits;
  const double ds_l =
      static_cast<double>(WrappedTickDelta(previous_->left_count, reading.left_count, bits)) *
      metres_per_tick_;
  const double ds_r =
      static_cast<double>(WrappedTickDelta(previous_->right_count, reading.right_count, bits)) *
      metres_per_tick_;
  const double dt_s = ToSeconds(dt);
  previous_ = reading;
  if (std::abs(ds_l) > options_.max_wheel_speed_mps * dt_s ||
      std::abs(ds_r) > options_.max_wheel_speed_mps * dt_s) {
    ++stats_.glitches;
    return false;
  }

  const double b = options_.track_width_m;
  const double ds = 0.5 * (ds_r + ds_l);
  const double dtheta = (ds_r - ds_l) / b;
  const double half = 0.5 * dtheta;
  const double chord = std::abs(half) < 1e-9 ? ds : ds * std::sin(half) / half;
  const double heading = axle_pose_.theta_rad + half;
  const double c = std::cos(heading);
  const double s = std::sin(heading);

  // Covariance propagation (midpoint Jacobians).
  using Mat3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
  Eigen::Map<Mat3> p(covariance_.data());
  Mat3 fp = Mat3::Identity();
  fp(0, 2) = -ds * s;
  fp(1, 2) = ds * c;
  Eigen::Matrix<double, 3, 2> fw;                                // columns: d/d(ds_r), d/d(ds_l)
  fw << 0.5 * c - ds / (2 * b) * s, 0.5 * c + ds / (2 * b) * s,  //
      0.5 * s + ds / (2 * b) * c, 0.5 * s - ds / (2 * b) * c,    //
      1.0 / b, -1.0 / b;
  Eigen::Matrix2d q = Eigen::Matrix2d::Zero();
  q(0, 0) = options_.wheel_variance_m2_per_m * std::abs(ds_r);
  q(1, 1) = options_.wheel_variance_m2_per_m * std::abs(ds_l);
  const Mat3 next = fp * p * fp.transpose() + fw * q * fw.transpose();
  p = 0.5 * (next + next.transpose());  // keep it exactly symmetric

  axle_pose_.x_m += chord * c;
  axle_pose_.y_m += chord * s;
  axle_pose_.theta_rad = std::remainder(axle_pose_.theta_rad + dtheta, 2.0 * M_PI);
  odometry_.pose = Ahead(axle_pose_, -options_.axle_x_m);
  odometry_.linear_mps = ds / dt_s;
  odometry_.angular_radps = dtheta / dt_s;
  odometry_.stamp = reading.stamp;
  odometry_.pose_variance = {covariance_[0], covariance_[4], covariance_[8]};
  ++stats_.readings;
  return true;
}

}  // namespace mostar::drive
