#include "robot_server/camera/file_stereo_camera.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "common/time/fake_clock.h"
#include "robot_server/camera/fake_stereo_camera.h"

namespace mostar::camera {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;

class FileStereoCameraTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "mostar_file_camera_XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes `count` PNG pairs left_NNN.png / right_NNN.png; pixel (0,0) blue = index (left)
  // or 100 + index (right).
  void WritePairs(int count, int width = 80, int height = 60) {
    for (int i = 0; i < count; ++i) {
      cv::Mat left = MakeSyntheticImage(width, height, static_cast<uint64_t>(i), false);
      cv::Mat right = MakeSyntheticImage(width, height, static_cast<uint64_t>(i), true);
      left.at<cv::Vec3b>(0, 0) = cv::Vec3b(static_cast<uint8_t>(i), 0, 0);
      right.at<cv::Vec3b>(0, 0) = cv::Vec3b(static_cast<uint8_t>(100 + i), 0, 0);
      char name[32];
      std::snprintf(name, sizeof(name), "%03d.png", i);
      ASSERT_TRUE(cv::imwrite((dir_ / ("left_" + std::string(name))).string(), left));
      ASSERT_TRUE(cv::imwrite((dir_ / ("right_" + std::string(name))).string(), right));
    }
  }

  FileStereoCamera::Options SequenceOptions() const {
    FileStereoCamera::Options options;
    options.source = FileStereoCamera::Source::kTwoImageSequences;
    options.left = (dir_ / "left_*.png").string();
    options.right = (dir_ / "right_*.png").string();
    options.clock = &clock_;
    return options;
  }

  fs::path dir_;
  FakeClock clock_;
};

TEST_F(FileStereoCameraTest, ReadsImageSequencesInOrderThenEnds) {
  WritePairs(3);
  FileStereoCamera camera(SequenceOptions());
  std::string error;
  ASSERT_TRUE(camera.Open(&error)) << error;
  EXPECT_EQ(camera.Info().width_px, 80);
  EXPECT_EQ(camera.Info().height_px, 60);
  EXPECT_EQ(camera.Info().backend, "file");
  for (int i = 0; i < 3; ++i) {
    StereoImagePair pair;
    const GrabResult result = camera.Grab(milliseconds(100), &pair);
    ASSERT_TRUE(result.ok()) << result.message;
    EXPECT_EQ(pair.sequence, static_cast<uint64_t>(i));
    EXPECT_EQ(pair.stamp, clock_.Now());
    EXPECT_EQ(pair.left.type(), CV_8UC3);
    EXPECT_EQ(pair.left.at<cv::Vec3b>(0, 0)[0], i);
    EXPECT_EQ(pair.right.at<cv::Vec3b>(0, 0)[0], 100 + i);
    // PNG is lossless: the rest of the image comes back exactly.
    cv::Mat expected = MakeSyntheticImage(80, 60, static_cast<uint64_t>(i), false);
    expected.at<cv::Vec3b>(0, 0) = pair.left.at<cv::Vec3b>(0, 0);
    EXPECT_EQ(cv::norm(expected, pair.left, cv::NORM_INF), 0.0);
  }
  StereoImagePair pair;
  EXPECT_EQ(camera.Grab(milliseconds(100), &pair).status, GrabStatus::kEndOfStream);
}

TEST_F(FileStereoCameraTest, DeliversTheNative1280x960Size) {
  WritePairs(1, 1280, 960);
  FileStereoCamera camera(SequenceOptions());
  std::string error;
  ASSERT_TRUE(camera.Open(&error)) << error;
  EXPECT_EQ(camera.Info().width_px, 1280);
  EXPECT_EQ(camera.Info().height_px, 960);
  StereoImagePair pair;
  ASSERT_TRUE(camera.Grab(milliseconds(100), &pair).ok());
  EXPECT_EQ(pair.left.size(), cv::Size(1280, 960));
  EXPECT_EQ(pair.right.size(), cv::Size(1280, 960));
}

TEST_F(FileStereoCameraTest, LoopsWhenAsked) {
  WritePairs(2);
  FileStereoCamera::Options options = SequenceOptions();
  options.loop = true;
  FileStereoCamera camera(options);
  std::string error;
  ASSERT_TRUE(camera.Open(&error)) << error;
  std::vector<int> firsts;
  for (int i = 0; i < 5; ++i) {
    StereoImagePair pair;
    ASSERT_TRUE(camera.Grab(milliseconds(100), &pair).ok());
    firsts.push_back(pair.left.at<cv::Vec3b>(0, 0)[0]);
    EXPECT_EQ(pair.sequence, static_cast<uint64_t>(i));
  }
  EXPECT_EQ(firsts, (std::vector<int>{0, 1, 0, 1, 0}));
}

TEST_F(FileStereoCameraTest, RefusesMismatchedSequences) {
  WritePairs(2);
  fs::remove(dir_ / "right_001.png");
  FileStereoCamera camera(SequenceOptions());
  std::string error;
  EXPECT_FALSE(camera.Open(&error));
  EXPECT_NE(error.find("2 left images"), std::string::npos) << error;
  EXPECT_NE(error.find("1 right images"), std::string::npos) << error;
}

TEST_F(FileStereoCameraTest, ReportsAMissingSequence) {
  FileStereoCamera camera(SequenceOptions());
  std::string error;
  EXPECT_FALSE(camera.Open(&error));
  EXPECT_NE(error.find("no image matches"), std::string::npos) << error;
  StereoImagePair pair;
  EXPECT_EQ(camera.Grab(milliseconds(1), &pair).status, GrabStatus::kNotOpen);
}

TEST_F(FileStereoCameraTest, AnUnreadableImageIsAGrabErrorNotACrash) {
  WritePairs(2);
  {
    std::FILE* file = std::fopen((dir_ / "left_001.png").c_str(), "wb");
    ASSERT_NE(file, nullptr);
    std::fputs("not a png", file);
    std::fclose(file);
  }
  FileStereoCamera camera(SequenceOptions());
  std::string error;
  ASSERT_TRUE(camera.Open(&error)) << error;
  StereoImagePair pair;
  EXPECT_TRUE(camera.Grab(milliseconds(100), &pair).ok());
  const GrabResult result = camera.Grab(milliseconds(100), &pair);
  EXPECT_EQ(result.status, GrabStatus::kDeviceLost);
  EXPECT_NE(result.message.find("left_001.png"), std::string::npos) << result.message;
}

TEST_F(FileStereoCameraTest, SplitsASideBySideVideo) {
  const std::string path = (dir_ / "sbs.avi").string();
  {
    cv::VideoWriter writer(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 30,
                           cv::Size(160, 60));
    if (!writer.isOpened()) GTEST_SKIP() << "no MJPG video writer in this OpenCV build";
    for (int i = 0; i < 4; ++i) {
      cv::Mat both(60, 160, CV_8UC3);
      both(cv::Rect(0, 0, 80, 60)).setTo(cv::Scalar(200, 0, 0));
      both(cv::Rect(80, 0, 80, 60)).setTo(cv::Scalar(0, 0, 200));
      writer.write(both);
    }
  }
  FileStereoCamera::Options options;
  options.source = FileStereoCamera::Source::kSideBySideVideo;
  options.left = path;
  options.clock = &clock_;
  FileStereoCamera camera(options);
  std::string error;
  ASSERT_TRUE(camera.Open(&error)) << error;
  EXPECT_EQ(camera.Info().width_px, 80);
  int pairs = 0;
  StereoImagePair pair;
  while (camera.Grab(milliseconds(100), &pair).ok()) {
    ++pairs;
    EXPECT_EQ(pair.left.size(), cv::Size(80, 60));
    EXPECT_GT(pair.left.at<cv::Vec3b>(30, 40)[0], 150);   // blue left
    EXPECT_GT(pair.right.at<cv::Vec3b>(30, 40)[2], 150);  // red right
  }
  EXPECT_EQ(pairs, 4);
}

}  // namespace
}  // namespace mostar::camera
