// The robot's control loop on real DDS (loopback, a domain of this process's own): an operator's
// control requests and commands arrive on DDS threads while the controller steps on its own
// thread and the laser's thread publishes scans through the node's outbox. The thread-sanitizer
// build runs it (label "concurrency"): races between DDS callbacks, the governor, the lease and
// the outbox show here.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

#include "common/dds/domain.h"
#include "common/dds/participant.h"
#include "operator_client/net/operator_node.h"
#include "robot_server/control/robot_controller.h"
#include "robot_server/node/robot_node.h"
#include "robot_server/testpattern/test_pattern.h"

namespace mostar {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

std::unique_ptr<dds::Participant> MakeParticipant(const std::string& name) {
  dds::ParticipantOptions options;
  options.domain_id = dds::PerProcessDomainId();
  options.name = name;
  std::string error;
  auto participant = dds::Participant::Create(options, &error);
  EXPECT_NE(participant, nullptr) << error;
  return participant;
}

// Polls `done` every 10 ms for up to `timeout`.
template <typename F>
bool WaitFor(F done, Duration timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (!done()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(milliseconds(10));
  }
  return true;
}

TEST(RobotControlOverDdsTest, AnOperatorTakesTheLeaseAndDrivesWhileScansFlow) {
  const Clock* clock = &SystemClock::Instance();
  testpattern::KinematicRobot robot({}, clock);  // motors and encoders
  testpattern::TestPatternLaser laser(&robot, 40.0, clock);

  auto robot_participant = MakeParticipant("robot");
  auto operator_participant = MakeParticipant("operator");
  ASSERT_TRUE(robot_participant && operator_participant);
  std::atomic<server::RobotController*> controller_ptr{nullptr};
  server::RobotNode::Callbacks callbacks;
  callbacks.on_command = [&](const VelocityCommand& c) {
    if (auto* controller = controller_ptr.load()) controller->OnCommand(c);
  };
  callbacks.on_control_request = [&](const ControlRequest& r) {
    if (auto* controller = controller_ptr.load()) controller->OnControlRequest(r);
  };
  std::string error;
  auto node = server::RobotNode::Create(robot_participant.get(), {{"pilot", /*pilot=*/true}},
                                        callbacks, clock, &error);
  ASSERT_NE(node, nullptr) << error;

  server::RobotControllerOptions options;
  options.roles.Set("pilot", {drive::Role::kPilot, 10});
  options.odometry.counter_bits = 16;
  server::RobotControllerDevices devices;
  devices.motors = &robot;
  devices.laser = &laser;
  server::RobotController controller(options, devices, node.get(), clock);
  controller_ptr = &controller;
  ASSERT_TRUE(controller.Start(&error)) << error;
  std::atomic<bool> stop{false};
  std::thread control_loop([&] {
    while (!stop) {
      controller.Step(clock->SteadyNow());
      std::this_thread::sleep_for(milliseconds(20));
    }
  });

  std::mutex mutex;
  std::string holder;
  double odometry_x_m = 0;
  std::atomic<int> scans{0};
  std::atomic<int> healths{0};
  client::OperatorNode::Callbacks operator_callbacks;
  operator_callbacks.on_lease = [&](const ControlLease& lease) {
    std::lock_guard<std::mutex> lock(mutex);
    holder = lease.holder_id;
  };
  operator_callbacks.on_odometry = [&](const Odometry& odometry) {
    std::lock_guard<std::mutex> lock(mutex);
    odometry_x_m = odometry.pose.x_m;
  };
  operator_callbacks.on_scan = [&](const LaserScan&) { ++scans; };
  operator_callbacks.on_health = [&](const RobotHealth&) { ++healths; };
  client::OperatorNode::Options operator_options;
  operator_options.client_id = "pilot";
  operator_options.pilot = true;
  auto pilot = client::OperatorNode::Create(operator_participant.get(), operator_options,
                                            operator_callbacks, &error);
  ASSERT_NE(pilot, nullptr) << error;

  auto holds = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    return holder == "pilot";
  };
  EXPECT_TRUE(WaitFor(
      [&] {
        ControlRequest request;
        request.stamp = clock->Now();
        request.sender_id = "pilot";
        pilot->SendControlRequest(request);
        std::this_thread::sleep_for(milliseconds(100));
        return holds();
      },
      seconds(20)))
      << "the lease never came";
  uint64_t sequence = 0;
  auto send = [&](bool enable, double v) {
    VelocityCommand command;
    command.stamp = clock->Now();
    command.sequence = ++sequence;
    command.sender_id = "pilot";
    command.enable = enable;
    command.linear_mps = v;
    pilot->SendCommand(command);
  };
  for (int i = 0; i < 10; ++i) {  // deadman up: arms
    send(false, 0);
    std::this_thread::sleep_for(milliseconds(20));
  }
  const bool drove = WaitFor(
      [&] {
        send(true, 0.3);
        std::this_thread::sleep_for(milliseconds(20));
        std::lock_guard<std::mutex> lock(mutex);
        return odometry_x_m > 0.2;
      },
      seconds(20));
  stop = true;
  control_loop.join();
  controller.Stop();
  controller_ptr = nullptr;
  EXPECT_TRUE(drove) << "odometry x " << odometry_x_m;
  EXPECT_GT(robot.TruePose().x_m, 0.2);
  EXPECT_GT(scans.load(), 10);
  EXPECT_GT(healths.load(), 0);
  EXPECT_EQ(controller.governor().status().counters.rejected_not_holder, 0u);
  EXPECT_GT(controller.governor().status().counters.accepted, 10u);
  EXPECT_EQ(node->outbox_dropped(), 0u);
  node.reset();
}

}  // namespace
}  // namespace mostar
