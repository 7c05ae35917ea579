#include "operator_client/ui/command_sender.h"

#include <gtest/gtest.h>

#include <vector>

#include "common/time/fake_clock.h"

namespace mostar::ui {
namespace {

struct Recorder {
  std::vector<VelocityCommand> commands;
  std::vector<ClockProbe> pings;
  std::vector<ControlRequest> requests;
  std::vector<EmergencyStop> stops;
  CommandSinks Sinks() {
    CommandSinks s;
    s.command = [this](const VelocityCommand& c) {
      commands.push_back(c);
      return true;
    };
    s.ping = [this](const ClockProbe& p) {
      pings.push_back(p);
      return true;
    };
    s.control = [this](const ControlRequest& r) {
      requests.push_back(r);
      return true;
    };
    s.estop = [this](const EmergencyStop& e) {
      stops.push_back(e);
      return true;
    };
    return s;
  }
};

TEST(CommandSenderTest, SequenceIncreasesAndReleaseSendsDisabledZero) {
  FakeClock clock;
  Recorder rec;
  CommandSender sender({"pilot-a", true, 10}, rec.Sinks(), &clock);
  sender.SetDrive({0.4, 0.2, true});
  sender.Tick();
  clock.Advance(std::chrono::milliseconds(50));
  sender.SetDrive({0.9, 0.9, false});  // released: values must not leak through
  sender.Tick();
  ASSERT_EQ(rec.commands.size(), 2u);
  EXPECT_EQ(rec.commands[0].sequence + 1, rec.commands[1].sequence);
  EXPECT_TRUE(rec.commands[0].enable);
  EXPECT_DOUBLE_EQ(rec.commands[0].linear_mps, 0.4);
  EXPECT_FALSE(rec.commands[1].enable);
  EXPECT_EQ(rec.commands[1].linear_mps, 0);
  EXPECT_EQ(rec.commands[1].angular_radps, 0);
  EXPECT_EQ(rec.commands[1].sender_id, "pilot-a");
  EXPECT_EQ(rec.commands[1].stamp, clock.Now());
  EXPECT_EQ(sender.commands_sent(), 2u);
}

TEST(CommandSenderTest, ObserverSendsNoCommandsButPings) {
  FakeClock clock;
  Recorder rec;
  CommandSender sender({"observer", false, 0}, rec.Sinks(), &clock);
  sender.SetDrive({0.4, 0, true});
  for (int i = 0; i < 30; ++i) {
    sender.Tick();
    clock.Advance(std::chrono::milliseconds(50));
  }
  EXPECT_TRUE(rec.commands.empty());
  EXPECT_EQ(rec.pings.size(), 2u);  // at t = 0 and t = 1 s
  EXPECT_EQ(rec.pings[1].sequence, 2u);
}

TEST(CommandSenderTest, InactivePilotWritesNoCommands) {
  FakeClock clock;
  Recorder rec;
  CommandSender sender({"pilot-a", true, 10}, rec.Sinks(), &clock);
  sender.SetActive(false);
  sender.SetDrive({0.4, 0, true});
  sender.Tick();
  EXPECT_TRUE(rec.commands.empty());
  sender.SetActive(true);
  sender.Tick();
  ASSERT_EQ(rec.commands.size(), 1u);
  EXPECT_EQ(rec.commands[0].sequence, 1u);
}

TEST(CommandSenderTest, ControlRequestsAreSentOnceAndTheEstopAtOnce) {
  FakeClock clock;
  Recorder rec;
  CommandSender sender({"pilot-b", true, 20}, rec.Sinks(), &clock);
  sender.RequestControl(true);
  sender.SendEmergencyStop(true);
  sender.Tick();
  sender.Tick();
  ASSERT_EQ(rec.requests.size(), 1u);
  EXPECT_TRUE(rec.requests[0].take);
  EXPECT_EQ(rec.requests[0].strength, 20);
  ASSERT_EQ(rec.stops.size(), 1u);
  EXPECT_TRUE(rec.stops[0].engage);
}

TEST(CommandSenderTest, AnEngagedEstopIsResentUntilTheRobotReportsIt) {
  FakeClock clock;
  Recorder rec;
  std::optional<ReportedEstop> reported;
  CommandSinks sinks = rec.Sinks();
  sinks.robot_estop = [&] { return reported; };
  CommandSender sender({"observer", false, 0}, sinks, &clock);
  // The robot reports itself released (its report arrives every half second).
  reported = ReportedEstop{false, clock.SteadyNow()};
  sender.SendEmergencyStop(true);
  for (int i = 0; i < 20; ++i) {  // one second of cycles
    sender.Tick();
    clock.Advance(std::chrono::milliseconds(50));
    if (i % 10 == 9) reported = ReportedEstop{false, clock.SteadyNow()};
  }
  EXPECT_EQ(rec.stops.size(), 4u);  // at 0, 250, 500 and 750 ms
  for (const EmergencyStop& stop : rec.stops) {
    EXPECT_TRUE(stop.engage);
    EXPECT_EQ(stop.sender_id, "observer");
  }
  EXPECT_EQ(sender.pending_estop(), std::optional<bool>(true));
  reported = ReportedEstop{true, clock.SteadyNow()};
  for (int i = 0; i < 40; ++i) {
    sender.Tick();
    clock.Advance(std::chrono::milliseconds(50));
  }
  EXPECT_EQ(rec.stops.size(), 4u) << "confirmed: no more re-sends";
  EXPECT_FALSE(sender.pending_estop().has_value());
  EXPECT_EQ(sender.estop_stats().confirmed, 1u);
}

}  // namespace
}  // namespace mostar::ui
