// Drive safety across processes: the real robot_server (simulated robot) and real operator
// clients on loopback DDS. Who drives is decided by the lease; a pilot that disappears stops
// the robot within the deadman period plus the deceleration ramp.
#include <gtest/gtest.h>
#include <signal.h>

#include <atomic>
#include <cstdlib>
#include <fstream>
#include <map>
#include <thread>

#include "common/dds/conversions.h"
#include "common/dds/domain.h"
#include "common/dds/endpoint.h"
#include "common/dds/participant.h"
#include "common/dds/topics.h"
#include "common/identity/sender_partition.h"
#include "common/testing/subprocess.h"
#include "common/testing/trace.h"
#include "mostar_msgsPubSubTypes.h"

namespace mostar {
namespace {

using testing::ReadTrace;
using testing::Subprocess;
using testing::TraceLine;

std::string Bin(const char* name) { return std::string(MOSTAR_TEST_BINARY_DIR) + "/" + name; }
std::string Source(const char* path) { return std::string(MOSTAR_TEST_SOURCE_DIR) + "/" + path; }

class DriveIntegrationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::getenv("DISPLAY") == nullptr) {
      GTEST_SKIP() << "no X display: run the suite under xvfb-run (as deploy/test.sh does)";
    }
    dir_ = testing::MakeTempDir("mostar_drive_");
    ASSERT_FALSE(dir_.empty());
    domain_ = std::to_string(dds::PerProcessDomainId());
  }

  void StartServer(Subprocess* server) {
    std::string error;
    ASSERT_TRUE(
        server->Start({Bin("robot_server/robot_server"), "--domain", domain_, "--config",
                       Source("deploy/config/server_sim.pbtxt"), "--sim",
                       Source("deploy/scenes/open_room.pbtxt"), "--trace", dir_ + "/server.csv"},
                      dir_ + "/server.log", &error))
        << error;
  }

  void StartClient(Subprocess* client, const std::string& id, const std::string& role,
                   double duration_s, const std::string& drive) {
    std::vector<std::string> argv = {Bin("operator_client/operator_client"),
                                     "--headless",
                                     "--domain",
                                     domain_,
                                     "--id",
                                     id,
                                     "--role",
                                     role,
                                     "--duration",
                                     std::to_string(duration_s)};
    if (!drive.empty()) {
      argv.push_back("--drive");
      argv.push_back(drive);
    }
    std::string error;
    ASSERT_TRUE(client->Start(argv, dir_ + "/" + id + ".log", &error)) << error;
  }

  // Lease holders in order of change, from the server trace.
  std::vector<std::string> LeaseHistory() {
    std::vector<std::string> holders;
    for (const TraceLine& t : ReadTrace(dir_ + "/server.csv")) {
      if (t.topic.rfind("lease:", 0) != 0) continue;
      const std::string holder = t.topic.substr(6);
      if (holders.empty() || holders.back() != holder) holders.push_back(holder);
    }
    return holders;
  }

  std::string dir_;
  std::string domain_;
};

// Asks for the lease under `sender_id` over DDS, as a client would, every 300 ms until
// destroyed. The operator client never asks as an observer (it has no control request writer
// then), so this stands in for an observer that does.
class ControlRequester {
 public:
  ControlRequester(const std::string& domain, const std::string& sender_id, int32_t strength) {
    dds::ParticipantOptions options;
    options.domain_id = std::stoi(domain);
    options.name = sender_id;
    participant_ = dds::Participant::Create(options, &error_);
    if (participant_ == nullptr) return;
    writer_ = std::make_unique<dds::Writer<mostar_msgs::msg::dds_::ControlRequest_PubSubType>>(
        *participant_, dds::topics::kControlRequest,
        dds::InPartition(dds::WriterQos(dds::Stream::kControl),
                         identity::SenderPartition(sender_id)));
    if (!writer_->ok()) {
      error_ = writer_->error();
      return;
    }
    thread_ = std::thread([this, sender_id, strength] {
      while (!stop_) {
        ControlRequest request;
        request.stamp = SystemClock::Instance().Now();
        request.sender_id = sender_id;
        request.strength = strength;
        request.take = true;
        if (writer_->Write(dds::ToIdl(request))) ++sent_;
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
      }
    });
  }
  ~ControlRequester() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    writer_.reset();
  }
  bool ok() const { return writer_ != nullptr && writer_->ok(); }
  const std::string& error() const { return error_; }
  int matched() const { return writer_ ? writer_->matched() : 0; }
  int sent() const { return sent_.load(); }

 private:
  std::string error_;
  std::unique_ptr<dds::Participant> participant_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::ControlRequest_PubSubType>> writer_;
  std::atomic<bool> stop_{false};
  std::atomic<int> sent_{0};
  std::thread thread_;
};

TEST_F(DriveIntegrationTest, LeaseGoesToTheStrongerPilotAndBackNeverToTheObserver) {
  Subprocess server;
  StartServer(&server);
  Subprocess observer, weak, strong;
  StartClient(&observer, "observer", "observer", 22, "");
  // The observer (an observer in server_sim.pbtxt's role table) asks for the lease throughout,
  // with the largest strength a request can carry: the robot takes roles and strengths from
  // its own table, never from the request.
  ControlRequester observer_requests(domain_, "observer", 1000);
  ASSERT_TRUE(observer_requests.ok()) << observer_requests.error();
  // The robot reads control requests only in its pilots' partitions: the observer's requests,
  // in its own partition, are never even matched, let alone granted.
  const std::string observer_asked = "control take by observer: ";
  std::this_thread::sleep_for(std::chrono::seconds(3));
  EXPECT_EQ(observer_requests.matched(), 0);
  StartClient(&weak, "operator", "pilot", 22, "");  // strength 10 in server_sim.pbtxt
  std::this_thread::sleep_for(std::chrono::seconds(5));
  // Strength 20 in the role table: takes over, then leaves.
  StartClient(&strong, "operator-2", "pilot", 8, "");
  ASSERT_TRUE(strong.Wait(std::chrono::seconds(60)).has_value());
  ASSERT_TRUE(weak.Wait(std::chrono::seconds(60)).has_value());
  ASSERT_TRUE(observer.Wait(std::chrono::seconds(60)).has_value());
  const int observer_requests_sent = observer_requests.sent();
  server.Signal(SIGTERM);
  ASSERT_TRUE(server.Wait(std::chrono::seconds(20)).has_value());

  const std::vector<std::string> history = LeaseHistory();
  std::string joined;
  for (const auto& h : history) joined += "[" + h + "]";
  // Nobody, then the weak pilot, the strong one takes over, leaves (lease freed), the weak pilot
  // asks again and gets it back.
  auto find = [&](const std::string& holder, size_t from) {
    for (size_t i = from; i < history.size(); ++i) {
      if (history[i] == holder) return i;
    }
    return history.size();
  };
  const size_t first_weak = find("operator", 0);
  const size_t strong_at = find("operator-2", first_weak);
  const size_t weak_again = find("operator", strong_at);
  EXPECT_LT(first_weak, history.size()) << joined;
  EXPECT_LT(strong_at, history.size()) << joined;
  EXPECT_LT(weak_again, history.size()) << joined;
  EXPECT_EQ(find("observer", 0), history.size()) << "an observer held the lease: " << joined;
  // It kept asking while the pilots came, took over and left (one request per 300 ms), and
  // was never granted the lease.
  EXPECT_GT(observer_requests_sent, 40);
  EXPECT_EQ(testing::ReadFile(dir_ + "/server.log").find(observer_asked + "granted"),
            std::string::npos);
  // The simulated cameras' intrinsics reached the clients (camera_info topics).
  EXPECT_NE(testing::ReadFile(dir_ + "/observer.log").find("using the robot's camera intrinsics"),
            std::string::npos);
}

TEST_F(DriveIntegrationTest, KilledPilotStopsTheRobotWithinDeadmanAndRamp) {
  Subprocess server;
  StartServer(&server);
  Subprocess pilot;
  StartClient(&pilot, "operator", "pilot", 60, "0.3,0");
  // Wait until the robot drives (lease and arming take longer on a loaded machine), drive on
  // for a second, then kill the pilot without any goodbye. The trace is buffered, so motion is
  // seen here with some delay; that only lengthens the drive.
  bool driving = false;
  for (int i = 0; i < 600 && !driving; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    for (const TraceLine& t : ReadTrace(dir_ + "/server.csv")) {
      if (t.topic == "drive_out_mmps" && t.sequence > 100) driving = true;
    }
  }
  ASSERT_TRUE(driving) << "the robot never drove: " << testing::ReadFile(dir_ + "/server.log");
  std::this_thread::sleep_for(std::chrono::seconds(1));
  pilot.Signal(SIGKILL);
  ASSERT_TRUE(pilot.Wait(std::chrono::seconds(10)).has_value());
  std::this_thread::sleep_for(std::chrono::seconds(2));
  server.Signal(SIGTERM);
  ASSERT_TRUE(server.Wait(std::chrono::seconds(20)).has_value());

  // When the last accepted command arrived, on the robot's clock (the deadman counts from there).
  int64_t last_command_ns = 0;
  for (const TraceLine& t : ReadTrace(dir_ + "/server.csv")) {
    if (t.topic == "command_rx") last_command_ns = std::max(last_command_ns, t.stamp_ns);
  }
  ASSERT_GT(last_command_ns, 0) << "no command was accepted: "
                                << testing::ReadFile(dir_ + "/server.log");
  // Output speed over time after the last accepted command (robot clock = command clock here).
  // Until the deadman expires the robot may still follow the last command and the obstacle
  // governor (speeding up or slowing down); after it, the output may only fall, to zero.
  const double deadman_s = 0.25, cycle_s = 0.02, decel_mps2 = 1.0;
  // Deadman plus one control cycle, plus 100 ms for scheduling: here the robot, the simulator's
  // renderer, a software-OpenGL client and other tests share two cores. The exact bound is
  // checked with an injected clock in
  // SafetyGovernorTest.DeadmanRampsToZeroWithinPeriodPlusOneCycle.
  const double scheduling_slack_s = 0.1;
  const int64_t ramp_from_ns =
      last_command_ns + static_cast<int64_t>((deadman_s + cycle_s + scheduling_slack_s) * 1e9);
  uint64_t speed_at_cut = 0;
  uint64_t peak_speed = 0;  // the fastest output between the last command and the ramp
  uint64_t previous = 0;
  int rises_after_deadman = 0;
  int64_t stopped_ns = -1;
  for (const TraceLine& t : ReadTrace(dir_ + "/server.csv")) {
    if (t.topic != "drive_out_mmps") continue;
    if (t.stamp_ns <= last_command_ns) {
      speed_at_cut = t.sequence;
    } else if (t.stamp_ns <= ramp_from_ns) {
      peak_speed = std::max(peak_speed, t.sequence);
    } else if (t.sequence > previous) {
      ++rises_after_deadman;
    }
    previous = t.sequence;
    if (t.stamp_ns > last_command_ns && stopped_ns < 0 && t.sequence == 0) stopped_ns = t.stamp_ns;
  }
  peak_speed = std::max(peak_speed, speed_at_cut);
  // The governor may already have slowed down for obstacles ahead; it must be moving.
  ASSERT_GT(speed_at_cut, 20u) << "the robot was not driving when the pilot died";
  EXPECT_EQ(rises_after_deadman, 0) << "the robot sped up after the deadman expired";
  ASSERT_GT(stopped_ns, 0) << "the robot never stopped";
  EXPECT_LE((stopped_ns - last_command_ns) * 1e-9,
            deadman_s + peak_speed * 1e-3 / decel_mps2 + 2 * cycle_s + scheduling_slack_s);
}

}  // namespace
}  // namespace mostar
