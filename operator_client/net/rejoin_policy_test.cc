#include "operator_client/net/rejoin_policy.h"

#include <gtest/gtest.h>

#include <string>

namespace mostar::client {
namespace {

using std::chrono::seconds;

const SteadyTime kT0 = SteadyTime{} + seconds(100);

TEST(RejoinPolicyTest, JoinsAgainAfterTheFirstWaitWithoutTheRobotThenWaitsTwiceAsLong) {
  RejoinPolicy policy;  // 15 s, at most 120 s
  EXPECT_FALSE(policy.Update(false, kT0));
  EXPECT_FALSE(policy.Update(false, kT0 + seconds(14)));
  ASSERT_TRUE(policy.Update(false, kT0 + seconds(15)));
  policy.Rejoined(kT0 + seconds(15));
  EXPECT_EQ(policy.rejoins(), 1);
  EXPECT_FALSE(policy.Update(false, kT0 + seconds(15 + 29)));
  ASSERT_TRUE(policy.Update(false, kT0 + seconds(15 + 30)));
  policy.Rejoined(kT0 + seconds(45));
  // 60, then 120, then 120 again: never longer than `longest`.
  ASSERT_TRUE(policy.Update(false, kT0 + seconds(45 + 60)));
  policy.Rejoined(kT0 + seconds(105));
  ASSERT_TRUE(policy.Update(false, kT0 + seconds(105 + 120)));
  policy.Rejoined(kT0 + seconds(225));
  EXPECT_FALSE(policy.Update(false, kT0 + seconds(225 + 119)));
  EXPECT_TRUE(policy.Update(false, kT0 + seconds(225 + 120)));
  EXPECT_EQ(policy.wait(), seconds(120));
}

TEST(RejoinPolicyTest, SeeingTheRobotStartsOver) {
  RejoinPolicy policy;
  EXPECT_FALSE(policy.Update(false, kT0));
  ASSERT_TRUE(policy.Update(false, kT0 + seconds(15)));
  policy.Rejoined(kT0 + seconds(15));
  EXPECT_FALSE(policy.Update(true, kT0 + seconds(20)));  // matched after the join
  EXPECT_EQ(policy.wait(), seconds(15));
  // Seen for an hour, then gone (a robot restart whose handshake never ends): 15 s again,
  // counted from when it was last seen.
  EXPECT_FALSE(policy.Update(true, kT0 + seconds(3600)));
  EXPECT_FALSE(policy.Update(false, kT0 + seconds(3601)));
  EXPECT_FALSE(policy.Update(false, kT0 + seconds(3615)));
  EXPECT_TRUE(policy.Update(false, kT0 + seconds(3616)));
}

TEST(RejoinPolicyTest, OptionsAreChecked) {
  std::string error;
  EXPECT_TRUE(RejoinOptions().IsValid(&error)) << error;
  RejoinOptions options;
  options.first = seconds(0);
  EXPECT_FALSE(options.IsValid(&error));
  options.first = seconds(30);
  options.longest = seconds(10);
  EXPECT_FALSE(options.IsValid(&error));
}

}  // namespace
}  // namespace mostar::client
