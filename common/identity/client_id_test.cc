#include "common/identity/client_id.h"

#include <gtest/gtest.h>

namespace mostar::identity {
namespace {

TEST(ClientIdTest, AcceptsTheNamesMakePkiAccepts) {
  for (const char* id : {"alice", "operator-2", "lab.pilot_1", "A", "0"}) {
    EXPECT_TRUE(IsValidClientId(id)) << id;
  }
  EXPECT_TRUE(IsValidClientId(std::string(kMaxClientIdBytes, 'x')));
}

TEST(ClientIdTest, RefusesEmptyLongAndOtherCharactersWithAReason) {
  std::string why;
  EXPECT_FALSE(IsValidClientId("", &why));
  EXPECT_NE(why.find("empty"), std::string::npos);
  EXPECT_FALSE(IsValidClientId(std::string(kMaxClientIdBytes + 1, 'x'), &why));
  EXPECT_NE(why.find("longer"), std::string::npos);
  for (const char* id : {"a b", "a,b", "a=b", "é", "a\nb", "a/b", "*"}) {
    EXPECT_FALSE(IsValidClientId(id, &why)) << id;
  }
  EXPECT_FALSE(IsValidClientId(std::string("a\0b", 3)));
}

}  // namespace
}  // namespace mostar::identity
