#include "operator_client/relay/estop_forwarding.h"

#include <gtest/gtest.h>

namespace mostar::relay {
namespace {

EmergencyStop Stop(const std::string& sender, bool engage) {
  EmergencyStop s;
  s.stamp = Time(std::chrono::seconds(1));
  s.sender_id = sender;
  s.engage = engage;
  return s;
}

TEST(EstopForwardingTest, AnObserversEngagementGoesOnUnderTheRelaysIdAndStamp) {
  EstopForwarding forwarding("hub", std::chrono::milliseconds(50));
  const Time now(std::chrono::seconds(1000));
  const auto out = forwarding.OnObserverEstop(Stop("carol", true), now, SteadyTime{});
  ASSERT_TRUE(out.has_value());
  EXPECT_EQ(out->sender_id, "hub");
  EXPECT_TRUE(out->engage);
  EXPECT_EQ(out->stamp, now);
  EXPECT_EQ(forwarding.stats().forwarded, 1u);
}

TEST(EstopForwardingTest, ReleasesAreNeverForwarded) {
  EstopForwarding forwarding("hub", std::chrono::milliseconds(50));
  EXPECT_FALSE(forwarding.OnObserverEstop(Stop("carol", false), Time{}, SteadyTime{}));
  EXPECT_FALSE(forwarding.OnObserverEstop(Stop("alice", false), Time{},
                                          SteadyTime(std::chrono::seconds(5))));
  EXPECT_EQ(forwarding.stats().releases_refused, 2u);
  EXPECT_EQ(forwarding.stats().forwarded, 0u);
  EXPECT_EQ(forwarding.stats().received, 2u);
}

TEST(EstopForwardingTest, RepeatedEngagementsAreThinnedToOnePerInterval) {
  EstopForwarding forwarding("hub", std::chrono::milliseconds(50));
  int forwarded = 0;
  // Two observers repeating every 10 ms for one second.
  for (int ms = 0; ms < 1000; ms += 10) {
    const SteadyTime t{std::chrono::milliseconds(ms)};
    if (forwarding.OnObserverEstop(Stop("carol", true), Time{}, t)) ++forwarded;
    if (forwarding.OnObserverEstop(Stop("dave", true), Time{}, t)) ++forwarded;
  }
  EXPECT_EQ(forwarded, 20);  // one per 50 ms
  EXPECT_EQ(forwarding.stats().rate_limited, 200u - 20u);
}

}  // namespace
}  // namespace mostar::relay
