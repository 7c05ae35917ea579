#include "common/dds/domain.h"

#include <gtest/gtest.h>
#include <stdlib.h>

namespace mostar::dds {
namespace {

// Ids in [240, 250): outside every range the code base uses, so that this test takes none from
// parallel test processes (the lock files are shared by the whole machine).
TEST(DomainTest, EachAcquiredIdIsHeldUntilExit) {
  const std::optional<int> first = AcquireUnusedDomainId(240, 10, 3);
  const std::optional<int> second = AcquireUnusedDomainId(240, 10, 3);
  ASSERT_TRUE(first.has_value());
  ASSERT_TRUE(second.has_value());
  EXPECT_GE(*first, 240);
  EXPECT_LT(*first, 250);
  EXPECT_NE(*first, *second) << "a held id is not handed out again";
}

TEST(DomainTest, NoneLeftWhenEveryIdIsHeld) {
  ASSERT_TRUE(AcquireUnusedDomainId(250, 2, 0).has_value());
  ASSERT_TRUE(AcquireUnusedDomainId(250, 2, 0).has_value());
  EXPECT_FALSE(AcquireUnusedDomainId(250, 2, 0).has_value());
}

TEST(DomainTest, PerProcessIdIsStableAndInItsRange) {
  const int id = PerProcessDomainId();
  EXPECT_GE(id, 100);
  EXPECT_LE(id, 231);
  EXPECT_EQ(PerProcessDomainId(), id);
}

TEST(DomainTest, EnvironmentOverridesOnlyWithAValidId) {
  setenv("MOSTAR_DDS_DOMAIN", "17", 1);
  EXPECT_EQ(DomainIdFromEnvironment(3), 17);
  setenv("MOSTAR_DDS_DOMAIN", "233", 1);
  EXPECT_EQ(DomainIdFromEnvironment(3), 3);
  setenv("MOSTAR_DDS_DOMAIN", "7x", 1);
  EXPECT_EQ(DomainIdFromEnvironment(3), 3);
  unsetenv("MOSTAR_DDS_DOMAIN");
  EXPECT_EQ(DomainIdFromEnvironment(3), 3);
}

}  // namespace
}  // namespace mostar::dds
