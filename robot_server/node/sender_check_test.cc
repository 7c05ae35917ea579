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

TEST(SenderCheckTest, WithIdentitiesOnlyThePartitionsOwnIdPasses) {
  SenderCheck check(/*identities_verified=*/true);
  EXPECT_EQ(check.Check(SenderChannel::kCommand, "alice", "alice"), SenderVerdict::kVerified);
  // Bob, in his own partition (the only one his permissions allow), posing as Alice.
  EXPECT_EQ(check.Check(SenderChannel::kCommand, "alice", "bob"), SenderVerdict::kMismatch);
  EXPECT_EQ(check.Check(SenderChannel::kControlRequest, "alice", "bob"), SenderVerdict::kMismatch);
  // An observer releasing the e-stop under a pilot's id.
  EXPECT_EQ(check.Check(SenderChannel::kEmergencyStop, "alice", "carol"), SenderVerdict::kMismatch);
  // A forged ping keyed by Alice's id.
  EXPECT_EQ(check.Check(SenderChannel::kClockPing, "alice", "bob"), SenderVerdict::kMismatch);
  const auto counters = Counters(check);
  EXPECT_EQ(counters.at("identities_verified"), 1u);
  EXPECT_EQ(counters.at("sender_mismatch_dropped"), 4u);
  EXPECT_EQ(counters.count("sender_unidentified_dropped"), 0u);
  EXPECT_EQ(counters.at("dropped_cmd_vel"), 1u);
  EXPECT_EQ(counters.at("dropped_control_request"), 1u);
  EXPECT_EQ(counters.at("dropped_estop"), 1u);
  EXPECT_EQ(counters.at("dropped_clock_ping"), 1u);
  EXPECT_EQ(check.dropped(), 4u);
}

TEST(SenderCheckTest, WithoutIdentitiesAgreeingIdsPassUnverifiedAndHealthSaysSo) {
  SenderCheck check(/*identities_verified=*/false);
  EXPECT_EQ(check.Check(SenderChannel::kCommand, "alice", "alice"), SenderVerdict::kUnverified);
  EXPECT_TRUE(SenderCheck::Admits(SenderVerdict::kUnverified));
  // Ids that disagree are dropped even unverified: an honest client writes in its own partition.
  EXPECT_EQ(check.Check(SenderChannel::kCommand, "alice", "bob"), SenderVerdict::kMismatch);
  EXPECT_EQ(Counters(check).at("identities_verified"), 0u);
  EXPECT_EQ(check.dropped(), 1u);
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

TEST(SenderProofLogTest, EachClientAndParticipantPairIsFirstOnce) {
  SenderProofLog log;
  EXPECT_TRUE(log.First("alice", "p1"));
  EXPECT_FALSE(log.First("alice", "p1"));  // alice's next writer of the same participant
  EXPECT_TRUE(log.First("bob", "p1"));     // another client's partition: said again
  EXPECT_TRUE(log.First("alice", "p2"));   // alice's restarted participant
  EXPECT_FALSE(log.First("bob", "p1"));
}

TEST(SenderProofLogTest, StaysBoundedAndForgetsAllAtOnceWhenFull) {
  SenderProofLog log;
  for (size_t i = 0; i < SenderProofLog::kMaxRemembered; ++i) {
    ASSERT_TRUE(log.First("mallory", "p" + std::to_string(i)));
  }
  EXPECT_FALSE(log.First("mallory", "p0"));
  EXPECT_TRUE(log.First("alice", "a"));  // full: forgotten, then remembered again
  EXPECT_TRUE(log.First("mallory", "p0"));
  EXPECT_FALSE(log.First("alice", "a"));
}

}  // namespace
}  // namespace mostar::server
