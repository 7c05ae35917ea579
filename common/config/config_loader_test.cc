#include "common/config/config_loader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "common/config/test_config.pb.h"

namespace mostar {
namespace {

using config::testing::TestConfig;
using ::testing::HasSubstr;

TEST(ConfigLoaderTest, ParsesValidText) {
  TestConfig c;
  std::string error;
  ASSERT_TRUE(
      ParseTextConfig("name: \"a\"\nbaud: 38400\ninner { gain: 2.5 }\n", "x.pbtxt", &c, &error))
      << error;
  EXPECT_EQ(c.baud(), 38400);
  EXPECT_DOUBLE_EQ(c.inner().gain(), 2.5);
  EXPECT_DOUBLE_EQ(c.extra_size(), 0);
}

TEST(ConfigLoaderTest, DefaultsApplyWhenKeyAbsent) {
  TestConfig c;
  std::string error;
  ASSERT_TRUE(ParseTextConfig("", "empty.pbtxt", &c, &error)) << error;
  EXPECT_EQ(c.baud(), 9600);
}

TEST(ConfigLoaderTest, UnknownKeyNamesFileLineAndKey) {
  TestConfig c;
  std::string error;
  EXPECT_FALSE(ParseTextConfig("baud: 9600\nbogus_key: 3\n", "server.pbtxt", &c, &error));
  EXPECT_THAT(error, HasSubstr("server.pbtxt:2:"));
  EXPECT_THAT(error, HasSubstr("bogus_key"));
}

TEST(ConfigLoaderTest, WrongTypeIsRefused) {
  TestConfig c;
  std::string error;
  EXPECT_FALSE(ParseTextConfig("baud: \"fast\"\n", "a.pbtxt", &c, &error));
  EXPECT_THAT(error, HasSubstr("a.pbtxt:1:"));
}

TEST(ConfigLoaderTest, SyntaxErrorIsRefused) {
  TestConfig c;
  std::string error;
  EXPECT_FALSE(ParseTextConfig("inner { gain: 1.0\n", "a.pbtxt", &c, &error));
  EXPECT_THAT(error, HasSubstr("a.pbtxt:"));
}

TEST(ConfigLoaderTest, OutOfRangeNamesLineKeyAndBounds) {
  TestConfig c;
  std::string error;
  EXPECT_FALSE(ParseTextConfig("name: \"x\"\nbaud: 1200\n", "s.pbtxt", &c, &error));
  EXPECT_THAT(error, HasSubstr("s.pbtxt:2:1: baud: 1200 is outside [9600, 500000]"));
}

TEST(ConfigLoaderTest, NestedAndRepeatedRangesAreChecked) {
  TestConfig c;
  std::string error;
  EXPECT_FALSE(ParseTextConfig("extra { gain: 1 }\nextra { gain: 11 }\n", "n.pbtxt", &c, &error));
  EXPECT_THAT(error, HasSubstr("n.pbtxt:2:"));
  EXPECT_THAT(error, HasSubstr("extra[1].gain: 11 is outside [0, 10]"));
}

TEST(ConfigLoaderTest, NanIsRefused) {
  TestConfig c;
  std::string error;
  EXPECT_FALSE(ParseTextConfig("tilt_rad: nan\n", "n.pbtxt", &c, &error));
  EXPECT_THAT(error, HasSubstr("tilt_rad"));
}

TEST(ConfigLoaderTest, MissingFileIsAnError) {
  TestConfig c;
  std::string error;
  EXPECT_FALSE(LoadTextConfig("/nonexistent/dir/x.pbtxt", &c, &error));
  EXPECT_THAT(error, HasSubstr("cannot open"));
}

TEST(ConfigLoaderTest, SaveThenLoadRoundTrips) {
  TestConfig c;
  c.set_name("profile");
  c.set_tilt_rad(0.25f);
  c.mutable_inner()->set_gain(3);
  const std::string path = ::testing::TempDir() + "/roundtrip.pbtxt";
  std::string error;
  ASSERT_TRUE(SaveTextConfig(path, c, &error)) << error;
  TestConfig back;
  ASSERT_TRUE(LoadTextConfig(path, &back, &error)) << error;
  EXPECT_EQ(back.SerializeAsString(), c.SerializeAsString());
  std::remove(path.c_str());
}

TEST(ConfigLoaderTest, ValidateRangesOnBuiltMessage) {
  TestConfig c;
  c.set_baud(5);
  std::string error;
  EXPECT_FALSE(ValidateRanges(c, "flags", &error));
  EXPECT_THAT(error, HasSubstr("flags: baud: 5 is outside"));
}

}  // namespace
}  // namespace mostar
