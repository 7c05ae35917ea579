#include "operator_client/web/token_table.h"

#include <gtest/gtest.h>

namespace mostar::web {
namespace {

constexpr char kTable[] =
    "# observers\n"
    "alice  0123456789abcdefABCDEF\n"
    "\n"
    "bob\tZYXWVUTSRQPONMLKJ+/==\n";

TEST(TokenTableTest, NamesTheObserverOfAValidToken) {
  std::string error;
  const auto table = TokenTable::Parse(kTable, &error);
  ASSERT_TRUE(table) << error;
  EXPECT_EQ(table->size(), 2u);
  EXPECT_EQ(table->Check("0123456789abcdefABCDEF"), "alice");
  EXPECT_EQ(table->Check("ZYXWVUTSRQPONMLKJ+/=="), "bob");
}

TEST(TokenTableTest, RefusesWrongPrefixAndEmptyTokens) {
  std::string error;
  const auto table = TokenTable::Parse(kTable, &error);
  ASSERT_TRUE(table) << error;
  EXPECT_FALSE(table->Check("0123456789abcdefABCDEf"));
  EXPECT_FALSE(table->Check("0123456789abcdefABCDE"));
  EXPECT_FALSE(table->Check("0123456789abcdefABCDEFG"));
  EXPECT_FALSE(table->Check(""));
  EXPECT_FALSE(table->Check("alice"));
}

TEST(TokenTableTest, RefusesBadFilesNamingTheLine) {
  std::string error;
  EXPECT_FALSE(TokenTable::Parse("alice short\n", &error));
  EXPECT_NE(error.find("line 1"), std::string::npos) << error;
  EXPECT_FALSE(TokenTable::Parse("# x\nalice\n", &error));
  EXPECT_NE(error.find("line 2"), std::string::npos) << error;
  EXPECT_FALSE(TokenTable::Parse("alice 0123456789abcdef extra\n", &error));
  EXPECT_FALSE(TokenTable::Parse("bad/name 0123456789abcdef\n", &error));
  EXPECT_FALSE(TokenTable::Parse("alice 0123456789abcdef\"\n", &error));
  EXPECT_FALSE(TokenTable::Parse("alice 0123456789abcdef\nalice 0123456789abcdeg\n", &error));
  EXPECT_NE(error.find("twice"), std::string::npos) << error;
  EXPECT_FALSE(TokenTable::Parse("alice 0123456789abcdef\nbob 0123456789abcdef\n", &error));
  EXPECT_NE(error.find("unique"), std::string::npos) << error;
}

TEST(TokenTableTest, AnEmptyTableAcceptsNobody) {
  std::string error;
  const auto table = TokenTable::Parse("", &error);
  ASSERT_TRUE(table);
  EXPECT_FALSE(table->Check("0123456789abcdefABCDEF"));
}

TEST(TokenTableTest, LoadNamesTheFile) {
  std::string error;
  EXPECT_FALSE(TokenTable::Load("/nonexistent/tokens", &error));
  EXPECT_NE(error.find("/nonexistent/tokens"), std::string::npos);
}

}  // namespace
}  // namespace mostar::web
