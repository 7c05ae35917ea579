#include "operator_client/ui/console_self_calibration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <thread>

namespace mostar::ui {
namespace {

constexpr double kDeg = M_PI / 180.0;
const Time kT0 = FromUnixNanos(1'700'000'000'000'000'000);

math::LaserCameraCalibration Truth() {
  math::LaserCameraCalibration c;
  c.focal_px = 440.0;
  c.tilt_rad = 14.0 * kDeg;
  return c;
}

// A rectangular room (walls x = 3.2, y = +-1.4, laser frame) turned by `yaw`: ranges per beam,
// and edge results whose NEPs are the true images of the walls' bases (both eyes; every beam
// agrees with its laser point).
// The result carries the scan it was computed against; `measured` is that scan's own stamp
// (default: the image's).
struct Frame {
  LaserScan scan;
  std::shared_ptr<const vision::VisionResult> result;
};

Frame RoomFrame(double yaw, uint64_t sequence, Time stamp, std::optional<Time> measured = {}) {
  Frame frame;
  LaserScan& scan = frame.scan;
  scan.stamp = measured.value_or(stamp);
  scan.angle_min_rad = static_cast<float>(-M_PI / 2);
  scan.angle_increment_rad = static_cast<float>(M_PI / 180);
  scan.range_min_m = 0.1f;
  scan.range_max_m = 8.f;
  const math::LaserCameraCalibration truth = Truth();
  const math::CameraModel eyes[2] = {math::CameraModel(truth, Eye::kLeft),
                                     math::CameraModel(truth, Eye::kRight)};
  auto result = std::make_shared<vision::VisionResult>();
  result->ok = true;
  result->stamp = stamp;
  result->sequence = sequence;
  result->classification.beams.resize(181);
  result->left_ned.neps.resize(181);
  result->right_ned.neps.resize(181);
  for (int i = 0; i < 181; ++i) {
    const double a = scan.angle_min_rad + i * scan.angle_increment_rad;
    const double c = std::cos(a + yaw), s = std::sin(a + yaw);
    double r = 1e9;
    if (c > 1e-6) r = std::min(r, 3.2 / c);
    if (std::abs(s) > 1e-6) r = std::min(r, 1.4 / std::abs(s));
    scan.ranges_m.push_back(static_cast<float>(r));
    result->classification.beams[i].relation = vision::NepRelation::kAgrees;
    const Eigen::Vector3d base(r * std::cos(a), r * std::sin(a), -truth.laser_height_m);
    for (int e = 0; e < 2; ++e) {
      const std::optional<Eigen::Vector2d> px = eyes[e].Project(base);
      if (!px || !eyes[e].IsInImage(*px)) continue;
      vision::Nep& nep = (e == 0 ? result->left_ned : result->right_ned).neps[i];
      nep.found = true;
      nep.distance_m = r;
      nep.metres_per_px = 0.01;
      nep.pixel = *px;
    }
  }
  result->scan = scan;
  result->placement.measured_stamp = scan.stamp;
  frame.result = std::move(result);
  return frame;
}

render::StereoGeometry Geometry(const math::LaserCameraCalibration& c) {
  render::StereoGeometry geometry;
  std::string error;
  EXPECT_TRUE(geometry.Update(c, c, render::AlignmentModel::kSharedModel, {}, {}, &error)) << error;
  return geometry;
}

// Feeds frames turning through the room until a fit is published.
std::shared_ptr<const calibration::FitResult> FeedUntilProposal(ConsoleSelfCalibration* self,
                                                                const render::StereoGeometry& g,
                                                                int frames) {
  for (int k = 0; k < frames; ++k) {
    const Frame frame =
        RoomFrame(0.25 * std::sin(0.4 * k), k + 1, kT0 + std::chrono::milliseconds(500) * k);
    self->Update(frame.result, std::nullopt, vision::VisionOptions{}, g);
    self->Update(frame.result, std::nullopt, vision::VisionOptions{}, g);
  }
  for (int i = 0; i < 600 && !self->proposal(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    self->Update(nullptr, std::nullopt, vision::VisionOptions{}, g);
  }
  return self->proposal();
}

TEST(ConsoleSelfCalibrationTest, ProposesAndAppliesOnlyOnRequest) {
  math::LaserCameraCalibration live = Truth();
  live.tilt_rad += 1.5 * kDeg;
  live.focal_px *= 0.95;
  const math::LaserCameraCalibration before = live;
  ConsoleSelfCalibration::Options options;
  options.fit_period = std::chrono::seconds(5);
  ConsoleSelfCalibration self(options);
  EXPECT_EQ(self.proposal(), nullptr);
  const render::StereoGeometry geometry = Geometry(live);
  const std::shared_ptr<const calibration::FitResult> shown =
      FeedUntilProposal(&self, geometry, 12);
  ASSERT_NE(shown, nullptr);
  EXPECT_GT(self.window_points(), 100u);
  ASSERT_TRUE(shown->ok) << shown->reason;
  EXPECT_TRUE(shown->trustworthy) << shown->reason;
  EXPECT_EQ(live.tilt_rad, before.tilt_rad) << "nothing changes before Apply";
  std::string message;
  ASSERT_TRUE(self.Apply(&live, &message)) << message;
  EXPECT_NEAR(live.tilt_rad, Truth().tilt_rad, 0.1 * kDeg);
  EXPECT_NEAR(live.focal_px, Truth().focal_px, 0.005 * Truth().focal_px);
  EXPECT_EQ(self.proposal(), nullptr) << "an applied proposal is not shown again";
  EXPECT_FALSE(self.Apply(&live, &message));
}

TEST(ConsoleSelfCalibrationTest, RejectHidesAndStaleProposalsAreNotShown) {
  const math::LaserCameraCalibration live = Truth();
  ConsoleSelfCalibration self;
  const render::StereoGeometry geometry = Geometry(live);
  ASSERT_NE(FeedUntilProposal(&self, geometry, 5), nullptr);
  self.Reject();
  EXPECT_EQ(self.proposal(), nullptr);
  std::string message;
  math::LaserCameraCalibration target = live;
  EXPECT_FALSE(self.Apply(&target, &message));
  EXPECT_FALSE(message.empty());

  ConsoleSelfCalibration other;
  ASSERT_NE(FeedUntilProposal(&other, geometry, 5), nullptr);
  math::LaserCameraCalibration edited = live;
  edited.tilt_rad += 0.01;  // a slider edit: the proposal started from another calibration
  other.Update(nullptr, std::nullopt, vision::VisionOptions{}, Geometry(edited));
  EXPECT_EQ(other.proposal(), nullptr);
}

TEST(ConsoleSelfCalibrationTest, EachResultCountsOnceAndAnImageSizeChangeEmptiesTheWindow) {
  ConsoleSelfCalibration self;
  math::LaserCameraCalibration c = Truth();
  const render::StereoGeometry geometry = Geometry(c);
  const Frame frame = RoomFrame(0.0, 1, kT0);
  self.Update(frame.result, std::nullopt, vision::VisionOptions{}, geometry);
  const size_t once = self.window_points();
  EXPECT_GT(once, 0u);
  self.Update(frame.result, std::nullopt, vision::VisionOptions{}, geometry);
  EXPECT_EQ(self.window_points(), once);
  c.image_width_px = 1280;
  c.image_height_px = 960;
  self.Update(nullptr, std::nullopt, vision::VisionOptions{}, Geometry(c));
  EXPECT_EQ(self.window_points(), 0u);
}

Odometry At(double x_m, double theta_rad) {
  Odometry odometry;
  odometry.pose.x_m = x_m;
  odometry.pose.theta_rad = theta_rad;
  return odometry;
}

// One scan serves several images, and a still robot sends new scans of an unchanged view: both
// add nothing; the robot moving on does.
TEST(ConsoleSelfCalibrationTest, RepeatedEvidenceIsAddedOnce) {
  ConsoleSelfCalibration self;
  const render::StereoGeometry geometry = Geometry(Truth());
  const Frame first = RoomFrame(0.0, 1, kT0);
  self.Update(first.result, At(0, 0), vision::VisionOptions{}, geometry);
  const size_t once = self.window_points();
  ASSERT_GT(once, 0u);
  // The next image, drawn with the same scan.
  const Frame same_scan = RoomFrame(0.0, 2, kT0 + std::chrono::milliseconds(33), first.scan.stamp);
  self.Update(same_scan.result, std::nullopt, vision::VisionOptions{}, geometry);
  EXPECT_EQ(self.window_points(), once) << "the same scan, without odometry too";
  for (uint64_t k = 3; k < 7; ++k) {  // new scans, the robot still (within 1 cm, 0.3 degree)
    const Frame still = RoomFrame(0.0, k, kT0 + std::chrono::milliseconds(100) * k);
    self.Update(still.result, At(0.01, 0.005), vision::VisionOptions{}, geometry);
  }
  EXPECT_EQ(self.window_points(), once);
  EXPECT_EQ(self.repeated_results(), 5u);
  const Frame moved = RoomFrame(0.0, 7, kT0 + std::chrono::milliseconds(700));
  self.Update(moved.result, At(0.03, 0.0), vision::VisionOptions{}, geometry);
  EXPECT_EQ(self.window_points(), 2 * once) << "3 cm on";
  const Frame turned = RoomFrame(0.0, 8, kT0 + std::chrono::milliseconds(800));
  self.Update(turned.result, At(0.03, 0.01), vision::VisionOptions{}, geometry);
  EXPECT_EQ(self.window_points(), 3 * once) << "turned 0.6 degree";
  const Frame no_odometry = RoomFrame(0.0, 9, kT0 + std::chrono::milliseconds(900));
  self.Update(no_odometry.result, std::nullopt, vision::VisionOptions{}, geometry);
  EXPECT_EQ(self.window_points(), 4 * once) << "a new scan, and nothing says the robot is still";

  ConsoleSelfCalibration::Options every;
  every.min_motion_m = 0.0;
  every.min_turn_rad = 0.0;
  ConsoleSelfCalibration all(every);
  for (uint64_t k = 1; k < 4; ++k) {
    const Frame still = RoomFrame(0.0, k, kT0 + std::chrono::milliseconds(100) * k);
    all.Update(still.result, At(0, 0), vision::VisionOptions{}, geometry);
  }
  EXPECT_EQ(all.window_points(), 3 * once);
  EXPECT_EQ(all.repeated_results(), 0u);
}

TEST(ConsoleSelfCalibrationTest, DisabledCollectsNothingAndProposesNothing) {
  ConsoleSelfCalibration::Options options;
  options.enabled = false;
  options.fit_period = std::chrono::milliseconds(100);
  ConsoleSelfCalibration self(options);
  EXPECT_FALSE(self.enabled());
  const render::StereoGeometry geometry = Geometry(Truth());
  for (int k = 0; k < 5; ++k) {
    const Frame frame = RoomFrame(0.1 * k, k + 1, kT0 + std::chrono::milliseconds(500) * k);
    self.Update(frame.result, std::nullopt, vision::VisionOptions{}, geometry);
  }
  EXPECT_EQ(self.window_points(), 0u);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(self.proposal(), nullptr);
}

TEST(ConsoleSelfCalibrationTest, OptionsAreCheckedPartByPart) {
  ConsoleSelfCalibration::Options options;
  std::string why;
  EXPECT_TRUE(options.IsValid(&why)) << why;
  options.window_points = 0;
  EXPECT_FALSE(options.IsValid(&why));
  EXPECT_NE(why.find("window_points"), std::string::npos) << why;
  options = {};
  options.correspondences.max_range_m = 0.0;
  EXPECT_FALSE(options.IsValid(&why));
  EXPECT_EQ(why.rfind("correspondences: ", 0), 0u) << why;
  options = {};
  options.fit.free.fill(false);
  EXPECT_FALSE(options.IsValid(&why));
  EXPECT_EQ(why, "fit: no parameter is free");
}

}  // namespace
}  // namespace mostar::ui
