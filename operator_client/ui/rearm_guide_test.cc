#include "operator_client/ui/rearm_guide.h"

#include <gtest/gtest.h>

namespace mostar::ui {
namespace {

using std::chrono::milliseconds;

TEST(RearmGuideTest, NothingToSayWhileDrivingOrWithoutTheLease) {
  RearmGuide guide;
  const SteadyTime t0{};
  EXPECT_TRUE(guide.Update(true, WatchdogState::kDriving, t0, true, false, t0).hud_text.empty());
  EXPECT_TRUE(guide.Update(false, WatchdogState::kWaitRearm, t0, true, true, t0).hud_text.empty());
  EXPECT_FALSE(guide.Update(false, WatchdogState::kWaitRearm, t0, true, true, t0).hold_disarmed);
  EXPECT_TRUE(guide.Update(true, std::nullopt, t0, true, true, t0).hud_text.empty());
}

// The pilot holding the keys after a link loss is told to let go; once let go, the console's
// enable = false commands re-arm.
TEST(RearmGuideTest, TheInteractivePilotIsToldToLetGoOfTheKeys) {
  RearmGuide guide;
  const SteadyTime t0{};
  const auto held = guide.Update(true, WatchdogState::kWaitRearm, t0, true, false, t0);
  EXPECT_NE(held.hud_text.find("let go of the drive keys"), std::string::npos);
  EXPECT_FALSE(held.hold_disarmed);  // the keys decide, not the guide
  const auto released = guide.Update(true, WatchdogState::kWaitRearm, t0, false, false, t0);
  EXPECT_NE(released.hud_text.find("re-arming"), std::string::npos);
  EXPECT_EQ(guide.scripted_rearms(), 0u);
}

// A scripted drive lets go for kRelease, then drives again; the health that still says
// WAIT_REARM from before the re-arm does not start another one, a later one does.
TEST(RearmGuideTest, AScriptedDriveRearmsOncePerLinkLoss) {
  RearmGuide guide;
  const SteadyTime t0 = SteadyTime{} + std::chrono::seconds(10);
  EXPECT_TRUE(guide.Update(true, WatchdogState::kWaitRearm, t0, true, true, t0).hold_disarmed);
  EXPECT_TRUE(guide.Update(true, WatchdogState::kWaitRearm, t0, false, true, t0 + milliseconds(100))
                  .hold_disarmed);
  const SteadyTime after = t0 + RearmGuide::kRelease + milliseconds(1);
  // The same (old) health: drive again, no second re-arm.
  EXPECT_FALSE(guide.Update(true, WatchdogState::kWaitRearm, t0, true, true, after).hold_disarmed);
  EXPECT_EQ(guide.scripted_rearms(), 1u);
  // The robot reports IDLE, then DRIVING: nothing to do.
  EXPECT_FALSE(guide.Update(true, WatchdogState::kIdle, after, true, true, after).hold_disarmed);
  // A later link loss, in a health newer than the re-arm: a second re-arm.
  const SteadyTime later = after + std::chrono::seconds(5);
  EXPECT_TRUE(
      guide.Update(true, WatchdogState::kWaitRearm, later, true, true, later).hold_disarmed);
  EXPECT_EQ(guide.scripted_rearms(), 2u);
}

}  // namespace
}  // namespace mostar::ui
