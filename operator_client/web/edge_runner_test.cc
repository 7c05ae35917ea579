#include "operator_client/web/edge_runner.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "operator_client/fusion/test_scenes.h"
#include "operator_client/web/frame_composer.h"

namespace mostar::web {
namespace {

std::vector<uint8_t> Jpeg(int width_px, int height_px) {
  cv::Mat image(height_px, width_px, CV_8UC3, cv::Scalar(90, 90, 90));
  cv::rectangle(image, cv::Rect(width_px / 3, height_px / 4, width_px / 4, height_px / 2),
                cv::Scalar(230, 230, 230), cv::FILLED);
  std::vector<uint8_t> bytes;
  cv::imencode(".jpg", image, bytes);
  return bytes;
}

EdgeJob Job(FrameComposer* composer, uint64_t sequence, const std::vector<uint8_t>& left,
            const std::vector<uint8_t>& right) {
  EdgeJob job;
  job.sequence = sequence;
  job.pair.left.stamp = job.pair.right.stamp = FromUnixNanos(1700000000000000000);
  job.pair.left.data = left;
  job.pair.right.data = right;
  job.scan = fusion::testing::MakeScan(fusion::testing::Room(), 181);
  job.potential_outliers = composer->PotentialOutliers(job.scan);
  job.left_camera = composer->left_model();
  job.right_camera = composer->right_model();
  return job;
}

// Waits (no time limit: CTest's timeout catches a hang) until `count` jobs were handled.
void WaitForHandled(const EdgeRunner& runner, uint64_t count) {
  while (runner.stats().processed + runner.stats().broken < count) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

TEST(EdgeRunnerTest, DecodesBothEyesAndTagsTheResultWithTheJobsSequence) {
  FrameComposer composer{ComposerOptions{}};
  EdgeRunner runner{vision::VisionOptions{}};
  EXPECT_EQ(runner.LatestResult(), nullptr);
  const std::vector<uint8_t> jpeg = Jpeg(640, 480);
  runner.Submit(Job(&composer, 7, jpeg, jpeg));
  WaitForHandled(runner, 1);
  const std::shared_ptr<const vision::VisionResult> result = runner.LatestResult();
  ASSERT_NE(result, nullptr);
  EXPECT_EQ(result->sequence, 7u);
  EXPECT_EQ(result->stamp, FromUnixNanos(1700000000000000000));
  EXPECT_TRUE(result->ok) << result->error;
  EXPECT_EQ(result->classification.corrected_scan.ranges_m.size(), 181u);
  const EdgeRunner::Stats stats = runner.stats();
  EXPECT_EQ(stats.submitted, 1u);
  EXPECT_EQ(stats.processed, 1u);
  EXPECT_EQ(stats.failed, 0u);
  EXPECT_EQ(stats.broken, 0u);
}

TEST(EdgeRunnerTest, BrokenOrOversizedImagesAreCountedAndGiveNoResult) {
  FrameComposer composer{ComposerOptions{}};
  EdgeRunner runner{vision::VisionOptions{}};
  const std::vector<uint8_t> good = Jpeg(640, 480);
  runner.Submit(Job(&composer, 1, {0xff, 0xd8, 0x00, 0x01}, good));
  WaitForHandled(runner, 1);
  runner.Submit(Job(&composer, 2, good, Jpeg(1280, 960)));  // more pixels than the camera's
  WaitForHandled(runner, 2);
  EXPECT_EQ(runner.stats().broken, 2u);
  EXPECT_EQ(runner.stats().processed, 0u);
  EXPECT_EQ(runner.LatestResult(), nullptr);
  // The runner goes on with the next good pair.
  runner.Submit(Job(&composer, 3, good, good));
  WaitForHandled(runner, 3);
  ASSERT_NE(runner.LatestResult(), nullptr);
  EXPECT_EQ(runner.LatestResult()->sequence, 3u);
}

TEST(EdgeRunnerTest, ANewerJobReplacesAWaitingOne) {
  FrameComposer composer{ComposerOptions{}};
  EdgeRunner runner{vision::VisionOptions{}};
  const std::vector<uint8_t> jpeg = Jpeg(640, 480);
  for (uint64_t s = 1; s <= 20; ++s) runner.Submit(Job(&composer, s, jpeg, jpeg));
  const EdgeRunner::Stats submitted = runner.stats();
  EXPECT_EQ(submitted.submitted, 20u);
  // Every job is either replaced or handled: nothing queues.
  WaitForHandled(runner, 20 - submitted.replaced);
  EXPECT_EQ(runner.stats().processed + runner.stats().replaced, 20u);
  EXPECT_EQ(runner.LatestResult()->sequence, 20u) << "the newest job is never dropped";
}

}  // namespace
}  // namespace mostar::web
