#include "robot_server/drive/pilot_lease.h"

#include <gtest/gtest.h>

#include "common/time/fake_clock.h"

namespace mostar::drive {
namespace {

ControlRequest Take(const std::string& id, int32_t claimed_strength = 0) {
  ControlRequest r;
  r.sender_id = id;
  r.strength = claimed_strength;
  r.take = true;
  return r;
}

ControlRequest Release(const std::string& id) {
  ControlRequest r = Take(id);
  r.take = false;
  return r;
}

class PilotLeaseTest : public ::testing::Test {
 protected:
  static RoleTable Roles() {
    RoleTable roles;
    roles.Set("alice", {Role::kPilot, 10});
    roles.Set("bob", {Role::kPilot, 20});
    roles.Set("carol", {Role::kPilot, 10});
    roles.Set("olga", {Role::kObserver, 0});
    return roles;
  }
  FakeClock clock_;
  PilotLease lease_{clock_, Roles()};
};

TEST_F(PilotLeaseTest, NobodyHoldsAtStart) {
  EXPECT_EQ(lease_.holder(), "");
  EXPECT_EQ(lease_.lease().lease_sequence, 0u);
  EXPECT_FALSE(lease_.IsHolder(""));
}

TEST_F(PilotLeaseTest, PilotTakesAFreeLease) {
  clock_.Advance(std::chrono::seconds(1));
  EXPECT_EQ(lease_.HandleRequest(Take("alice")), LeaseDecision::kGranted);
  const ControlLease l = lease_.lease();
  EXPECT_EQ(l.holder_id, "alice");
  EXPECT_EQ(l.holder_strength, 10);
  EXPECT_EQ(l.since, clock_.Now());
  EXPECT_EQ(l.lease_sequence, 1u);
  // Asking again changes nothing.
  EXPECT_EQ(lease_.HandleRequest(Take("alice")), LeaseDecision::kGranted);
  EXPECT_EQ(lease_.lease().lease_sequence, 1u);
}

TEST_F(PilotLeaseTest, ObserversAndUnknownClientsNeverDrive) {
  EXPECT_EQ(lease_.HandleRequest(Take("olga", 1000)), LeaseDecision::kRefusedObserver);
  EXPECT_EQ(lease_.HandleRequest(Take("mallory", 1000)), LeaseDecision::kRefusedObserver);
  EXPECT_EQ(lease_.holder(), "");
  EXPECT_EQ(lease_.stats().refused, 2u);
}

TEST_F(PilotLeaseTest, ClaimedStrengthIsIgnored) {
  lease_.HandleRequest(Take("bob"));
  EXPECT_EQ(lease_.HandleRequest(Take("alice", 1'000'000)), LeaseDecision::kRefusedHeld);
  EXPECT_EQ(lease_.holder(), "bob");
}

TEST_F(PilotLeaseTest, StrongerPilotTakesOver) {
  lease_.HandleRequest(Take("alice"));
  EXPECT_EQ(lease_.HandleRequest(Take("bob")), LeaseDecision::kGranted);
  EXPECT_EQ(lease_.holder(), "bob");
  EXPECT_EQ(lease_.lease().holder_strength, 20);
  EXPECT_EQ(lease_.lease().lease_sequence, 2u);
  EXPECT_EQ(lease_.stats().takeovers, 1u);
}

TEST_F(PilotLeaseTest, EqualOrWeakerPilotIsRefused) {
  lease_.HandleRequest(Take("alice"));
  EXPECT_EQ(lease_.HandleRequest(Take("carol")), LeaseDecision::kRefusedHeld);
  lease_.HandleRequest(Take("bob"));
  EXPECT_EQ(lease_.HandleRequest(Take("alice")), LeaseDecision::kRefusedHeld);
  EXPECT_EQ(lease_.holder(), "bob");
}

TEST_F(PilotLeaseTest, ExplicitReleaseFreesTheLeaseForAnyPilot) {
  lease_.HandleRequest(Take("bob"));
  EXPECT_EQ(lease_.HandleRequest(Release("alice")), LeaseDecision::kRefusedNotHolder);
  EXPECT_EQ(lease_.holder(), "bob");
  EXPECT_EQ(lease_.HandleRequest(Release("bob")), LeaseDecision::kReleased);
  EXPECT_EQ(lease_.holder(), "");
  EXPECT_EQ(lease_.lease().lease_sequence, 2u);
  EXPECT_EQ(lease_.HandleRequest(Take("alice")), LeaseDecision::kGranted);
}

TEST_F(PilotLeaseTest, LostHolderMeansNobodyDrives) {
  lease_.HandleRequest(Take("alice"));
  EXPECT_FALSE(lease_.OnLivelinessLost("bob"));
  EXPECT_EQ(lease_.holder(), "alice");
  EXPECT_TRUE(lease_.OnLivelinessLost("alice"));
  EXPECT_EQ(lease_.holder(), "");
  EXPECT_EQ(lease_.lease().lease_sequence, 2u);
  EXPECT_EQ(lease_.stats().holder_lost, 1u);
}

// Anyone in the role table may engage the e-stop; only the lease holder may release it.
TEST_F(PilotLeaseTest, EstopAuthorisation) {
  EXPECT_TRUE(lease_.MayEngageEstop("olga"));
  EXPECT_TRUE(lease_.MayEngageEstop("alice"));
  EXPECT_FALSE(lease_.MayEngageEstop("mallory"));
  // Nobody holds the lease: nobody releases.
  for (const char* id : {"alice", "bob", "olga", "mallory"}) {
    EXPECT_FALSE(lease_.MayReleaseEstop(id)) << id;
  }
  ASSERT_EQ(lease_.HandleRequest(Take("alice")), LeaseDecision::kGranted);
  EXPECT_TRUE(lease_.MayReleaseEstop("alice"));
  EXPECT_FALSE(lease_.MayReleaseEstop("bob")) << "a pilot without the lease";
  EXPECT_FALSE(lease_.MayReleaseEstop("carol"));
  EXPECT_FALSE(lease_.MayReleaseEstop("olga")) << "observers never release";
  EXPECT_FALSE(lease_.MayReleaseEstop("mallory"));
  ASSERT_EQ(lease_.HandleRequest(Take("bob")), LeaseDecision::kGranted);
  EXPECT_FALSE(lease_.MayReleaseEstop("alice"));
  EXPECT_TRUE(lease_.MayReleaseEstop("bob"));
}

TEST_F(PilotLeaseTest, SilentHolderExpiresAfterTheTimeoutFromTheGrant) {
  using std::chrono::milliseconds;
  clock_.Advance(std::chrono::seconds(10));  // the timeout runs from the grant, not the start
  ASSERT_EQ(lease_.HandleRequest(Take("alice")), LeaseDecision::kGranted);
  const uint64_t sequence = lease_.lease().lease_sequence;
  clock_.Advance(PilotLease::kDefaultHolderTimeout);
  EXPECT_FALSE(lease_.ExpireSilentHolder(clock_.SteadyNow()).has_value()) << "not more than";
  clock_.Advance(milliseconds(1));
  EXPECT_EQ(lease_.ExpireSilentHolder(clock_.SteadyNow()), "alice");
  EXPECT_EQ(lease_.holder(), "");
  EXPECT_EQ(lease_.lease().lease_sequence, sequence + 1);
  EXPECT_EQ(lease_.stats().holder_lost, 1u);
  EXPECT_FALSE(lease_.ExpireSilentHolder(clock_.SteadyNow()).has_value()) << "nobody to expire";
}

TEST_F(PilotLeaseTest, OnlyTheHoldersSignsOfLifeKeepTheLease) {
  using std::chrono::milliseconds;
  ASSERT_EQ(lease_.HandleRequest(Take("alice")), LeaseDecision::kGranted);
  for (int i = 0; i < 10; ++i) {  // 15 s of life signs every 1.5 s
    clock_.Advance(milliseconds(1500));
    lease_.NoteAlive("alice");
    lease_.NoteAlive("bob");
    EXPECT_FALSE(lease_.ExpireSilentHolder(clock_.SteadyNow()).has_value());
  }
  clock_.Advance(milliseconds(1500));
  lease_.NoteAlive("bob");  // not the holder: does not keep alice's lease
  clock_.Advance(milliseconds(600));
  EXPECT_EQ(lease_.ExpireSilentHolder(clock_.SteadyNow()), "alice");
}

TEST_F(PilotLeaseTest, TheHoldersRepeatedTakeIsASignOfLife) {
  using std::chrono::milliseconds;
  ASSERT_EQ(lease_.HandleRequest(Take("alice")), LeaseDecision::kGranted);
  clock_.Advance(milliseconds(1500));
  ASSERT_EQ(lease_.HandleRequest(Take("alice")), LeaseDecision::kGranted);
  clock_.Advance(milliseconds(1500));
  EXPECT_FALSE(lease_.ExpireSilentHolder(clock_.SteadyNow()).has_value());
}

TEST(PilotLeaseDeathTest, NonPositiveHolderTimeoutIsABug) {
  FakeClock clock;
  EXPECT_DEATH(PilotLease(clock, RoleTable{}, Duration::zero()), "holder_timeout must be positive");
}

}  // namespace
}  // namespace mostar::drive
