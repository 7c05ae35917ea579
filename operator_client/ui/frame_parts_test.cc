#include "operator_client/ui/frame_parts.h"

#include <gtest/gtest.h>

namespace mostar::ui {
namespace {

TEST(FramePartsTest, OneRowPerPartWithPercentilesOverTheWindow) {
  FrameParts parts(/*window=*/20);
  EXPECT_EQ(parts.Rows().size(), static_cast<size_t>(kFramePartCount));
  EXPECT_EQ(parts.Rows()[0].samples, 0u);
  EXPECT_DOUBLE_EQ(parts.Rows()[0].p95_ms, 0.0);
  for (int i = 0; i < 30; ++i) {
    // The first 10 frames are slow and leave the window.
    const double scale = i < 10 ? 100.0 : 1.0;
    parts.Add({1.0 * scale, 2.0 * scale, 3.0 * scale, i == 29 ? 40.0 : 4.0});
  }
  const std::vector<LatencyRow> rows = parts.Rows();
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0].name, "overlay");
  EXPECT_EQ(rows[1].name, "eyes");
  EXPECT_EQ(rows[2].name, "compose");
  EXPECT_EQ(rows[3].name, "panels");
  EXPECT_EQ(rows[0].samples, 20u);
  EXPECT_DOUBLE_EQ(rows[0].p95_ms, 1.0);
  EXPECT_DOUBLE_EQ(rows[1].p50_ms, 2.0);
  EXPECT_DOUBLE_EQ(rows[3].p50_ms, 4.0);
  EXPECT_DOUBLE_EQ(rows[3].p95_ms, 4.0);  // nearest rank 19 of 20: the one slow frame is above
  EXPECT_EQ(parts.frames(), 20u);
}

TEST(FramePartsTest, NegativeTimesCountAsZero) {
  FrameParts parts;
  parts.Add({-1.0, 0.5, 0.5, 0.5});
  EXPECT_DOUBLE_EQ(parts.Rows()[0].p50_ms, 0.0);
}

}  // namespace
}  // namespace mostar::ui
