#include "robot_server/camera/fake_stereo_camera.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "common/time/fake_clock.h"
#include "robot_server/camera/stereo_pairer.h"

namespace mostar::camera {
namespace {

using std::chrono::milliseconds;

FakeStereoCamera::Options SmallOptions(const Clock* clock) {
  FakeStereoCamera::Options options;
  options.width_px = 64;
  options.height_px = 48;
  options.clock = clock;
  return options;
}

TEST(FakeStereoCameraTest, PlaysItsScript) {
  FakeClock clock;
  FakeStereoCamera camera(SmallOptions(&clock));
  std::string error;
  ASSERT_TRUE(camera.Open(&error)) << error;
  camera.QueuePairs(2);
  camera.QueueTimeout();
  camera.QueuePairs(1);
  camera.QueueDeviceLost();

  StereoImagePair pair;
  ASSERT_TRUE(camera.Grab(milliseconds(1), &pair).ok());
  EXPECT_EQ(pair.sequence, 0u);
  EXPECT_EQ(pair.stamp, clock.Now());
  EXPECT_EQ(pair.left.size(), cv::Size(64, 48));
  EXPECT_EQ(pair.left.type(), CV_8UC3);
  ASSERT_TRUE(camera.Grab(milliseconds(1), &pair).ok());
  EXPECT_EQ(pair.sequence, 1u);
  EXPECT_EQ(camera.Grab(milliseconds(1), &pair).status, GrabStatus::kTimeout);
  ASSERT_TRUE(camera.Grab(milliseconds(1), &pair).ok());
  EXPECT_EQ(pair.sequence, 2u);
  const GrabResult lost = camera.Grab(milliseconds(1), &pair);
  EXPECT_EQ(lost.status, GrabStatus::kDeviceLost);
  EXPECT_FALSE(lost.message.empty());
  EXPECT_FALSE(camera.IsOpen());
  EXPECT_EQ(camera.Grab(milliseconds(1), &pair).status, GrabStatus::kNotOpen);
  EXPECT_EQ(camera.pairs_delivered(), 3u);
}

TEST(FakeStereoCameraTest, EmptyScriptTimesOut) {
  FakeClock clock;
  FakeStereoCamera camera(SmallOptions(&clock));
  std::string error;
  ASSERT_TRUE(camera.Open(&error));
  StereoImagePair pair;
  EXPECT_EQ(camera.Grab(milliseconds(1), &pair).status, GrabStatus::kTimeout);
}

TEST(FakeStereoCameraTest, OpenFailsWhileUnpluggedOrScriptedToFail) {
  FakeClock clock;
  FakeStereoCamera camera(SmallOptions(&clock));
  std::string error;
  camera.SetOpenFailures(2);
  EXPECT_FALSE(camera.Open(&error));
  EXPECT_FALSE(error.empty());
  EXPECT_FALSE(camera.Open(&error));
  EXPECT_TRUE(camera.Open(&error));
  camera.Unplug();
  StereoImagePair pair;
  EXPECT_EQ(camera.Grab(milliseconds(1), &pair).status, GrabStatus::kDeviceLost);
  EXPECT_FALSE(camera.Open(&error));
  EXPECT_NE(error.find("unplugged"), std::string::npos);
  camera.Replug();
  EXPECT_TRUE(camera.Open(&error));
  EXPECT_EQ(camera.open_calls(), 5);
}

// Eyes from the fake camera, re-timed as two free-running devices, go through the pairer:
// one lost right frame costs one left frame, and every pair matches.
TEST(FakeStereoCameraTest, PairerKeepsEyesInStepWithDroppedFrames) {
  FakeClock clock;
  FakeStereoCamera camera(SmallOptions(&clock));
  std::string error;
  ASSERT_TRUE(camera.Open(&error));
  camera.QueuePairs(20);
  StereoPairer pairer;
  int pairs = 0;
  for (int i = 0; i < 20; ++i) {
    StereoImagePair pair;
    ASSERT_TRUE(camera.Grab(milliseconds(1), &pair).ok());
    clock.Advance(milliseconds(33));
    pairer.AddLeft({pair.stamp, pair.left});
    if (i != 7 && i != 12) pairer.AddRight({pair.stamp + milliseconds(3), pair.right});
    while (auto matched = pairer.PopPair()) {
      ++pairs;
      EXPECT_EQ(matched->left.at<cv::Vec3b>(5, 5) != cv::Vec3b(), true);
    }
  }
  EXPECT_EQ(pairs, 18);
  EXPECT_EQ(pairer.stats().dropped_left, 2u);
  EXPECT_EQ(pairer.stats().dropped_right, 0u);
  EXPECT_EQ(pairer.stats().last_skew, -milliseconds(3));
}

TEST(FakeStereoCameraTest, SyntheticImagesAreDeterministicAndDifferPerEye) {
  const cv::Mat a = MakeSyntheticImage(64, 48, 3, false);
  const cv::Mat b = MakeSyntheticImage(64, 48, 3, false);
  const cv::Mat right = MakeSyntheticImage(64, 48, 3, true);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, right, cv::NORM_L1), 0.0);
}

}  // namespace
}  // namespace mostar::camera
