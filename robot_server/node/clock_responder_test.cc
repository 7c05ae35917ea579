#include "robot_server/node/clock_responder.h"

#include <gtest/gtest.h>

#include "common/time/fake_clock.h"

namespace mostar::server {
namespace {

using std::chrono::milliseconds;

// A client whose clock is `client_minus_robot` ahead of the robot's, pinging with a symmetric
// one-way delay of 5 ms.
class Pinger {
 public:
  Pinger(std::string id, Duration client_minus_robot)
      : id_(std::move(id)), offset_(client_minus_robot) {}
  // One ping through `responder` at robot time `clock.Now()`; advances the clock.
  void Ping(ClockResponder* responder, FakeClock* clock) {
    ClockProbe ping;
    ping.sender_id = id_;
    ping.sequence = ++sequence_;
    ping.t0 = clock->Now() + offset_;
    ping.t3 = last_t3_;
    clock->Advance(milliseconds(5));
    const ClockProbe pong = responder->Answer(id_, ping, clock->Now());
    clock->Advance(milliseconds(5));
    last_t3_ = clock->Now() + offset_;
    EXPECT_EQ(pong.sequence, ping.sequence);
    EXPECT_EQ(pong.sender_id, id_);
    clock->Advance(milliseconds(100));
  }

 private:
  std::string id_;
  Duration offset_;
  uint64_t sequence_ = 0;
  Time last_t3_;
};

TEST(ClockResponderTest, EstimatesEachClientsOffsetFromItsOwnPings) {
  FakeClock clock;
  ClockResponder responder(clock);
  Pinger alice("alice", milliseconds(250));
  Pinger bob("bob", milliseconds(-40));
  for (int i = 0; i < 5; ++i) {
    alice.Ping(&responder, &clock);
    bob.Ping(&responder, &clock);
  }
  ASSERT_TRUE(responder.RobotMinusClient("alice"));
  EXPECT_EQ(*responder.RobotMinusClient("alice"), milliseconds(-250));
  ASSERT_TRUE(responder.RobotMinusClient("bob"));
  EXPECT_EQ(*responder.RobotMinusClient("bob"), milliseconds(40));
  EXPECT_FALSE(responder.RobotMinusClient("carol"));
}

TEST(ClockResponderTest, ForgetResetsAClientsEstimate) {
  FakeClock clock;
  ClockResponder responder(clock);
  Pinger alice("alice", milliseconds(250));
  for (int i = 0; i < 5; ++i) alice.Ping(&responder, &clock);
  ASSERT_TRUE(responder.RobotMinusClient("alice"));
  responder.Forget("alice");
  EXPECT_FALSE(responder.RobotMinusClient("alice"));
  for (int i = 0; i < 5; ++i) alice.Ping(&responder, &clock);
  EXPECT_TRUE(responder.RobotMinusClient("alice"));
}

// Many ids (a flood of forged pings without DDS Security) cannot grow the table; the client
// heard from least recently goes first.
TEST(ClockResponderTest, TracksAtMostMaxClients) {
  FakeClock clock;
  ClockResponder responder(clock, /*max_clients=*/4);
  Pinger alice("alice", milliseconds(10));
  for (int i = 0; i < 4; ++i) alice.Ping(&responder, &clock);
  for (int n = 0; n < 1000; ++n) {
    Pinger flood("id" + std::to_string(n), milliseconds(0));
    flood.Ping(&responder, &clock);
    if (n % 3 == 0) alice.Ping(&responder, &clock);  // alice keeps pinging
  }
  EXPECT_EQ(responder.clients(), 4u);
  EXPECT_EQ(responder.evicted(), 997u);
  EXPECT_TRUE(responder.RobotMinusClient("alice"));
}

}  // namespace
}  // namespace mostar::server
