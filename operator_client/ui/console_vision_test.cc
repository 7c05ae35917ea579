#include "operator_client/ui/console_vision.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

#include "operator_client/fusion/test_scenes.h"

namespace mostar::ui {
namespace {

using std::chrono::seconds;

client::DecodedStereoPair Pair(uint64_t sequence) {
  client::DecodedStereoPair pair;
  pair.sequence = sequence;
  pair.stamp = FromUnixNanos(static_cast<int64_t>(sequence) * 40'000'000);
  return pair;
}

// Records what the worker was handed and answers with a stereo result whose NESC residual is
// 4 px.
struct FakeProcess {
  std::mutex mutex;
  std::vector<vision::VisionInput> inputs;
  std::atomic<int> calls{0};

  vision::EdgeWorker::ProcessFunction Function() {
    return [this](const vision::VisionInput& input, vision::VisionResult* result) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        inputs.push_back(input);
      }
      result->stamp = input.stamp;
      result->sequence = input.sequence;
      result->ok = true;
      result->stereo = true;
      result->nesc.offset.valid = true;
      result->nesc.offset.vertical_offset_px = 4.0;
      result->nesc.offset.samples = 20;
      ++calls;
    };
  }
};

// Polls until the worker's result for `sequence` is shown (bounded).
bool ShowResult(ConsoleVision* vision, const client::DecodedStereoPair& pair,
                const ConsoleVision::ScanForImage& nearest, const fusion::ArFeatureBuilder& b) {
  for (int i = 0; i < 2000; ++i) {
    vision->Update(pair, true, SteadyTime{}, nearest, b);  // the wait never runs out
    const auto& shown = vision->picker().shown_result();
    if (shown && shown->sequence == pair.sequence) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return false;
}

TEST(ConsoleVisionTest, HandsEachNewPairOverOnceWithItsPlacedScanModelsAndOutlierLabels) {
  FakeProcess fake;
  ConsoleVision vision(vision::VisionOptions{}, fake.Function());
  auto left =
      std::make_shared<const math::CameraModel>(math::LaserCameraCalibration{}, math::kMonoCamera);
  auto right =
      std::make_shared<const math::CameraModel>(math::LaserCameraCalibration{}, math::kMonoCamera);
  vision.GeometryChanged(left, right);
  fusion::testing::Scene wall;
  wall.segments.push_back({3.0, -6.0, 3.0, 6.0});
  const LaserScan scan = fusion::testing::MakeScan(wall, 181);
  std::vector<Time> asked;
  const ConsoleVision::ScanForImage nearest = [&](Time stamp) {
    asked.push_back(stamp);
    ConsoleVision::PlacedScan placed{scan, {}};
    placed.placement.at_image_time = true;
    placed.placement.measured_stamp = stamp - std::chrono::milliseconds(30);
    return std::optional<ConsoleVision::PlacedScan>(placed);
  };
  const fusion::ArFeatureBuilder builder{fusion::ArFeatureOptions{}};
  ASSERT_TRUE(ShowResult(&vision, Pair(1), nearest, builder));
  ASSERT_EQ(fake.calls.load(), 1);  // taken once however many ticks it took
  std::lock_guard<std::mutex> lock(fake.mutex);
  const vision::VisionInput& input = fake.inputs.front();
  EXPECT_EQ(input.sequence, 1u);
  ASSERT_EQ(asked.size(), 1u);
  EXPECT_EQ(asked.front(), Pair(1).stamp);
  EXPECT_EQ(input.scan.ranges_m, scan.ranges_m);
  // The placement travels with the scan (the result hands it to the overlay).
  EXPECT_TRUE(input.placement.at_image_time);
  EXPECT_EQ(input.placement.measured_stamp, Pair(1).stamp - std::chrono::milliseconds(30));
  EXPECT_EQ(input.potential_outliers.size(), scan.ranges_m.size());
  EXPECT_EQ(input.left_camera, left);
  EXPECT_EQ(input.right_camera, right);
}

TEST(ConsoleVisionTest, APairIsShownWithoutItsResultOnceTheWaitEndsAndTheResultIsAddedLater) {
  // A worker held until released: its result for pair 1 comes after the wait.
  std::mutex gate;
  gate.lock();
  std::atomic<int> calls{0};
  ConsoleVision vision(vision::VisionOptions{},
                       [&](const vision::VisionInput& input, vision::VisionResult* result) {
                         std::lock_guard<std::mutex> held(gate);
                         result->sequence = input.sequence;
                         result->stamp = input.stamp;
                         result->ok = true;
                         ++calls;
                       });
  WakeSignal wake;
  vision.SetWakeSignal(&wake);
  vision.SetResultWait(std::chrono::milliseconds(10));
  const fusion::ArFeatureBuilder builder{fusion::ArFeatureOptions{}};
  const auto none = [](Time) { return std::optional<ConsoleVision::PlacedScan>(); };
  const SteadyTime t0 = SteadyTime(std::chrono::seconds(50));
  vision.Update(Pair(1), true, t0, none, builder);  // nothing shown yet: shown at once
  vision.Update(Pair(2), true, t0, none, builder);
  EXPECT_EQ(vision.picker().shown_pair()->sequence, 1u);
  ASSERT_TRUE(vision.NextWaitEnd().has_value());
  EXPECT_EQ(*vision.NextWaitEnd(), t0 + std::chrono::milliseconds(10));
  vision.Update(Pair(2), true, t0 + std::chrono::milliseconds(10), none, builder);
  EXPECT_EQ(vision.picker().shown_pair()->sequence, 2u);
  EXPECT_EQ(vision.picker().result_state(), FramePicker::ResultState::kWaiting);
  gate.unlock();
  // The worker's results wake the loop; pair 2's is added to the shown pair.
  bool added = false;
  for (int i = 0; i < 200 && !added; ++i) {
    wake.WaitFor(std::chrono::milliseconds(50));
    vision.Update(Pair(2), true, t0 + std::chrono::milliseconds(20), none, builder);
    added = vision.picker().result_state() == FramePicker::ResultState::kAddedLate;
  }
  ASSERT_TRUE(added);
  EXPECT_EQ(vision.picker().shown_result()->sequence, 2u);
  EXPECT_GE(wake.notifications(), 1u);
  vision.SetWakeSignal(nullptr);
}

TEST(ConsoleVisionTest, DisabledShowsTheLatestPairWithoutTheWorker) {
  FakeProcess fake;
  ConsoleVision vision(vision::VisionOptions{}, fake.Function());
  const fusion::ArFeatureBuilder builder{fusion::ArFeatureOptions{}};
  vision.Update(
      Pair(5), false, SteadyTime{}, [](Time) { return std::optional<ConsoleVision::PlacedScan>(); },
      builder);
  ASSERT_TRUE(vision.picker().shown_pair());
  EXPECT_EQ(vision.picker().shown_pair()->sequence, 5u);
  EXPECT_EQ(fake.calls.load(), 0);
}

TEST(ConsoleVisionTest, TheOffsetHintIsStaleAfterAGeometryChangeUntilANewPairIsProcessed) {
  FakeProcess fake;
  ConsoleVision vision(vision::VisionOptions{}, fake.Function());
  const fusion::ArFeatureBuilder builder{fusion::ArFeatureOptions{}};
  const auto none = [](Time) { return std::optional<ConsoleVision::PlacedScan>(); };
  const auto suggest = [](double residual_px) { return static_cast<float>(-residual_px); };
  ASSERT_TRUE(ShowResult(&vision, Pair(1), none, builder));
  std::optional<StereoOffsetHint> hint = vision.OffsetHint(suggest);
  ASSERT_TRUE(hint.has_value());
  EXPECT_FLOAT_EQ(hint->suggested_right_offset_y_px, -4.f);
  vision.GeometryChanged(nullptr, nullptr);  // e.g. the offset was applied
  EXPECT_FALSE(vision.OffsetHint(suggest).has_value());
  ASSERT_TRUE(ShowResult(&vision, Pair(2), none, builder));
  EXPECT_TRUE(vision.OffsetHint(suggest).has_value());
}

TEST(ConsoleVisionTest, SettingsTheWorkerRefusesAreNotTaken) {
  FakeProcess fake;  // a custom process refuses every options change
  ConsoleVision vision(vision::VisionOptions{}, fake.Function());
  VisionSettings next(vision::VisionOptions{});
  std::string error;
  ASSERT_TRUE(next.SetEdgeThreshold(0.2, &error)) << error;
  EXPECT_FALSE(vision.ApplySettings(next, &error));
  EXPECT_FALSE(error.empty());
  EXPECT_NE(vision.settings().options().classifier.edge_threshold_m,
            next.options().classifier.edge_threshold_m);

  ConsoleVision real(vision::VisionOptions{});
  EXPECT_TRUE(real.ApplySettings(next, &error)) << error;
  EXPECT_EQ(real.settings().options().classifier.edge_threshold_m,
            next.options().classifier.edge_threshold_m);
}

}  // namespace
}  // namespace mostar::ui
