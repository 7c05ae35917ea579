#include "robot_server/testpattern/test_pattern.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "common/check/check.h"

namespace mostar::testpattern {

KinematicRobot::KinematicRobot(const RoomOptions& options, const Clock* clock)
    : options_(options), clock_(clock), last_(clock->SteadyNow()) {}

void KinematicRobot::AdvanceLocked() {
  const SteadyTime now = clock_->SteadyNow();
  const double dt = std::clamp(ToSeconds(now - last_), 0.0, 0.2);
  last_ = now;
  const double heading = pose_.theta_rad + 0.5 * angular_radps_ * dt;
  double x = pose_.x_m + linear_mps_ * dt * std::cos(heading);
  double y = pose_.y_m + linear_mps_ * dt * std::sin(heading);
  // Walls stop the robot (0.3 m body radius).
  const double margin = 0.3;
  x = std::clamp(x, -options_.half_length_m + margin, options_.half_length_m - margin);
  y = std::clamp(y, -options_.half_width_m + margin, options_.half_width_m - margin);
  const double moved = std::hypot(x - pose_.x_m, y - pose_.y_m);
  const double sign = linear_mps_ >= 0 ? 1.0 : -1.0;
  pose_.x_m = x;
  pose_.y_m = y;
  const double dtheta = angular_radps_ * dt;
  pose_.theta_rad = std::remainder(pose_.theta_rad + dtheta, 2 * M_PI);
  const double ticks_per_m = options_.ticks_per_turn / (2 * M_PI * options_.wheel_radius_m);
  left_ticks_ += (sign * moved - 0.5 * options_.track_width_m * dtheta) * ticks_per_m;
  right_ticks_ += (sign * moved + 0.5 * options_.track_width_m * dtheta) * ticks_per_m;
}

bool KinematicRobot::SetWheelVelocities(const drive::WheelVelocities& wheels, std::string*) {
  std::lock_guard<std::mutex> lock(mutex_);
  AdvanceLocked();
  linear_mps_ = 0.5 * (wheels.left_mps + wheels.right_mps);
  angular_radps_ = (wheels.right_mps - wheels.left_mps) / options_.track_width_m;
  return true;
}

bool KinematicRobot::SetVelocity(double linear_mps, double angular_radps, std::string*) {
  std::lock_guard<std::mutex> lock(mutex_);
  AdvanceLocked();
  linear_mps_ = linear_mps;
  angular_radps_ = angular_radps;
  return true;
}

bool KinematicRobot::Stop(std::string* error, bool) { return SetVelocity(0, 0, error); }

drive::MotorStatus KinematicRobot::Status() const {
  std::lock_guard<std::mutex> lock(mutex_);
  drive::MotorStatus s;
  s.link_ok = true;
  s.driving = linear_mps_ != 0 || angular_radps_ != 0;
  return s;
}

bool KinematicRobot::ReadEncoders(drive::EncoderReading* reading, std::string*) {
  std::lock_guard<std::mutex> lock(mutex_);
  AdvanceLocked();
  reading->stamp = clock_->Now();
  reading->steady_stamp = clock_->SteadyNow();
  auto wrap = [](double ticks) {
    return static_cast<uint32_t>(static_cast<int64_t>(std::llround(ticks)) & 0xFFFF);
  };
  reading->left_count = wrap(left_ticks_);
  reading->right_count = wrap(right_ticks_);
  return true;
}

Pose2D KinematicRobot::TruePose() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return pose_;
}

LaserScan SyntheticScan(const KinematicRobot& robot, Time stamp, uint64_t sequence) {
  const Pose2D pose = robot.TruePose();
  const RoomOptions& room = robot.options();
  LaserScan scan;
  scan.stamp = stamp;
  scan.sequence = sequence;
  scan.angle_min_rad = static_cast<float>(-M_PI / 2);
  scan.angle_increment_rad = static_cast<float>(M_PI / 180);
  scan.scan_time_s = 1.0f / 75;
  scan.time_increment_s = scan.scan_time_s / 480;
  scan.range_min_m = 0.01f;
  scan.range_max_m = 8.183f;
  for (int i = 0; i < 181; ++i) {
    const double a = pose.theta_rad + scan.AngleOf(static_cast<size_t>(i));
    const double dx = std::cos(a);
    const double dy = std::sin(a);
    double t = std::numeric_limits<double>::infinity();
    if (dx > 1e-9) t = std::min(t, (room.half_length_m - pose.x_m) / dx);
    if (dx < -1e-9) t = std::min(t, (-room.half_length_m - pose.x_m) / dx);
    if (dy > 1e-9) t = std::min(t, (room.half_width_m - pose.y_m) / dy);
    if (dy < -1e-9) t = std::min(t, (-room.half_width_m - pose.y_m) / dy);
    scan.ranges_m.push_back(t <= scan.range_max_m ? static_cast<float>(t)
                                                  : std::numeric_limits<float>::infinity());
  }
  return scan;
}

TestPatternCamera::TestPatternCamera(const KinematicRobot* robot, int width, int height,
                                     double rate_hz, const Clock* clock)
    : robot_(robot), width_(width), height_(height), rate_hz_(rate_hz), clock_(clock) {}

bool TestPatternCamera::Open(std::string*) {
  open_ = true;
  next_ = clock_->SteadyNow();
  return true;
}

camera::StereoCameraInfo TestPatternCamera::Info() const {
  camera::StereoCameraInfo info;
  info.backend = "test_pattern";
  info.left_device = "pattern-left";
  info.right_device = "pattern-right";
  info.width_px = width_;
  info.height_px = height_;
  info.frame_rate_hz = rate_hz_;
  return info;
}

camera::GrabResult TestPatternCamera::Grab(Duration timeout, camera::StereoImagePair* pair) {
  if (!open_) return camera::GrabResult::Error(camera::GrabStatus::kNotOpen, "not open");
  const SteadyTime now = clock_->SteadyNow();
  if (next_ - now > timeout) {
    std::this_thread::sleep_for(timeout);
    return camera::GrabResult::Error(camera::GrabStatus::kTimeout, "pattern not due");
  }
  if (next_ > now) std::this_thread::sleep_for(next_ - now);
  next_ = std::max(next_ + FromSeconds(1.0 / rate_hz_), clock_->SteadyNow());
  pair->sequence = ++sequence_;
  pair->stamp = clock_->Now();
  const Pose2D pose = robot_->TruePose();
  for (int eye = 0; eye < 2; ++eye) {
    cv::Mat image(height_, width_, CV_8UC3, cv::Scalar(70, 60, 50));
    // Floor from the horizon (row h/3) down, with lines that scroll as the robot moves.
    const int horizon = height_ / 3;
    cv::rectangle(image, cv::Point(0, horizon), cv::Point(width_, height_),
                  cv::Scalar(110, 120, 120), cv::FILLED);
    const double phase = std::fmod(pose.x_m, 0.5) / 0.5;
    for (int k = 0; k < 12; ++k) {
      const double d = 0.5 * (k + 1 - phase);  // distance of a floor line, m
      const int row = horizon + static_cast<int>((height_ - horizon) * 0.6 / std::max(d, 0.3));
      if (row < height_) cv::line(image, {0, row}, {width_, row}, cv::Scalar(60, 70, 70), 2);
    }
    const int shift = eye == 0 ? 8 : -8;
    for (int k = -6; k <= 6; ++k) {
      const int x = width_ / 2 + shift + k * width_ / 8;
      cv::line(image, {width_ / 2 + shift, horizon}, {x * 3 - width_ + width_ / 2, height_},
               cv::Scalar(60, 70, 70), 2);
    }
    cv::putText(image, std::string("mostar test pattern ") + (eye == 0 ? "L" : "R"), {20, 40},
                cv::FONT_HERSHEY_SIMPLEX, 0.9, cv::Scalar(255, 255, 255), 2);
    cv::putText(image, "#" + std::to_string(pair->sequence), {20, 80}, cv::FONT_HERSHEY_SIMPLEX,
                0.8, cv::Scalar(200, 255, 200), 2);
    (eye == 0 ? pair->left : pair->right) = image;
  }
  return camera::GrabResult::Ok();
}

TestPatternLaser::TestPatternLaser(const KinematicRobot* robot, double rate_hz, const Clock* clock)
    : robot_(robot), rate_hz_(rate_hz), clock_(clock) {
  MOSTAR_CHECK(robot_ != nullptr && clock_ != nullptr && rate_hz_ > 0);
}

TestPatternLaser::~TestPatternLaser() { Stop(); }

bool TestPatternLaser::Start(ScanCallback on_scan, std::string* error) {
  if (thread_.joinable()) {
    *error = "test-pattern laser already started";
    return false;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = false;
  }
  thread_ = std::thread([this, on_scan = std::move(on_scan)] { Run(on_scan); });
  return true;
}

void TestPatternLaser::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void TestPatternLaser::Run(ScanCallback on_scan) {
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(1.0 / rate_hz_));
  auto next = std::chrono::steady_clock::now();
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    lock.unlock();
    on_scan(SyntheticScan(*robot_, clock_->Now(), ++scans_));
    lock.lock();
    next += period;
    wake_.wait_until(lock, next, [this] { return stop_; });
  }
}

DeviceHealth TestPatternLaser::Health() const {
  DeviceHealth health;
  health.name = "laser";
  health.rate_hz = static_cast<float>(rate_hz_);
  health.counters = {{"scans", scans_.load()}};
  return health;
}

}  // namespace mostar::testpattern
