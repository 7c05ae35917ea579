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

const SteadyTime kT0 = SteadyTime(std::chrono::seconds(100));
// A wait no test reaches unless it says so.
constexpr Duration kLongWait = std::chrono::seconds(10);

TEST(FramePickerTest, ShowsTheLatestPairUntilTheFirstResult) {
  FramePicker picker;
  EXPECT_TRUE(picker.TakeNew(Pair(1), kT0));
  picker.OnResult(nullptr, Pair(1), kT0, kLongWait);
  ASSERT_TRUE(picker.shown_pair());
  EXPECT_EQ(picker.shown_pair()->sequence, 1u);
  EXPECT_EQ(picker.shown_result(), nullptr);
  EXPECT_EQ(picker.result_state(), FramePicker::ResultState::kWaiting);
  EXPECT_EQ(picker.counts().without_result, 1u);
  // Once something is shown, newer unprocessed pairs wait for their results.
  EXPECT_TRUE(picker.TakeNew(Pair(2), kT0));
  picker.OnResult(nullptr, Pair(2), kT0, kLongWait);
  EXPECT_EQ(picker.shown_pair()->sequence, 1u);
}

TEST(FramePickerTest, DrawsTheCorrectedScanOnlyWithTheResultOfTheShownPair) {
  FramePicker picker;
  LaserScan nearest;
  nearest.ranges_m = {1.0f, 2.0f};
  EXPECT_EQ(picker.ScanToDraw(nearest).scan->ranges_m, nearest.ranges_m);  // nothing shown yet
  EXPECT_FALSE(picker.ScanToDraw(nearest).placement);  // to be moved by the caller
  EXPECT_FALSE(picker.ScanToDraw(std::nullopt).scan);
  picker.TakeNew(Pair(1), kT0);
  auto result = std::make_shared<vision::VisionResult>();
  result->sequence = 1;
  result->ok = true;
  result->classification.corrected_scan.ranges_m = {1.5f, 2.5f};
  result->placement.at_image_time = true;
  picker.OnResult(result, Pair(1), kT0, kLongWait);
  const FramePicker::DrawnScan drawn = picker.ScanToDraw(nearest);
  EXPECT_EQ(drawn.scan->ranges_m, result->classification.corrected_scan.ranges_m);
  // Placed by edge processing: drawn where it is, not moved a second time.
  ASSERT_TRUE(drawn.placement);
  EXPECT_TRUE(drawn.placement->at_image_time);
  // A result without a corrected scan (edge processing found nothing to correct) draws `nearest`.
  picker.TakeNew(Pair(2), kT0);
  picker.OnResult(Result(2), Pair(2), kT0, kLongWait);
  EXPECT_EQ(picker.ScanToDraw(nearest).scan->ranges_m, nearest.ranges_m);
  EXPECT_FALSE(picker.ScanToDraw(nearest).placement);
}

TEST(FramePickerTest, TakesEachPairOnce) {
  FramePicker picker;
  EXPECT_FALSE(picker.TakeNew(std::nullopt, kT0));
  EXPECT_TRUE(picker.TakeNew(Pair(1), kT0));
  EXPECT_FALSE(picker.TakeNew(Pair(1), kT0));
  EXPECT_TRUE(picker.TakeNew(Pair(2), kT0));
  EXPECT_EQ(picker.in_flight(), 2u);
}

TEST(FramePickerTest, ShowsThePairTheResultBelongsTo) {
  FramePicker picker;
  for (uint64_t s = 1; s <= 3; ++s) picker.TakeNew(Pair(s), kT0);
  const auto result = Result(2);
  picker.OnResult(result, Pair(3), kT0, kLongWait);
  EXPECT_EQ(picker.shown_pair()->sequence, 2u);
  EXPECT_EQ(picker.shown_result(), result);
  EXPECT_EQ(picker.result_sequence(), 2u);
  // Pair 1 can no longer be shown (older than what is on screen); pair 3 is still awaited.
  EXPECT_EQ(picker.in_flight(), 1u);
  // The same result again changes nothing.
  picker.OnResult(result, Pair(3), kT0, kLongWait);
  EXPECT_EQ(picker.shown_pair()->sequence, 2u);
  picker.OnResult(Result(3), Pair(3), kT0, kLongWait);
  EXPECT_EQ(picker.shown_pair()->sequence, 3u);
  EXPECT_EQ(picker.in_flight(), 0u);
}

TEST(FramePickerTest, FailedResultShowsThePairWithoutResult) {
  FramePicker picker;
  picker.TakeNew(Pair(1), kT0);
  picker.OnResult(Result(1, /*ok=*/false), Pair(1), kT0, kLongWait);
  EXPECT_EQ(picker.shown_pair()->sequence, 1u);
  EXPECT_EQ(picker.shown_result(), nullptr);
  EXPECT_EQ(picker.result_sequence(), 1u);
}

TEST(FramePickerTest, KeepsAtMostFourPairsInFlight) {
  FramePicker picker;
  for (uint64_t s = 1; s <= 6; ++s) picker.TakeNew(Pair(s), kT0);
  EXPECT_EQ(picker.in_flight(), FramePicker::kMaxInFlight);
  // The result for a dropped pair cannot be shown: nothing changes (here: the latest is shown).
  picker.OnResult(Result(2), Pair(6), kT0, kLongWait);
  EXPECT_EQ(picker.shown_pair()->sequence, 6u);
  EXPECT_EQ(picker.shown_result(), nullptr);
  EXPECT_EQ(picker.result_sequence(), 0u);
  // Pair 3's result would take the picture back from pair 6: missed, pair 6 stays.
  picker.OnResult(Result(3), Pair(6), kT0, kLongWait);
  EXPECT_EQ(picker.shown_pair()->sequence, 6u);
  EXPECT_EQ(picker.counts().missed, 1u);
  picker.OnResult(Result(6), Pair(6), kT0, kLongWait);
  EXPECT_EQ(picker.shown_pair()->sequence, 6u);
  EXPECT_EQ(picker.result_sequence(), 6u);
}

TEST(FramePickerTest, UnprocessedShowsLatestAndForgetsPairsInFlight) {
  FramePicker picker;
  picker.TakeNew(Pair(1), kT0);
  picker.OnResult(Result(1), Pair(1), kT0, kLongWait);
  picker.TakeNew(Pair(2), kT0);
  picker.ShowUnprocessed(Pair(3));
  EXPECT_EQ(picker.shown_pair()->sequence, 3u);
  EXPECT_EQ(picker.shown_result(), nullptr);
  EXPECT_EQ(picker.in_flight(), 0u);
  picker.ShowUnprocessed(std::nullopt);
  EXPECT_FALSE(picker.shown_pair());
}

TEST(FramePickerTest, APairIsShownWithoutItsResultWhenTheWaitRunsOutAndTheResultIsAddedLater) {
  FramePicker picker;
  constexpr Duration kWait = std::chrono::milliseconds(10);
  picker.TakeNew(Pair(1), kT0);
  picker.OnResult(Result(1), Pair(1), kT0 + std::chrono::milliseconds(4), kWait);
  EXPECT_EQ(picker.result_state(), FramePicker::ResultState::kInTime);
  const uint64_t version = picker.shown_version();
  // Pair 2 waits for its result until kT0 + 30 ms.
  const SteadyTime taken = kT0 + std::chrono::milliseconds(20);
  picker.TakeNew(Pair(2), taken);
  EXPECT_EQ(picker.NextWaitEnd(kWait), taken + kWait);
  picker.OnResult(Result(1), Pair(2), taken + std::chrono::milliseconds(9), kWait);
  EXPECT_EQ(picker.shown_pair()->sequence, 1u);
  EXPECT_EQ(picker.shown_version(), version);  // nothing to draw again
  picker.OnResult(Result(1), Pair(2), taken + kWait, kWait);
  EXPECT_EQ(picker.shown_pair()->sequence, 2u);
  EXPECT_EQ(picker.shown_result(), nullptr);
  EXPECT_EQ(picker.result_state(), FramePicker::ResultState::kWaiting);
  EXPECT_EQ(picker.shown_ready_at(), taken + kWait);
  EXPECT_FALSE(picker.NextWaitEnd(kWait));
  EXPECT_GT(picker.shown_version(), version);
  // Its result comes: added to the same pair, which keeps the time it was first shown.
  const auto late = Result(2);
  picker.OnResult(late, Pair(2), taken + std::chrono::milliseconds(25), kWait);
  EXPECT_EQ(picker.shown_pair()->sequence, 2u);
  EXPECT_EQ(picker.shown_result(), late);
  EXPECT_EQ(picker.result_state(), FramePicker::ResultState::kAddedLate);
  EXPECT_EQ(picker.shown_ready_at(), taken + kWait);
  EXPECT_EQ(picker.result_sequence(), 2u);
  EXPECT_EQ(picker.counts().in_time, 1u);
  EXPECT_EQ(picker.counts().without_result, 1u);
  EXPECT_EQ(picker.counts().added_late, 1u);
  EXPECT_EQ(picker.in_flight(), 0u);
}

TEST(FramePickerTest, AResultInTimeIsShownAtItsPublication) {
  FramePicker picker;
  constexpr Duration kWait = std::chrono::milliseconds(10);
  picker.TakeNew(Pair(1), kT0);
  auto result = std::make_shared<vision::VisionResult>();
  result->sequence = 1;
  result->ok = true;
  result->published = kT0 + std::chrono::milliseconds(3);
  picker.OnResult(result, Pair(1), kT0 + std::chrono::milliseconds(5), kWait);
  EXPECT_EQ(picker.shown_ready_at(), result->published);
}

TEST(FramePickerTest, OnlyTheNewestPairInFlightIsShownWhenTheWaitRunsOut) {
  FramePicker picker;
  constexpr Duration kWait = std::chrono::milliseconds(10);
  picker.TakeNew(Pair(1), kT0);
  picker.OnResult(Result(1), Pair(1), kT0, kWait);
  picker.TakeNew(Pair(2), kT0 + std::chrono::milliseconds(1));
  picker.TakeNew(Pair(3), kT0 + std::chrono::milliseconds(2));
  // Pair 2's wait ran out but pair 3's has not: nothing changes yet.
  picker.OnResult(Result(1), Pair(3), kT0 + std::chrono::milliseconds(11), kWait);
  EXPECT_EQ(picker.shown_pair()->sequence, 1u);
  picker.OnResult(Result(1), Pair(3), kT0 + std::chrono::milliseconds(12), kWait);
  EXPECT_EQ(picker.shown_pair()->sequence, 3u);
  // Pair 2's result now would go back in time: missed.
  picker.OnResult(Result(2), Pair(3), kT0 + std::chrono::milliseconds(13), kWait);
  EXPECT_EQ(picker.shown_pair()->sequence, 3u);
  EXPECT_EQ(picker.counts().missed, 1u);
  EXPECT_EQ(picker.in_flight(), 1u);  // pair 3 still awaits its result
}

TEST(FramePickerTest, AZeroWaitShowsEachPairAtOnce) {
  FramePicker picker;
  picker.TakeNew(Pair(1), kT0);
  picker.OnResult(nullptr, Pair(1), kT0, Duration(0));
  picker.TakeNew(Pair(2), kT0);
  picker.OnResult(nullptr, Pair(2), kT0, Duration(0));
  EXPECT_EQ(picker.shown_pair()->sequence, 2u);
  EXPECT_EQ(picker.result_state(), FramePicker::ResultState::kWaiting);
}

}  // namespace
}  // namespace mostar::ui
