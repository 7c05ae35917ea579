#include "operator_client/ui/latency_trace.h"

#include <gtest/gtest.h>

namespace mostar::ui {
namespace {

using std::chrono::milliseconds;

const Time kCapture = FromUnixNanos(1'800'000'000'000'000'000);

// Stage s ends (s + 1) * step after the previous one.
PairTimeline Complete(Time capture, int step_ms) {
  PairTimeline pair;
  pair.capture = capture;
  Time t = capture;
  for (int s = 0; s < kLatencyStageCount; ++s) {
    t += milliseconds((s + 1) * step_ms);
    pair.at[s] = t;
  }
  return pair;
}

const LatencyRow& Row(const std::vector<LatencyRow>& rows, const std::string& name) {
  for (const LatencyRow& r : rows) {
    if (r.name == name) return r;
  }
  static const LatencyRow kNone;
  ADD_FAILURE() << "no row " << name;
  return kNone;
}

TEST(LatencyTraceTest, StagesOfACompleteTimelineAddUpToTheTotal) {
  LatencyTrace trace;
  trace.Add(Complete(kCapture, 1));
  const std::vector<LatencyRow> rows = trace.Rows();
  ASSERT_EQ(rows.size(), static_cast<size_t>(kLatencyStageCount) + 2);
  EXPECT_EQ(rows[0].name, "encoded");
  EXPECT_DOUBLE_EQ(rows[0].p50_ms, 1.0);
  EXPECT_DOUBLE_EQ(Row(rows, "presented").p50_ms, 10.0);
  EXPECT_DOUBLE_EQ(Row(rows, "total").p50_ms, 55.0);  // 1 + 2 + ... + 10
  EXPECT_NEAR(Row(rows, "unexplained").p50_ms, 0.0, 1e-9);
  EXPECT_EQ(trace.pairs(), 1u);
}

TEST(LatencyTraceTest, AMissingStampLeavesItsTimeAndTheNextUnexplained) {
  PairTimeline pair = Complete(kCapture, 1);
  pair.at[static_cast<int>(LatencyStage::kWritten)].reset();  // e.g. no robot timing known
  LatencyTrace trace;
  trace.Add(pair);
  const std::vector<LatencyRow> rows = trace.Rows();
  EXPECT_EQ(Row(rows, "written").samples, 0u);
  EXPECT_EQ(Row(rows, "received").samples, 0u) << "its start is unknown";
  EXPECT_NEAR(Row(rows, "unexplained").p50_ms, 2.0 + 3.0, 1e-9);
  EXPECT_DOUBLE_EQ(Row(rows, "total").p50_ms, 55.0);
}

TEST(LatencyTraceTest, PairsThatNeverReachedTheScreenAreCountedNotTimed) {
  PairTimeline pair = Complete(kCapture, 1);
  pair.at[static_cast<int>(LatencyStage::kPresented)].reset();
  LatencyTrace trace;
  trace.Add(pair);
  EXPECT_EQ(trace.pairs(), 0u);
  EXPECT_EQ(trace.incomplete(), 1u);
  EXPECT_EQ(Row(trace.Rows(), "total").samples, 0u);
  EXPECT_DOUBLE_EQ(Row(trace.Rows(), "total").p95_ms, 0.0);
}

TEST(LatencyTraceTest, PercentilesOverTheLastWindowOfPairs) {
  LatencyTrace trace(/*window=*/10);
  for (int i = 0; i < 30; ++i)
    trace.Add(Complete(kCapture + milliseconds(33 * i), i < 20 ? 10 : 1));
  EXPECT_EQ(trace.pairs(), 10u);
  EXPECT_DOUBLE_EQ(Row(trace.Rows(), "total").p95_ms, 55.0) << "the slow pairs left the window";
  LatencyTrace mixed;
  for (int i = 0; i < 19; ++i) mixed.Add(Complete(kCapture, 1));
  mixed.Add(Complete(kCapture, 2));
  EXPECT_DOUBLE_EQ(Row(mixed.Rows(), "total").p50_ms, 55.0);
  EXPECT_DOUBLE_EQ(Row(mixed.Rows(), "total").p95_ms, 55.0);  // nearest rank 19 of 20
  mixed.Add(Complete(kCapture, 2));
  EXPECT_DOUBLE_EQ(Row(mixed.Rows(), "total").p95_ms, 110.0);  // rank 20 of 21
}

TEST(LatencyTraceTest, StageNamesAreDistinct) {
  for (int a = 0; a < kLatencyStageCount; ++a) {
    for (int b = a + 1; b < kLatencyStageCount; ++b) {
      EXPECT_STRNE(LatencyStageName(static_cast<LatencyStage>(a)),
                   LatencyStageName(static_cast<LatencyStage>(b)));
    }
  }
}

}  // namespace
}  // namespace mostar::ui
