// Sender identities under DDS Security, across processes: the real robot_server on a secure
// profile made by deploy/security/make_pki.sh (PKI-DH, permissions, AES-GCM), actors with
// certificates of their own (identity_actor), and this process as an observer ("watcher")
// reading health, lease and odometry. Every process uses this test's own DDS domain.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <regex>
#include <set>
#include <thread>

#include "common/dds/conversions.h"
#include "common/dds/domain.h"
#include "common/dds/endpoint.h"
#include "common/dds/participant.h"
#include "common/dds/topics.h"
#include "common/testing/subprocess.h"
#include "mostar_msgsPubSubTypes.h"
#include "ros2_msgsPubSubTypes.h"

namespace mostar {
namespace {

using testing::Subprocess;
using namespace std::chrono_literals;

std::string Bin(const std::string& name) {
  return std::string(MOSTAR_TEST_BINARY_DIR) + "/" + name;
}
std::string Source(const std::string& path) {
  return std::string(MOSTAR_TEST_SOURCE_DIR) + "/" + path;
}

template <class Predicate>
bool WaitUntil(Predicate predicate, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (predicate()) return true;
    std::this_thread::sleep_for(50ms);
  }
  return predicate();
}

class SenderIdentityTest : public ::testing::Test {
 protected:
  // One PKI for the test suite: Fast DDS keeps the first XML profile of a name for the whole
  // process, so every test of this process uses the same profile files.
  static void SetUpTestSuite() {
    pki_dir_ = testing::MakeTempDir("mostar_identity_pki_");
    // Pilots alice and bob, observers carol and watcher (the test process).
    const std::string pki = Source("deploy/security/make_pki.sh") + " " + pki_dir_ + " --profile " +
                            Source("tests/security/secure_loopback.xml") +
                            " --pilot alice --pilot bob --observer carol --observer watcher" +
                            " > " + pki_dir_ + "/make_pki.log 2>&1";
    pki_made_ = !pki_dir_.empty() && std::system(pki.c_str()) == 0;
  }
  static void TearDownTestSuite() { std::system(("rm -rf " + pki_dir_).c_str()); }

  void SetUp() override {
    ASSERT_TRUE(pki_made_) << testing::ReadFile(pki_dir_ + "/make_pki.log");
    dir_ = testing::MakeTempDir("mostar_identity_");
    ASSERT_FALSE(dir_.empty());
    domain_ = std::to_string(dds::PerProcessDomainId());
    // The role table is keyed by the certificates' CNs.
    std::ofstream(dir_ + "/robot.pbtxt") << R"(
robot_id: "identity-test"
source: TEST_PATTERN
test_pattern { frame_rate_hz: 2 width_px: 160 height_px: 120 }
drive {
  roles { client_id: "alice" role: PILOT strength: 10 }
  roles { client_id: "bob" role: PILOT strength: 20 }
  roles { client_id: "carol" role: OBSERVER }
}
)";
    std::string error;
    ASSERT_TRUE(robot_.Start({Bin("robot_server/robot_server"), "--domain", domain_, "--config",
                              dir_ + "/robot.pbtxt", "--dds-profile", pki_dir_ + "/robot.xml"},
                             dir_ + "/robot.log", &error))
        << error;
    dds::ParticipantOptions options;
    options.domain_id = std::stoi(domain_);
    options.profile = pki_dir_ + "/watcher.xml";
    options.name = "operator";
    watcher_ = dds::Participant::Create(options, &error);
    ASSERT_NE(watcher_, nullptr) << error;
    health_ =
        std::make_unique<HealthReader>(*watcher_, dds::topics::kHealth, dds::Stream::kState,
                                       [this](const dds::wire::RobotHealth& h) {
                                         std::lock_guard<std::mutex> lock(mutex_);
                                         health_seen_ = dds::FromIdl(h);
                                         if (health_seen_.watchdog_state == WatchdogState::kDriving)
                                           ever_driving_ = true;
                                       });
    lease_ =
        std::make_unique<LeaseReader>(*watcher_, dds::topics::kControlLease, dds::Stream::kState,
                                      [this](const dds::wire::ControlLease& l) {
                                        std::lock_guard<std::mutex> lock(mutex_);
                                        holder_ = l.holder_id().to_string();
                                      });
    odometry_ = std::make_unique<OdometryReader>(
        *watcher_, dds::topics::kOdometry, dds::Stream::kSensor,
        [this](const dds::wire::Odometry& o) {
          const Odometry odometry = dds::FromIdl(o);
          std::lock_guard<std::mutex> lock(mutex_);
          max_speed_ = std::max(
              {max_speed_, std::abs(odometry.linear_mps), std::abs(odometry.angular_radps)});
        });
    ASSERT_TRUE(health_->ok() && lease_->ok() && odometry_->ok());
    ASSERT_TRUE(WaitUntil([this] { return Health().robot_id == "identity-test"; }, 30s))
        << "no health from the robot: " << testing::ReadFile(dir_ + "/robot.log");
  }

  void TearDown() override {
    health_.reset();
    lease_.reset();
    odometry_.reset();
    watcher_.reset();
    robot_.Signal(SIGTERM);
    robot_.Wait(20s);
    if (!HasFailure()) std::system(("rm -rf " + dir_).c_str());
  }

  // An actor with `certificate`'s PKI files, claiming `sender_id`.
  void StartActor(Subprocess* actor, const std::string& certificate, const std::string& sender_id,
                  std::vector<std::string> args, double duration_s, bool with_stdin = false) {
    std::vector<std::string> argv = {Bin("tests/security/identity_actor"),
                                     "--domain",
                                     domain_,
                                     "--dds-profile",
                                     pki_dir_ + "/" + certificate + ".xml",
                                     "--sender-id",
                                     sender_id,
                                     "--duration-s",
                                     std::to_string(duration_s)};
    argv.insert(argv.end(), args.begin(), args.end());
    const std::string log =
        dir_ + "/" + certificate + "_as_" + sender_id + "_" + std::to_string(++actors_) + ".log";
    std::string error;
    ASSERT_TRUE(with_stdin ? actor->StartWithStdin(argv, log, &error)
                           : actor->Start(argv, log, &error))
        << error;
  }
  // Runs an actor to its end; expects a clean exit.
  void RunActor(const std::string& certificate, const std::string& sender_id,
                std::vector<std::string> args, double duration_s) {
    Subprocess actor;
    StartActor(&actor, certificate, sender_id, std::move(args), duration_s);
    const std::optional<int> status = actor.Wait(60s);
    ASSERT_EQ(status, 0) << certificate << " as " << sender_id;
  }

  RobotHealth Health() {
    std::lock_guard<std::mutex> lock(mutex_);
    return health_seen_;
  }
  std::string Holder() {
    std::lock_guard<std::mutex> lock(mutex_);
    return holder_;
  }
  // A counter of the robot's health device `device`; -1 when absent.
  int64_t Counter(const std::string& device, const std::string& name) {
    for (const DeviceHealth& d : Health().devices) {
      if (d.name != device) continue;
      for (const auto& [key, value] : d.counters) {
        if (key == name) return static_cast<int64_t>(value);
      }
    }
    return -1;
  }
  // Waits for two fresh health samples, so that counters include everything sent before.
  void WaitForFreshHealth() {
    const Time now = SystemClock::Instance().Now();
    ASSERT_TRUE(WaitUntil([&] { return Health().stamp > now + 600ms; }, 10s));
  }

  using HealthReader = dds::Reader<mostar_msgs::msg::dds_::RobotHealth_PubSubType>;
  using LeaseReader = dds::Reader<mostar_msgs::msg::dds_::ControlLease_PubSubType>;
  using OdometryReader = dds::Reader<nav_msgs::msg::dds_::Odometry_PubSubType>;

  static std::string pki_dir_;
  static bool pki_made_;
  std::string dir_;
  std::string domain_;
  Subprocess robot_;
  std::unique_ptr<dds::Participant> watcher_;
  std::unique_ptr<HealthReader> health_;
  std::unique_ptr<LeaseReader> lease_;
  std::unique_ptr<OdometryReader> odometry_;
  std::mutex mutex_;
  RobotHealth health_seen_;
  std::string holder_;
  bool ever_driving_ = false;
  double max_speed_ = 0;
  int actors_ = 0;
};

std::string SenderIdentityTest::pki_dir_;
bool SenderIdentityTest::pki_made_ = false;

// Bob's pilot certificate with Alice's sender_id: commands that would arm and turn the robot,
// clock pings keyed by Alice, a release of Alice's lease. All dropped and counted; Alice keeps
// the lease and the robot never moves, until Alice herself drives.
TEST_F(SenderIdentityTest, APilotCannotActUnderAnotherPilotsId) {
  EXPECT_EQ(Counter("network", "identities_verified"), 1);
  Subprocess alice;
  StartActor(&alice, "alice", "alice", {"--take", "--commands", "idle", "--pings", "--stdin"}, 90,
             /*with_stdin=*/true);
  ASSERT_TRUE(WaitUntil([this] { return Holder() == "alice"; }, 30s))
      << testing::ReadFile(dir_ + "/robot.log");

  RunActor("bob", "alice",
           {"--commands", "drive", "--angular", "0.8", "--first-sequence", "1000000", "--pings"},
           4);
  RunActor("bob", "alice", {"--release"}, 3);
  WaitForFreshHealth();
  EXPECT_EQ(Holder(), "alice");
  EXPECT_GE(Counter("network", "dropped_cmd_vel"), 20);
  EXPECT_GE(Counter("network", "dropped_clock_ping"), 5);
  EXPECT_GE(Counter("network", "dropped_control_request"), 2);
  EXPECT_GE(Counter("network", "sender_mismatch_dropped"), 27);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    EXPECT_FALSE(ever_driving_) << "the impostor's commands armed the robot";
    EXPECT_EQ(max_speed_, 0.0) << "the robot moved";
  }
  const std::string log = testing::ReadFile(dir_ + "/robot.log");
  EXPECT_NE(log.find("in the partition of 'bob'"), std::string::npos);
  // The log names each participant by the client whose partition it proved it may write in:
  // alice and bob, each participant one client only, although bob wrote as alice.
  std::map<std::string, std::set<std::string>> clients_of_participant;
  const std::regex proof(
      "client '([a-z]+)' is DDS participant ([0-9a-f.]+): its [a-z_]+ writer "
      "matched in partition mostar\\.client\\.\\1, which DDS access control "
      "allows only the signed permissions of '\\1'");
  for (auto it = std::sregex_iterator(log.begin(), log.end(), proof); it != std::sregex_iterator();
       ++it) {
    clients_of_participant[(*it)[2]].insert((*it)[1]);
  }
  std::set<std::string> proven;
  for (const auto& [participant, clients] : clients_of_participant) {
    EXPECT_EQ(clients.size(), 1u) << participant << " shown as more than one client";
    proven.insert(clients.begin(), clients.end());
  }
  EXPECT_EQ(proven, (std::set<std::string>{"alice", "bob"})) << log;

  // Alice herself drives: the robot turns (so the checks above could have failed).
  ASSERT_TRUE(alice.WriteStdin("drive 0.8\n"));
  EXPECT_TRUE(WaitUntil(
      [this] {
        std::lock_guard<std::mutex> lock(mutex_);
        return ever_driving_ && max_speed_ > 0.1;
      },
      15s))
      << testing::ReadFile(dir_ + "/robot.log");
  alice.CloseStdin();
}

// An observer may engage the e-stop but not release it, neither under its own id nor under the
// holder's; a pilot who does not hold the lease cannot either. The holder can.
TEST_F(SenderIdentityTest, AnObserverEngagesTheEstopButOnlyTheHolderReleasesIt) {
  Subprocess alice;
  StartActor(&alice, "alice", "alice", {"--take", "--commands", "idle", "--stdin"}, 90,
             /*with_stdin=*/true);
  ASSERT_TRUE(WaitUntil([this] { return Holder() == "alice"; }, 30s))
      << testing::ReadFile(dir_ + "/robot.log");

  RunActor("carol", "carol", {"--estop", "engage"}, 2);
  ASSERT_TRUE(WaitUntil([this] { return Health().estop_engaged; }, 10s));
  const int64_t refused_before = Counter("drive_safety", "estop_refused");

  RunActor("carol", "carol", {"--estop", "release"}, 2);
  RunActor("carol", "alice", {"--estop", "release"}, 2);
  RunActor("bob", "bob", {"--estop", "release"}, 2);
  WaitForFreshHealth();
  EXPECT_TRUE(Health().estop_engaged);
  // Carol's and Bob's own releases reach the lease check and are refused; Carol's release as
  // Alice never gets that far.
  EXPECT_GE(Counter("drive_safety", "estop_refused"), refused_before + 2);
  EXPECT_GE(Counter("network", "dropped_estop"), 1);
  EXPECT_GE(Counter("network", "sender_mismatch_dropped"), 1);

  ASSERT_TRUE(alice.WriteStdin("estop release\n"));
  EXPECT_TRUE(WaitUntil([this] { return !Health().estop_engaged; }, 10s))
      << testing::ReadFile(dir_ + "/robot.log");
  alice.CloseStdin();
}

}  // namespace
}  // namespace mostar
