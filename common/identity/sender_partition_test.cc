#include "common/identity/sender_partition.h"

#include <fnmatch.h>
#include <gtest/gtest.h>

namespace mostar::identity {
namespace {

TEST(SenderPartitionTest, EachClientHasItsOwnPartition) {
  EXPECT_EQ(SenderPartition("alice"), "mostar.client.alice");
  EXPECT_EQ(ClientIdOfSenderPartition("mostar.client.alice"), "alice");
  EXPECT_EQ(ClientIdOfSenderPartition(SenderPartition("operator-2")), "operator-2");
}

TEST(SenderPartitionTest, AnythingButOneClientsPartitionNamesNobody) {
  for (const char* partition : {"", "mostar.client.", "mostar.client.*", "mostar.client.al*",
                                "mostar.client.[a]lice", "mostar.client.alice;mostar.client.bob",
                                "other.alice", "mostar.clientalice", "mostar.client.a b"}) {
    EXPECT_EQ(ClientIdOfSenderPartition(partition), std::nullopt) << partition;
  }
}

// Fast DDS matches a writer's partitions against the patterns of its permissions with fnmatch
// (pattern = the permission's partition): one client's partition, taken as a pattern, matches
// no other client's, and the robot's wildcard matches all of them.
TEST(SenderPartitionTest, AsAPermissionPatternAClientsPartitionAllowsOnlyItself) {
  const std::string alice = SenderPartition("alice");
  EXPECT_EQ(fnmatch(alice.c_str(), alice.c_str(), FNM_NOESCAPE), 0);
  for (const char* other :
       {"mostar.client.alice2", "mostar.client.alic", "mostar.client.*", "mostar.client.bob", ""}) {
    EXPECT_NE(fnmatch(alice.c_str(), other, FNM_NOESCAPE), 0) << other;
  }
  EXPECT_EQ(fnmatch(kAnySenderPartition, alice.c_str(), FNM_NOESCAPE), 0);
  EXPECT_NE(fnmatch(kAnySenderPartition, "", FNM_NOESCAPE), 0);
}

TEST(SenderPartitionDeathTest, AnInvalidIdIsABug) {
  EXPECT_DEATH(SenderPartition("a*"), "client id");
}

}  // namespace
}  // namespace mostar::identity
