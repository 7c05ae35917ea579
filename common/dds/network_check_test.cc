#include "common/dds/network_check.h"

#include <gtest/gtest.h>

#include "common/dds/domain.h"

namespace mostar::dds {
namespace {

// The loopback profile is pinned to 127.0.0.1: never a new participant; checks run once per
// period, whatever the calls in between.
TEST(NetworkCheckTest, ChecksOncePerPeriodAndAPinnedParticipantNeverNeedsARestart) {
  ParticipantOptions options;
  options.domain_id = PerProcessDomainId();
  std::string error;
  auto participant = Participant::Create(options, &error);
  ASSERT_NE(participant, nullptr) << error;
  NetworkCheck check({participant.get(), nullptr}, std::chrono::milliseconds(250));
  const NetworkCheck::TimePoint t0{};
  EXPECT_FALSE(check.RestartNeeded(t0));
  EXPECT_FALSE(check.RestartNeeded(t0 + std::chrono::milliseconds(100)));
  EXPECT_EQ(check.checks(), 1);
  EXPECT_FALSE(check.RestartNeeded(t0 + std::chrono::milliseconds(250)));
  EXPECT_EQ(check.checks(), 2);
  EXPECT_FALSE(check.RestartNeeded(t0 + std::chrono::milliseconds(499)));
  EXPECT_EQ(check.checks(), 2);
}

}  // namespace
}  // namespace mostar::dds
