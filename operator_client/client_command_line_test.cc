#include "operator_client/client_command_line.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace mostar::client {
namespace {

// Parses `args` (after the program name) as operator_client would; false on a refusal.
bool Parse(std::vector<std::string> args, ClientCommandLine* line, std::string* error = nullptr) {
  CLI::App app{"test"};
  AddClientOptions(&app, line);
  args.insert(args.begin(), "operator_client");
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::ParseError& e) {
    if (error != nullptr) *error = e.what();
    return false;
  }
  return true;
}

TEST(ClientCommandLineTest, DefaultsAreALoopbackPilotWithoutLimits) {
  ClientCommandLine line;
  ASSERT_TRUE(Parse({}, &line));
  EXPECT_EQ(line.domain, -1);
  EXPECT_EQ(line.dds_profile, "loopback");
  EXPECT_EQ(line.flags.role, "pilot");
  EXPECT_EQ(line.flags.client_id, "operator");
  EXPECT_FALSE(line.flags.client_id_given);
  EXPECT_FALSE(line.capture());
  EXPECT_EQ(line.max_frames, 0);
  EXPECT_TRUE(line.scripted_drive.empty());
}

TEST(ClientCommandLineTest, ValuesReachTheirFields) {
  ClientCommandLine line;
  ASSERT_TRUE(Parse({"--id", "alice", "--role", "observer", "--window-size", "320x240", "--drive",
                     "0.1,-0.2", "--video-via-relay", "--video-domain", "7", "--duration", "2.5",
                     "--capture-after", "3", "--headless", "--strength", "10"},
                    &line));
  EXPECT_EQ(line.flags.client_id, "alice");
  EXPECT_TRUE(line.flags.client_id_given);
  EXPECT_EQ(line.flags.role, "observer");
  EXPECT_EQ(line.flags.window_size, (std::vector<int>{320, 240}));
  EXPECT_EQ(line.scripted_drive, (std::vector<double>{0.1, -0.2}));
  EXPECT_TRUE(line.video_via_relay);
  EXPECT_EQ(line.video_domain, 7);
  EXPECT_DOUBLE_EQ(line.duration_s, 2.5);
  EXPECT_TRUE(line.capture());
  EXPECT_TRUE(line.flags.headless);
}

TEST(ClientCommandLineTest, ContradictionsAndBadValuesAreRefused) {
  ClientCommandLine line;
  std::string error;
  EXPECT_FALSE(Parse({"--video-domain", "3"}, &line, &error));  // needs --video-via-relay
  EXPECT_NE(error.find("video-via-relay"), std::string::npos) << error;
  EXPECT_FALSE(Parse({"--capture-stamp", "5", "--capture-after", "2"}, &line));
  EXPECT_FALSE(Parse({"--role", "driver"}, &line));
  EXPECT_FALSE(Parse({"--domain", "233"}, &line));
  EXPECT_FALSE(Parse({"--frames", "-1"}, &line));
  EXPECT_FALSE(Parse({"--drive", "0.1"}, &line));  // V and W
  EXPECT_FALSE(Parse({"--log-level", "loud"}, &line));
}

}  // namespace
}  // namespace mostar::client
