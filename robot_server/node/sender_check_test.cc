#include "robot_server/node/sender_check.h"

#include <gtest/gtest.h>

#include <map>

namespace mostar::server {
namespace {

std::map<std::string, uint64_t> Counters(const SenderCheck& check) {
  std::map<std::string, uint64_t> out;
  for (const auto& [name, value] : check.HealthCounters()) out[name] = value;
  return out;
}

TEST(SenderCheckTest, WithIdentitiesOnlyTheWritersOwnIdPasses) {
  SenderCheck check(/*identities_verified=*/true);
  EXPECT_EQ(check.Check(SenderChannel::kCommand, "alice", std::string("alice")),
            SenderVerdict::kVerified);
  // Bob's certificate posing as Alice.
  EXPECT_EQ(check.Check(SenderChannel::kCommand, "alice", std::string("bob")),
            SenderVerdict::kMismatch);
  EXPECT_EQ(check.Check(SenderChannel::kControlRequest, "alice", std::string("bob")),
            SenderVerdict::kMismatch);
  // An observer releasing the e-stop under a pilot's id.
  EXPECT_EQ(check.Check(SenderChannel::kEmergencyStop, "alice", std::string("carol")),
            SenderVerdict::kMismatch);
  // A forged ping keyed by Alice's id.
  EXPECT_EQ(check.Check(SenderChannel::kClockPing, "alice", std::string("bob")),
            SenderVerdict::kMismatch);
  // A writer without a verified identity (no certificate announced, or another vendor).
  EXPECT_EQ(check.Check(SenderChannel::kCommand, "alice", std::nullopt),
            SenderVerdict::kUnidentified);
  const auto counters = Counters(check);
  EXPECT_EQ(counters.at("identities_verified"), 1u);
  EXPECT_EQ(counters.at("sender_mismatch_dropped"), 4u);
  EXPECT_EQ(counters.at("sender_unidentified_dropped"), 1u);
  EXPECT_EQ(counters.at("dropped_cmd_vel"), 2u);
  EXPECT_EQ(counters.at("dropped_control_request"), 1u);
  EXPECT_EQ(counters.at("dropped_estop"), 1u);
  EXPECT_EQ(counters.at("dropped_clock_ping"), 1u);
  EXPECT_EQ(check.dropped(), 5u);
}

TEST(SenderCheckTest, WithoutIdentitiesIdsPassUnverifiedAndHealthSaysSo) {
  SenderCheck check(/*identities_verified=*/false);
  EXPECT_EQ(check.Check(SenderChannel::kCommand, "alice", std::nullopt),
            SenderVerdict::kUnverified);
  EXPECT_TRUE(SenderCheck::Admits(SenderVerdict::kUnverified));
  EXPECT_EQ(Counters(check).at("identities_verified"), 0u);
  EXPECT_EQ(check.dropped(), 0u);
}

TEST(SenderCheckTest, InvalidIdsAreDroppedEitherWay) {
  for (const bool verified : {true, false}) {
    SenderCheck check(verified);
    for (const std::string& id :
         {std::string(""), std::string(65, 'a'), std::string("a\nb"), std::string("alice\0", 6)}) {
      EXPECT_EQ(check.Check(SenderChannel::kEmergencyStop, id, id), SenderVerdict::kInvalidId);
    }
    EXPECT_EQ(Counters(check).at("sender_invalid_dropped"), 4u);
    EXPECT_EQ(Counters(check).at("dropped_estop"), 4u);
  }
}

}  // namespace
}  // namespace mostar::server
