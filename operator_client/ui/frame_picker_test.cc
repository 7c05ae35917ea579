#include "operator_client/ui/frame_picker.h"

#include <gtest/gtest.h>

namespace mostar::ui {
namespace {

client::DecodedStereoPair Pair(uint64_t sequence) {
  client::DecodedStereoPair pair;
  pair.sequence = sequence;
  pair.stamp = FromUnixNanos(static_cast<int64_t>(sequence) * 40'000'000);
  return pair;
}

std::shared_ptr<const vision::VisionResult> Result(uint64_t sequence, bool ok = true) {
  auto result = std::make_shared<vision::VisionResult>();
  result->sequence = sequence;
  result->ok = ok;
  return result;
}

TEST(FramePickerTest, ShowsTheLatestPairUntilTheFirstResult) {
  FramePicker picker;
  EXPECT_TRUE(picker.TakeNew(Pair(1)));
  picker.OnResult(nullptr, Pair(1));
  ASSERT_TRUE(picker.shown_pair());
  EXPECT_EQ(picker.shown_pair()->sequence, 1u);
  EXPECT_EQ(picker.shown_result(), nullptr);
  // Once something is shown, newer unprocessed pairs wait for their results.
  EXPECT_TRUE(picker.TakeNew(Pair(2)));
  picker.OnResult(nullptr, Pair(2));
  EXPECT_EQ(picker.shown_pair()->sequence, 1u);
}

TEST(FramePickerTest, DrawsTheCorrectedScanOnlyWithTheResultOfTheShownPair) {
  FramePicker picker;
  LaserScan nearest;
  nearest.ranges_m = {1.0f, 2.0f};
  EXPECT_EQ(picker.ScanToDraw(nearest).scan->ranges_m, nearest.ranges_m);  // nothing shown yet
  EXPECT_FALSE(picker.ScanToDraw(nearest).placement);  // to be moved by the caller
  EXPECT_FALSE(picker.ScanToDraw(std::nullopt).scan);
  picker.TakeNew(Pair(1));
  auto result = std::make_shared<vision::VisionResult>();
  result->sequence = 1;
  result->ok = true;
  result->classification.corrected_scan.ranges_m = {1.5f, 2.5f};
  result->placement.at_image_time = true;
  picker.OnResult(result, Pair(1));
  const FramePicker::DrawnScan drawn = picker.ScanToDraw(nearest);
  EXPECT_EQ(drawn.scan->ranges_m, result->classification.corrected_scan.ranges_m);
  // Placed by edge processing: drawn where it is, not moved a second time.
  ASSERT_TRUE(drawn.placement);
  EXPECT_TRUE(drawn.placement->at_image_time);
  // A result without a corrected scan (edge processing found nothing to correct) draws `nearest`.
  picker.TakeNew(Pair(2));
  picker.OnResult(Result(2), Pair(2));
  EXPECT_EQ(picker.ScanToDraw(nearest).scan->ranges_m, nearest.ranges_m);
  EXPECT_FALSE(picker.ScanToDraw(nearest).placement);
}

TEST(FramePickerTest, TakesEachPairOnce) {
  FramePicker picker;
  EXPECT_FALSE(picker.TakeNew(std::nullopt));
  EXPECT_TRUE(picker.TakeNew(Pair(1)));
  EXPECT_FALSE(picker.TakeNew(Pair(1)));
  EXPECT_TRUE(picker.TakeNew(Pair(2)));
  EXPECT_EQ(picker.in_flight(), 2u);
}

TEST(FramePickerTest, ShowsThePairTheResultBelongsTo) {
  FramePicker picker;
  for (uint64_t s = 1; s <= 3; ++s) picker.TakeNew(Pair(s));
  const auto result = Result(2);
  picker.OnResult(result, Pair(3));
  EXPECT_EQ(picker.shown_pair()->sequence, 2u);
  EXPECT_EQ(picker.shown_result(), result);
  EXPECT_EQ(picker.result_sequence(), 2u);
  // Pair 1 can no longer be shown (older than what is on screen); pair 3 is still awaited.
  EXPECT_EQ(picker.in_flight(), 1u);
  // The same result again changes nothing.
  picker.OnResult(result, Pair(3));
  EXPECT_EQ(picker.shown_pair()->sequence, 2u);
  picker.OnResult(Result(3), Pair(3));
  EXPECT_EQ(picker.shown_pair()->sequence, 3u);
  EXPECT_EQ(picker.in_flight(), 0u);
}

TEST(FramePickerTest, FailedResultShowsThePairWithoutResult) {
  FramePicker picker;
  picker.TakeNew(Pair(1));
  picker.OnResult(Result(1, /*ok=*/false), Pair(1));
  EXPECT_EQ(picker.shown_pair()->sequence, 1u);
  EXPECT_EQ(picker.shown_result(), nullptr);
  EXPECT_EQ(picker.result_sequence(), 1u);
}

TEST(FramePickerTest, KeepsAtMostFourPairsInFlight) {
  FramePicker picker;
  for (uint64_t s = 1; s <= 6; ++s) picker.TakeNew(Pair(s));
  EXPECT_EQ(picker.in_flight(), FramePicker::kMaxInFlight);
  // The result for a dropped pair cannot be shown: nothing changes (here: the latest is shown).
  picker.OnResult(Result(2), Pair(6));
  EXPECT_EQ(picker.shown_pair()->sequence, 6u);
  EXPECT_EQ(picker.shown_result(), nullptr);
  EXPECT_EQ(picker.result_sequence(), 0u);
  picker.OnResult(Result(3), Pair(6));
  EXPECT_EQ(picker.shown_pair()->sequence, 3u);
}

TEST(FramePickerTest, UnprocessedShowsLatestAndForgetsPairsInFlight) {
  FramePicker picker;
  picker.TakeNew(Pair(1));
  picker.OnResult(Result(1), Pair(1));
  picker.TakeNew(Pair(2));
  picker.ShowUnprocessed(Pair(3));
  EXPECT_EQ(picker.shown_pair()->sequence, 3u);
  EXPECT_EQ(picker.shown_result(), nullptr);
  EXPECT_EQ(picker.in_flight(), 0u);
  picker.ShowUnprocessed(std::nullopt);
  EXPECT_FALSE(picker.shown_pair());
}

}  // namespace
}  // namespace mostar::ui
