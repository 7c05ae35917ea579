#include "common/identity/peer_identity_table.h"

#include <gtest/gtest.h>

namespace mostar::identity {
namespace {

GuidPrefix Prefix(uint8_t n) {
  GuidPrefix p{};
  p[0] = 0x80;
  p[11] = n;
  return p;
}

TEST(PeerIdentityTableTest, AnIdNeedsBothAVerifiedCertificateAndAuthentication) {
  PeerIdentityTable table;
  EXPECT_EQ(table.AnnouncedClientId(Prefix(1)), std::nullopt);
  ASSERT_TRUE(table.Bind(Prefix(1), "alice"));
  EXPECT_EQ(table.AnnouncedClientId(Prefix(1)), std::nullopt);  // not authenticated yet
  ASSERT_TRUE(table.MarkAuthenticated(Prefix(1)));
  EXPECT_EQ(table.AnnouncedClientId(Prefix(1)), "alice");
  // The other order.
  ASSERT_TRUE(table.MarkAuthenticated(Prefix(2)));
  EXPECT_EQ(table.AnnouncedClientId(Prefix(2)), std::nullopt);  // no verified certificate
  ASSERT_TRUE(table.Bind(Prefix(2), "bob"));
  EXPECT_EQ(table.AnnouncedClientId(Prefix(2)), "bob");
  table.Forget(Prefix(1));
  EXPECT_EQ(table.AnnouncedClientId(Prefix(1)), std::nullopt);
  EXPECT_EQ(table.stats().peers, 1u);
}

TEST(PeerIdentityTableTest, ABoundParticipantIsNeverRebound) {
  PeerIdentityTable table;
  ASSERT_TRUE(table.Bind(Prefix(1), "alice"));
  ASSERT_TRUE(table.MarkAuthenticated(Prefix(1)));
  EXPECT_TRUE(table.Bind(Prefix(1), "alice"));  // the same announcement again
  EXPECT_FALSE(table.Bind(Prefix(1), "bob"));
  EXPECT_EQ(table.AnnouncedClientId(Prefix(1)), "alice");
  EXPECT_EQ(table.stats().rebind_refused, 1u);
}

TEST(PeerIdentityTableTest, IncompleteEntriesMakeRoomCompleteOnesAreKept) {
  PeerIdentityTable table(/*max_peers=*/3, /*max_per_client=*/3);
  ASSERT_TRUE(table.Bind(Prefix(1), "alice"));
  ASSERT_TRUE(table.MarkAuthenticated(Prefix(1)));
  ASSERT_TRUE(table.Bind(Prefix(2), "bob"));  // never authenticates (a forged announcement)
  ASSERT_TRUE(table.Bind(Prefix(3), "carol"));
  ASSERT_TRUE(table.MarkAuthenticated(Prefix(3)));
  // Full: the incomplete entry goes.
  ASSERT_TRUE(table.Bind(Prefix(4), "dave"));
  ASSERT_TRUE(table.MarkAuthenticated(Prefix(4)));
  EXPECT_EQ(table.stats().evicted, 1u);
  EXPECT_EQ(table.AnnouncedClientId(Prefix(1)), "alice");
  EXPECT_EQ(table.AnnouncedClientId(Prefix(3)), "carol");
  EXPECT_EQ(table.AnnouncedClientId(Prefix(4)), "dave");
  // Full of complete entries: a newcomer is refused, nobody is evicted.
  EXPECT_FALSE(table.Bind(Prefix(5), "erin"));
  EXPECT_FALSE(table.MarkAuthenticated(Prefix(5)));
  EXPECT_EQ(table.stats().refused_full, 2u);
  EXPECT_EQ(table.AnnouncedClientId(Prefix(1)), "alice");
  EXPECT_EQ(table.stats().peers, 3u);
}

// One certificate cannot fill the table by starting many participants.
TEST(PeerIdentityTableTest, AClientHoldsAtMostItsShareOfTheTable) {
  PeerIdentityTable table(/*max_peers=*/8, /*max_per_client=*/2);
  ASSERT_TRUE(table.Bind(Prefix(100), "alice"));
  ASSERT_TRUE(table.MarkAuthenticated(Prefix(100)));
  ASSERT_TRUE(table.Bind(Prefix(1), "mallory"));
  ASSERT_TRUE(table.MarkAuthenticated(Prefix(1)));
  for (uint8_t n = 2; n <= 20; ++n) table.Bind(Prefix(n), "mallory");  // never authenticate
  // The second slot went round the incomplete ones; the complete entry stayed.
  EXPECT_EQ(table.stats().peers, 3u);
  EXPECT_EQ(table.stats().evicted, 18u);
  EXPECT_EQ(table.AnnouncedClientId(Prefix(1)), "mallory");
  EXPECT_EQ(table.AnnouncedClientId(Prefix(20), /*authenticated_only=*/false), "mallory");
  EXPECT_EQ(table.AnnouncedClientId(Prefix(19), /*authenticated_only=*/false), std::nullopt);
  EXPECT_EQ(table.AnnouncedClientId(Prefix(100)), "alice");
}

// Participants announcing alice's id (an insider forging her GUID and certificate, or a stuck
// handshake) never push out alice's complete entry, authenticated or not.
TEST(PeerIdentityTableTest, AnnouncingAnIdNeverEvictsItsCompleteEntries) {
  PeerIdentityTable table(/*max_peers=*/16, /*max_per_client=*/2);
  ASSERT_TRUE(table.Bind(Prefix(1), "alice"));
  ASSERT_TRUE(table.MarkAuthenticated(Prefix(1)));
  for (uint8_t n = 2; n <= 10; ++n) {  // each authenticates too: the forger's handshake passes
    table.Bind(Prefix(n), "alice");
    table.MarkAuthenticated(Prefix(n));
  }
  EXPECT_EQ(table.AnnouncedClientId(Prefix(1)), "alice");
  EXPECT_EQ(table.AnnouncedClientId(Prefix(2)), "alice");  // the second complete entry
  for (uint8_t n = 3; n <= 10; ++n) EXPECT_EQ(table.AnnouncedClientId(Prefix(n)), std::nullopt);
  EXPECT_EQ(table.stats().refused_per_client, 8u);
  EXPECT_EQ(table.stats().evicted, 0u);
}

}  // namespace
}  // namespace mostar::identity
