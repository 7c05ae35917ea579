#include "operator_client/web/http_target.h"

#include <gtest/gtest.h>

namespace mostar::web {
namespace {

TEST(ParseTargetTest, SplitsPathAndDecodesTheQuery) {
  const auto t = ParseTarget("/ws?eyes=2&token=a%2Bb%3D%3D&empty=&flag");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->path, "/ws");
  EXPECT_EQ(t->query.at("eyes"), "2");
  EXPECT_EQ(t->query.at("token"), "a+b==");
  EXPECT_EQ(t->query.at("empty"), "");
  EXPECT_EQ(t->query.at("flag"), "");
}

TEST(ParseTargetTest, APlainPathHasNoQuery) {
  const auto t = ParseTarget("/app.js");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->path, "/app.js");
  EXPECT_TRUE(t->query.empty());
}

TEST(ParseTargetTest, RefusesMalformedTargets) {
  EXPECT_FALSE(ParseTarget(""));
  EXPECT_FALSE(ParseTarget("ws?token=x"));
  EXPECT_FALSE(ParseTarget("/ws?token=%"));
  EXPECT_FALSE(ParseTarget("/ws?token=%4"));
  EXPECT_FALSE(ParseTarget("/ws?token=%zz"));
  EXPECT_FALSE(ParseTarget("/ws?token=%-1"));
  EXPECT_FALSE(ParseTarget("/ws?token=%+1"));
  EXPECT_FALSE(ParseTarget("/ws?token=%4g"));
  EXPECT_FALSE(ParseTarget("/" + std::string(kMaxTargetBytes, 'a')));
}

}  // namespace
}  // namespace mostar::web
