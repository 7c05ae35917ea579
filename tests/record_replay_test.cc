// Recording and replay across processes: robot_server --record on the simulated robot, the info
// tool on the file, robot_server --replay to a headless client, and a truncated file replayed up
// to the damage.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include "common/dds/domain.h"
#include "common/testing/subprocess.h"
#include "common/testing/trace.h"

namespace mostar {
namespace {

using testing::ReadTrace;
using testing::Subprocess;

std::string Bin(const char* name) { return std::string(MOSTAR_TEST_BINARY_DIR) + "/" + name; }
std::string Source(const char* path) { return std::string(MOSTAR_TEST_SOURCE_DIR) + "/" + path; }

class RecordReplayTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::getenv("DISPLAY") == nullptr) {
      GTEST_SKIP() << "no X display: run the suite under xvfb-run (as deploy/test.sh does)";
    }
    dir_ = testing::MakeTempDir("mostar_rec_");
    ASSERT_FALSE(dir_.empty());
    domain_ = std::to_string(dds::PerProcessDomainId());
  }
  std::string dir_;
  std::string domain_;
};

TEST_F(RecordReplayTest, RecordedSimulatorSessionReplaysToAClient) {
  const std::string recording = dir_ + "/session.mostar";
  std::string error;
  {
    Subprocess recorder;
    ASSERT_TRUE(recorder.Start({Bin("robot_server/robot_server"), "--domain", domain_, "--config",
                                Source("deploy/config/server_sim.pbtxt"), "--record", recording,
                                "--duration", "6", "--trace", dir_ + "/recorded.csv"},
                               dir_ + "/record.log", &error))
        << error;
    const auto code = recorder.Wait(std::chrono::seconds(60));
    ASSERT_TRUE(code.has_value());
    ASSERT_EQ(*code, 0) << testing::ReadFile(dir_ + "/record.log");
  }
  {
    Subprocess info;
    ASSERT_TRUE(info.Start({Bin("common/record/mostar_record_info"), recording}, dir_ + "/info.log",
                           &error));
    const auto code = info.Wait(std::chrono::seconds(30));
    ASSERT_TRUE(code.has_value());
    const std::string summary = testing::ReadFile(dir_ + "/info.log");
    EXPECT_EQ(*code, 0) << summary;
    EXPECT_NE(summary.find("scan"), std::string::npos) << summary;
    EXPECT_NE(summary.find("camera/left"), std::string::npos) << summary;
  }
  std::set<int64_t> recorded_frames, recorded_scans;
  for (const auto& t : ReadTrace(dir_ + "/recorded.csv")) {
    if (t.topic == "left") recorded_frames.insert(t.stamp_ns);
    if (t.topic == "scan") recorded_scans.insert(t.stamp_ns);
  }
  ASSERT_GE(recorded_frames.size(), 10u);
  ASSERT_GE(recorded_scans.size(), 10u);

  Subprocess replay;
  ASSERT_TRUE(replay.Start({Bin("robot_server/robot_server"), "--domain", domain_, "--replay",
                            recording, "--loop", "--trace", dir_ + "/replayed.csv"},
                           dir_ + "/replay.log", &error));
  Subprocess client;
  ASSERT_TRUE(client.Start(
      {Bin("operator_client/operator_client"), "--headless", "--domain", domain_, "--role",
       "observer", "--id", "observer", "--duration", "8", "--trace", dir_ + "/client.csv",
       "--screenshot", dir_ + "/replay.png", "--record", dir_ + "/observer.mostar"},
      dir_ + "/client.log", &error));
  const auto client_code = client.Wait(std::chrono::seconds(60));
  replay.Signal(SIGTERM);
  ASSERT_TRUE(replay.Wait(std::chrono::seconds(20)).has_value());
  ASSERT_TRUE(client_code.has_value());
  EXPECT_EQ(*client_code, 0) << testing::ReadFile(dir_ + "/client.log");
  size_t frames = 0, scans = 0;
  for (const auto& t : ReadTrace(dir_ + "/client.csv")) {
    if (t.topic == "left") {
      ++frames;
      EXPECT_TRUE(recorded_frames.count(t.stamp_ns)) << "frame not from the recording";
    }
    if (t.topic == "scan") {
      ++scans;
      EXPECT_TRUE(recorded_scans.count(t.stamp_ns)) << "scan not from the recording";
    }
  }
  EXPECT_GE(frames, 10u);
  EXPECT_GE(scans, 10u);
  EXPECT_FALSE(testing::ReadFile(dir_ + "/replay.png").empty());
  {
    // The observer's own recording of what it received.
    Subprocess info;
    ASSERT_TRUE(info.Start({Bin("common/record/mostar_record_info"), dir_ + "/observer.mostar"},
                           dir_ + "/observer_info.log", &error));
    const auto code = info.Wait(std::chrono::seconds(30));
    ASSERT_TRUE(code.has_value());
    const std::string summary = testing::ReadFile(dir_ + "/observer_info.log");
    EXPECT_EQ(*code, 0) << summary;
    EXPECT_NE(summary.find("camera/left"), std::string::npos) << summary;
    EXPECT_NE(summary.find("scan"), std::string::npos) << summary;
  }

  // Paused replay, stepped from standard input: exactly the stepped records are published.
  {
    Subprocess stepped;
    ASSERT_TRUE(
        stepped.StartWithStdin({Bin("robot_server/robot_server"), "--domain", domain_, "--replay",
                                recording, "--replay-paused", "--trace", dir_ + "/stepped.csv"},
                               dir_ + "/stepped.log", &error));
    std::this_thread::sleep_for(std::chrono::seconds(2));
    ASSERT_TRUE(stepped.WriteStdin("s 40\n"));
    std::this_thread::sleep_for(std::chrono::seconds(2));
    ASSERT_TRUE(stepped.WriteStdin("q\n"));
    const auto code = stepped.Wait(std::chrono::seconds(30));
    ASSERT_TRUE(code.has_value()) << "replay did not quit on 'q'";
    EXPECT_EQ(*code, 0) << testing::ReadFile(dir_ + "/stepped.log");
    // 40 records of every kind were published; the trace holds the images and scans among them.
    size_t traced = 0;
    for (const auto& t : ReadTrace(dir_ + "/stepped.csv")) {
      traced += t.topic == "left" || t.topic == "right" || t.topic == "scan";
    }
    EXPECT_GT(traced, 0u);
    EXPECT_LE(traced, 40u);
  }

  // A truncated copy replays up to the damage and says where it is.
  const std::string data = testing::ReadFile(recording);
  const std::string truncated = dir_ + "/truncated.mostar";
  {
    std::ofstream out(truncated, std::ios::binary);
    out.write(data.data(), static_cast<std::streamsize>(data.size() / 2));
  }
  Subprocess damaged;
  ASSERT_TRUE(damaged.Start({Bin("robot_server/robot_server"), "--domain", domain_, "--replay",
                             truncated, "--replay-rate", "8", "--trace", dir_ + "/damaged.csv"},
                            dir_ + "/damaged.log", &error));
  const auto code = damaged.Wait(std::chrono::seconds(60));
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 0);
  const std::string log = testing::ReadFile(dir_ + "/damaged.log");
  EXPECT_NE(log.find("damaged at byte"), std::string::npos) << log;
  size_t replayed = 0;
  for (const auto& t : ReadTrace(dir_ + "/damaged.csv")) replayed += t.topic == "scan";
  EXPECT_GT(replayed, 0u);
  EXPECT_LT(replayed, recorded_scans.size());
}

}  // namespace
}  // namespace mostar
