#include "operator_client/web/client_outbox.h"

#include <gtest/gtest.h>

namespace mostar::web {
namespace {

OutMessage Frame(const std::string& text) {
  return {MessageKind::kFrame, std::make_shared<const std::string>(text)};
}
OutMessage Hud(const std::string& text) {
  return {MessageKind::kHud, std::make_shared<const std::string>(text)};
}

TEST(ClientOutboxTest, AnIdleBrowserIsWrittenToAtOnce) {
  ClientOutbox outbox;
  const auto now = outbox.Offer(Frame("f1"));
  ASSERT_TRUE(now);
  EXPECT_EQ(*now->bytes, "f1");
  EXPECT_TRUE(outbox.writing());
  EXPECT_FALSE(outbox.Written());
  EXPECT_FALSE(outbox.writing());
}

TEST(ClientOutboxTest, ABusyBrowserGetsOnlyTheNewestFrame) {
  ClientOutbox outbox;
  ASSERT_TRUE(outbox.Offer(Frame("f1")));
  for (int i = 2; i <= 9; ++i) EXPECT_FALSE(outbox.Offer(Frame("f" + std::to_string(i))));
  const auto next = outbox.Written();
  ASSERT_TRUE(next);
  EXPECT_EQ(*next->bytes, "f9");
  EXPECT_EQ(outbox.counters().frames_dropped, 7u);
  EXPECT_FALSE(outbox.Written());
  EXPECT_EQ(outbox.counters().written, 2u);
  EXPECT_EQ(outbox.counters().offered, 9u);
}

TEST(ClientOutboxTest, AFrameNeverReplacesAWaitingHudAndTheHudGoesFirst) {
  ClientOutbox outbox;
  ASSERT_TRUE(outbox.Offer(Frame("f1")));
  EXPECT_FALSE(outbox.Offer(Hud("h1")));
  EXPECT_FALSE(outbox.Offer(Frame("f2")));
  EXPECT_FALSE(outbox.Offer(Frame("f3")));
  EXPECT_FALSE(outbox.Offer(Hud("h2")));
  auto next = outbox.Written();
  ASSERT_TRUE(next);
  EXPECT_EQ(*next->bytes, "h2");
  next = outbox.Written();
  ASSERT_TRUE(next);
  EXPECT_EQ(*next->bytes, "f3");
  EXPECT_FALSE(outbox.Written());
  EXPECT_EQ(outbox.counters().frames_dropped, 1u);
  EXPECT_EQ(outbox.counters().huds_dropped, 1u);
}

TEST(ClientOutboxTest, HoldsAtMostOneMessageOfEachKindWhateverIsOffered) {
  ClientOutbox outbox;
  ASSERT_TRUE(outbox.Offer(Frame("busy")));
  for (int i = 0; i < 1000; ++i) {
    outbox.Offer(i % 3 == 0 ? Hud("h") : Frame("f"));
  }
  int drained = 0;
  while (outbox.Written()) ++drained;
  EXPECT_EQ(drained, 2);
}

}  // namespace
}  // namespace mostar::web
