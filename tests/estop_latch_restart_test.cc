// The persistent e-stop latch across real restarts of robot_server (test pattern source, its
// own DDS domain, a temporary state directory): killed, it comes back latched with the reason in
// its health; a pilot's release and a clean stop bring it back unlatched.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>

#include <atomic>
#include <mutex>
#include <optional>
#include <thread>

#include "common/dds/conversions.h"
#include "common/dds/domain.h"
#include "common/dds/endpoint.h"
#include "common/dds/participant.h"
#include "common/dds/topics.h"
#include "common/identity/sender_partition.h"
#include "common/testing/subprocess.h"
#include "mostar_msgsPubSubTypes.h"

namespace mostar {
namespace {

using std::chrono::seconds;
using testing::Subprocess;

std::string Bin(const char* name) { return std::string(MOSTAR_TEST_BINARY_DIR) + "/" + name; }
std::string Source(const char* path) { return std::string(MOSTAR_TEST_SOURCE_DIR) + "/" + path; }

// What the robot last said about its e-stop.
struct LatchReport {
  Time stamp;  // robot clock (this machine's)
  bool engaged = false;
  std::string latch_message;  // of the "estop_latch" device
};

class EstopLatchRestartTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::MakeTempDir("mostar_estop_restart_");
    ASSERT_FALSE(dir_.empty());
    state_dir_ = dir_ + "/state";
    ASSERT_EQ(::mkdir(state_dir_.c_str(), 0700), 0);
    dds::ParticipantOptions options;
    options.domain_id = dds::PerProcessDomainId();
    options.name = "latch-test";
    std::string error;
    participant_ = dds::Participant::Create(options, &error);
    ASSERT_NE(participant_, nullptr) << error;
    health_ = std::make_unique<dds::Reader<mostar_msgs::msg::dds_::RobotHealth_PubSubType>>(
        *participant_, dds::topics::kHealth, dds::Stream::kState,
        [this](const dds::wire::RobotHealth& wire) {
          const RobotHealth health = dds::FromIdl(wire);
          LatchReport report;
          report.stamp = health.stamp;
          report.engaged = health.estop_engaged;
          for (const DeviceHealth& device : health.devices) {
            if (device.name == "estop_latch") report.latch_message = device.message;
          }
          std::lock_guard<std::mutex> lock(mutex_);
          report_ = report;
        });
    // As the pilot "operator" of server_sim.pbtxt, in its partition.
    const auto qos = dds::InPartition(dds::WriterQos(dds::Stream::kControl),
                                      identity::SenderPartition("operator"));
    estop_ = std::make_unique<dds::Writer<mostar_msgs::msg::dds_::EmergencyStop_PubSubType>>(
        *participant_, dds::topics::kEmergencyStop, qos);
    request_ = std::make_unique<dds::Writer<mostar_msgs::msg::dds_::ControlRequest_PubSubType>>(
        *participant_, dds::topics::kControlRequest, qos);
  }

  void StartServer(Subprocess* server, int run) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      report_.reset();
      started_ = SystemClock::Instance().Now();  // reports of an earlier run are older
    }
    std::string error;
    ASSERT_TRUE(server->Start(
        {Bin("robot_server/robot_server"), "--domain", std::to_string(dds::PerProcessDomainId()),
         "--config", Source("deploy/config/server_sim.pbtxt"), "--source", "test_pattern",
         "--state-dir", state_dir_},
        dir_ + "/server" + std::to_string(run) + ".log", &error))
        << error;
  }

  // The first health report of the running server (up to 60 s on a loaded machine).
  std::optional<LatchReport> FirstReport() {
    for (int i = 0; i < 600; ++i) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (report_ && report_->stamp >= started_) return report_;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return std::nullopt;
  }

  // As the pilot "operator": takes the lease (only its holder may release the e-stop) and sends
  // a release, until the health reports it released.
  bool Release() {
    for (int i = 0; i < 300; ++i) {
      ControlRequest take;
      take.stamp = SystemClock::Instance().Now();
      take.sender_id = "operator";
      take.take = true;
      request_->Write(dds::ToIdl(take));
      EmergencyStop stop;
      stop.stamp = SystemClock::Instance().Now();
      stop.sender_id = "operator";  // a pilot in server_sim.pbtxt's role table
      stop.engage = false;
      estop_->Write(dds::ToIdl(stop));
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      std::lock_guard<std::mutex> lock(mutex_);
      if (report_ && report_->stamp >= started_ && !report_->engaged) return true;
    }
    return false;
  }

  // The newest report of the running server says released (up to 30 s).
  bool ReportsReleased() {
    for (int i = 0; i < 300; ++i) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (report_ && report_->stamp >= started_ && !report_->engaged) return true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return false;
  }

  std::string dir_;
  std::string state_dir_;
  std::unique_ptr<dds::Participant> participant_;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::RobotHealth_PubSubType>> health_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::EmergencyStop_PubSubType>> estop_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::ControlRequest_PubSubType>> request_;
  std::mutex mutex_;
  std::optional<LatchReport> report_;
  Time started_;
};

TEST_F(EstopLatchRestartTest, AKilledServerComesBackLatchedUntilAPilotReleasesIt) {
  Subprocess server;
  StartServer(&server, 1);
  std::optional<LatchReport> report = FirstReport();
  ASSERT_TRUE(report.has_value()) << testing::ReadFile(dir_ + "/server1.log");
  EXPECT_FALSE(report->engaged) << "first start in an empty state directory";
  EXPECT_NE(report->latch_message.find("started unlatched"), std::string::npos)
      << report->latch_message;
  server.Signal(SIGKILL);  // as the service watchdog does
  ASSERT_TRUE(server.Wait(seconds(20)).has_value());

  StartServer(&server, 2);
  report = FirstReport();
  ASSERT_TRUE(report.has_value()) << testing::ReadFile(dir_ + "/server2.log");
  EXPECT_TRUE(report->engaged);
  EXPECT_NE(report->latch_message.find("did not stop cleanly"), std::string::npos)
      << report->latch_message;
  ASSERT_TRUE(Release()) << testing::ReadFile(dir_ + "/server2.log");
  server.Signal(SIGTERM);
  EXPECT_EQ(server.Wait(seconds(20)), std::optional<int>(0));

  StartServer(&server, 3);
  report = FirstReport();
  ASSERT_TRUE(report.has_value()) << testing::ReadFile(dir_ + "/server3.log");
  EXPECT_FALSE(report->engaged) << "released, then stopped cleanly";
  EXPECT_NE(report->latch_message.find("started unlatched"), std::string::npos)
      << report->latch_message;
  server.Signal(SIGTERM);
  EXPECT_EQ(server.Wait(seconds(20)), std::optional<int>(0));
}

// Someone at the robot (root) releases the latch without a pilot: SIGUSR2 to robot_server.
TEST_F(EstopLatchRestartTest, SigusrTwoReleasesTheLatchAtTheRobot) {
  Subprocess server;
  StartServer(&server, 1);
  ASSERT_TRUE(FirstReport().has_value()) << testing::ReadFile(dir_ + "/server1.log");
  server.Signal(SIGKILL);
  ASSERT_TRUE(server.Wait(seconds(20)).has_value());
  StartServer(&server, 2);
  const std::optional<LatchReport> report = FirstReport();
  ASSERT_TRUE(report.has_value()) << testing::ReadFile(dir_ + "/server2.log");
  ASSERT_TRUE(report->engaged);
  server.Signal(SIGUSR2);
  EXPECT_TRUE(ReportsReleased()) << testing::ReadFile(dir_ + "/server2.log");
  EXPECT_NE(testing::ReadFile(dir_ + "/server2.log").find("released locally"), std::string::npos);
  server.Signal(SIGTERM);
  EXPECT_EQ(server.Wait(seconds(20)), std::optional<int>(0));
}

}  // namespace
}  // namespace mostar
