// The walking skeleton end to end: the real robot_server and a headless operator_client on
// loopback DDS with a private domain id. Checks that frames, scans and commands flow both ways
// with matching stamps and sequence numbers, that the robot moves under the pilot's command,
// and that both programs shut down cleanly on SIGTERM.
#include <gtest/gtest.h>
#include <signal.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "common/dds/domain.h"
#include "common/testing/subprocess.h"
#include "common/testing/trace.h"

namespace mostar {
namespace {

using testing::Subprocess;

using testing::ReadTrace;

std::string Bin(const char* name) { return std::string(MOSTAR_TEST_BINARY_DIR) + "/" + name; }
std::string Source(const char* path) { return std::string(MOSTAR_TEST_SOURCE_DIR) + "/" + path; }

class EndToEndTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::getenv("DISPLAY") == nullptr) {
      GTEST_SKIP() << "no X display: run the suite under xvfb-run (as .ci/run does)";
    }
    dir_ = testing::MakeTempDir("mostar_e2e_");
    ASSERT_FALSE(dir_.empty());
    domain_ = std::to_string(dds::PerProcessDomainId());
  }
  std::string dir_;
  std::string domain_;
};

TEST_F(EndToEndTest, FramesScansAndCommandsFlowBothWays) {
  Subprocess server;
  std::string error;
  ASSERT_TRUE(server.Start({Bin("robot_server/robot_server"), "--domain", domain_, "--config",
                            Source("deploy/config/server_sim.pbtxt"), "--source", "test_pattern",
                            "--trace", dir_ + "/server.csv"},
                           dir_ + "/server.log", &error))
      << error;
  Subprocess client;
  ASSERT_TRUE(client.Start({Bin("operator_client/operator_client"), "--headless", "--domain",
                            domain_, "--id", "operator", "--duration", "6", "--drive", "0.3,0",
                            "--trace", dir_ + "/client.csv", "--screenshot", dir_ + "/client.png"},
                           dir_ + "/client.log", &error))
      << error;
  const std::optional<int> client_exit = client.Wait(std::chrono::seconds(60));
  ASSERT_TRUE(client_exit.has_value()) << "client hung";
  EXPECT_EQ(*client_exit, 0) << testing::ReadFile(dir_ + "/client.log");
  server.Signal(SIGTERM);
  const std::optional<int> server_exit = server.Wait(std::chrono::seconds(20));
  ASSERT_TRUE(server_exit.has_value()) << "server did not stop on SIGTERM";
  EXPECT_EQ(*server_exit, 0) << testing::ReadFile(dir_ + "/server.log");

  const auto published = ReadTrace(dir_ + "/server.csv");
  const auto received = ReadTrace(dir_ + "/client.csv");
  std::map<std::string, std::set<int64_t>> published_stamps;
  std::set<uint64_t> accepted_commands;
  uint64_t max_odom_x_mm = 0;
  for (const auto& t : published) {
    published_stamps[t.topic].insert(t.stamp_ns);
    if (t.topic == "command") accepted_commands.insert(t.sequence);
    if (t.topic == "odom_x_mm") max_odom_x_mm = std::max(max_odom_x_mm, t.sequence);
  }
  std::map<std::string, int> received_count;
  std::set<int64_t> left_stamps, right_stamps;
  std::set<uint64_t> sent_commands;
  uint64_t acked_sequence = 0;
  for (const auto& t : received) {
    ++received_count[t.topic];
    if (t.topic == "left" || t.topic == "right" || t.topic == "scan") {
      EXPECT_TRUE(published_stamps[t.topic].count(t.stamp_ns))
          << t.topic << " stamp " << t.stamp_ns << " was never published";
    }
    if (t.topic == "left") left_stamps.insert(t.stamp_ns);
    if (t.topic == "right") right_stamps.insert(t.stamp_ns);
    if (t.topic == "command") sent_commands.insert(t.sequence);
    if (t.topic == "health") acked_sequence = std::max(acked_sequence, t.sequence);
  }
  // Video, scans and health reached the client.
  EXPECT_GE(received_count["left"], 30);
  EXPECT_GE(received_count["right"], 30);
  EXPECT_GE(received_count["scan"], 10);
  EXPECT_GE(received_count["health"], 3);
  // Both eyes of a pair carry the same capture stamp.
  size_t paired = 0;
  for (int64_t s : left_stamps) paired += right_stamps.count(s);
  EXPECT_GE(paired, left_stamps.size() * 8 / 10);
  // Commands reached the robot: every accepted sequence was sent, and health echoes one.
  ASSERT_GE(accepted_commands.size(), 20u);
  for (uint64_t seq : accepted_commands) EXPECT_TRUE(sent_commands.count(seq)) << seq;
  EXPECT_TRUE(sent_commands.count(acked_sequence)) << acked_sequence;
  // The robot drove forward under the command (0.3 m/s for several seconds).
  EXPECT_GT(max_odom_x_mm, 500u);
  // The client rendered and saved a frame.
  EXPECT_FALSE(testing::ReadFile(dir_ + "/client.png").empty());
  const std::string report = testing::ReadFile(dir_ + "/client.log");
  EXPECT_NE(report.find("report: rendered_frames="), std::string::npos);
}

TEST_F(EndToEndTest, BadFlagsAndConfigGiveClearErrors) {
  Subprocess server;
  std::string error;
  ASSERT_TRUE(server.Start({Bin("robot_server/robot_server"), "--domain", "999"},
                           dir_ + "/bad_domain.log", &error));
  std::optional<int> code = server.Wait(std::chrono::seconds(20));
  ASSERT_TRUE(code.has_value());
  EXPECT_NE(*code, 0);
  EXPECT_NE(testing::ReadFile(dir_ + "/bad_domain.log").find("--domain"), std::string::npos);

  {
    std::ofstream bad(dir_ + "/bad.pbtxt");
    bad << "robot_id: \"x\"\ncontrol_period_s: 7\n";
  }
  Subprocess server2;
  ASSERT_TRUE(server2.Start({Bin("robot_server/robot_server"), "--config", dir_ + "/bad.pbtxt"},
                            dir_ + "/bad_config.log", &error));
  code = server2.Wait(std::chrono::seconds(20));
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 2);
  const std::string log = testing::ReadFile(dir_ + "/bad_config.log");
  EXPECT_NE(log.find("bad.pbtxt:2:1: control_period_s: 7 is outside"), std::string::npos) << log;

  Subprocess client;
  ASSERT_TRUE(
      client.Start({Bin("operator_client/operator_client"), "--display", "hologram", "--headless"},
                   dir_ + "/bad_display.log", &error));
  code = client.Wait(std::chrono::seconds(20));
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 2);
  EXPECT_NE(testing::ReadFile(dir_ + "/bad_display.log").find("unknown display mode"),
            std::string::npos);
}

}  // namespace
}  // namespace mostar
