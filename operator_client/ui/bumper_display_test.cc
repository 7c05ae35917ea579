#include "operator_client/ui/bumper_display.h"

#include <gtest/gtest.h>

namespace mostar::ui {
namespace {

const SteadyTime kNow = SteadyTime(std::chrono::seconds(100));

BumperState Belt(uint32_t pressed, uint32_t latched, bool readable = true) {
  BumperState s;
  s.segment_count = 16;
  s.pressed = pressed;
  s.latched = latched;
  s.readable = readable;
  return s;
}

TEST(BumperDisplayTest, SixteenSegmentsNamedCounterClockwiseFromAhead) {
  EXPECT_STREQ(SegmentDirection(0, 16), "front");
  EXPECT_STREQ(SegmentDirection(2, 16), "front-left");
  EXPECT_STREQ(SegmentDirection(4, 16), "left");
  EXPECT_STREQ(SegmentDirection(8, 16), "rear");
  EXPECT_STREQ(SegmentDirection(12, 16), "right");
  EXPECT_STREQ(SegmentDirection(15, 16), "front");  // 337.5 degrees: nearest is ahead
  EXPECT_STREQ(SegmentDirection(14, 16), "front-right");
  EXPECT_STREQ(SegmentDirection(3, 4), "right");
}

TEST(BumperDisplayTest, NothingKnownOrNoBeltShowsNothing) {
  EXPECT_TRUE(ViewBumpers(std::nullopt, kNow, kNow).segments.empty());
  BumperState none;
  const BumperView view = ViewBumpers(none, kNow, kNow);
  EXPECT_TRUE(view.segments.empty());
  EXPECT_FALSE(view.alert);
  EXPECT_TRUE(view.status.empty());
}

TEST(BumperDisplayTest, QuietBeltHasIdleSegmentsAndNoStatus) {
  const BumperView view = ViewBumpers(Belt(0, 0), kNow, kNow);
  ASSERT_EQ(view.segments.size(), 16u);
  for (SegmentLook look : view.segments) EXPECT_EQ(look, SegmentLook::kIdle);
  EXPECT_FALSE(view.alert);
  EXPECT_TRUE(view.status.empty());
}

TEST(BumperDisplayTest, PressedSegmentsOutrankLatchedOnesAndAreNamed) {
  const BumperView view = ViewBumpers(Belt(1u << 2, (1u << 2) | (1u << 8)), kNow, kNow);
  EXPECT_TRUE(view.alert);
  EXPECT_EQ(view.segments[2], SegmentLook::kPressed);
  EXPECT_EQ(view.segments[8], SegmentLook::kLatched);
  EXPECT_EQ(view.segments[0], SegmentLook::kIdle);
  EXPECT_NE(view.status.find("CONTACT"), std::string::npos);
  EXPECT_NE(view.status.find("front-left (2)"), std::string::npos);
}

TEST(BumperDisplayTest, ALatchAfterReleaseAsksForTheRearm) {
  const BumperView view = ViewBumpers(Belt(0, 1u << 8), kNow, kNow);
  EXPECT_TRUE(view.alert);
  EXPECT_NE(view.status.find("rear (8)"), std::string::npos);
  EXPECT_NE(view.status.find("re-arm"), std::string::npos);
}

TEST(BumperDisplayTest, UnreadableBeltAlertsAndBitsBeyondTheBeltAreIgnored) {
  const BumperView unreadable = ViewBumpers(Belt(0, 0, false), kNow, kNow);
  EXPECT_TRUE(unreadable.alert);
  EXPECT_NE(unreadable.status.find("UNREADABLE"), std::string::npos);
  const BumperView beyond = ViewBumpers(Belt(1u << 20, 1u << 31), kNow, kNow);
  EXPECT_FALSE(beyond.alert);
  EXPECT_TRUE(beyond.status.empty());
}

TEST(BumperDisplayTest, FlashesAtTwoHertzAndSaysWhenStale) {
  const BumperView a = ViewBumpers(Belt(1, 1), kNow, kNow);
  const BumperView b = ViewBumpers(Belt(1, 1), kNow, kNow + std::chrono::milliseconds(250));
  const BumperView c = ViewBumpers(Belt(1, 1), kNow, kNow + std::chrono::milliseconds(500));
  EXPECT_NE(a.flash_on, b.flash_on);
  EXPECT_EQ(a.flash_on, c.flash_on);
  EXPECT_FALSE(a.stale);
  const BumperView old = ViewBumpers(Belt(1, 1), kNow, kNow + std::chrono::seconds(4));
  EXPECT_TRUE(old.stale);
  EXPECT_NE(old.status.find("no bumper state"), std::string::npos);
}

}  // namespace
}  // namespace mostar::ui
