#include "robot_server/drive/safety_governor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "common/time/fake_clock.h"

namespace mostar::drive {
namespace {

using std::chrono::milliseconds;

constexpr Duration kCycle = milliseconds(20);
constexpr float kInfRange = std::numeric_limits<float>::infinity();
constexpr float kErrorRange = std::numeric_limits<float>::quiet_NaN();  // an LMS200 error code

// An LMS200-like scan (-90..+90 deg, 1 deg) of the given points (x, y) in the laser frame;
// other beams see nothing.
LaserScan ScanOf(Time stamp, const std::vector<std::pair<double, double>>& points) {
  LaserScan scan;
  scan.stamp = stamp;
  scan.angle_min_rad = static_cast<float>(-M_PI / 2);
  scan.angle_increment_rad = static_cast<float>(M_PI / 180);
  scan.range_min_m = 0.05f;
  scan.range_max_m = 30.f;
  scan.ranges_m.assign(181, kInfRange);
  for (const auto& [x, y] : points) {
    const long i = std::lround((std::atan2(y, x) + M_PI / 2) / (M_PI / 180));
    const float r = static_cast<float>(std::hypot(x, y));
    scan.ranges_m[static_cast<size_t>(i)] = std::min(scan.ranges_m[static_cast<size_t>(i)], r);
  }
  return scan;
}

// A wall across the path at x = `x_m`, from y = -2 to 2 m.
LaserScan WallAt(Time stamp, double x_m) {
  std::vector<std::pair<double, double>> points;
  for (double y = -2.0; y <= 2.0; y += 0.01) points.emplace_back(x_m, y);
  return ScanOf(stamp, points);
}

// A clear scan whose beams at the given angles (degrees, 0 ahead, CCW) carry `range`.
LaserScan ClearWithBeams(Time stamp, const std::vector<int>& angles_deg, float range) {
  LaserScan scan = ScanOf(stamp, {});
  for (const int a : angles_deg) scan.ranges_m[static_cast<size_t>(a + 90)] = range;
  return scan;
}

uint64_t CounterOf(const DeviceHealth& health, const std::string& name) {
  for (const auto& [counter, value] : health.counters) {
    if (counter == name) return value;
  }
  ADD_FAILURE() << "no counter " << name;
  return 0;
}

class SafetyGovernorTest : public ::testing::Test {
 protected:
  SafetyGovernorTest() { governor_.SetLeaseHolder("alice"); }

  // A command from `sender` stamped now on the sender's clock (sender = robot - offset).
  VelocityCommand Command(double v, double w, bool enable, const std::string& sender = "alice") {
    VelocityCommand c;
    c.stamp = clock_.Now() - sender_offset_;
    c.sequence = ++sequence_;
    c.sender_id = sender;
    c.linear_mps = v;
    c.angular_radps = w;
    c.enable = enable;
    return c;
  }
  CommandVerdict Send(double v, double w, bool enable = true) {
    return governor_.HandleCommand(Command(v, w, enable), known_offset_);
  }
  void Arm() {
    ASSERT_EQ(Send(0, 0, false), CommandVerdict::kAccepted);
    ASSERT_EQ(Send(0, 0, true), CommandVerdict::kAccepted);
  }
  // One control cycle: time passes, a clear scan arrives, the governor decides.
  GovernorOutput Cycle(bool with_clear_scan = true) {
    clock_.Advance(kCycle);
    if (with_clear_scan) governor_.SetLaserScan(ScanOf(clock_.Now(), {}));
    return governor_.Update();
  }
  // Drives with the pilot sending (v, w) every cycle for `cycles`; returns the last output.
  GovernorOutput Drive(double v, double w, int cycles, const LaserScan* scan = nullptr) {
    GovernorOutput out;
    for (int i = 0; i < cycles; ++i) {
      Send(v, w);
      clock_.Advance(kCycle);
      if (scan) {
        LaserScan fresh = *scan;
        fresh.stamp = clock_.Now();
        governor_.SetLaserScan(fresh);
      } else {
        governor_.SetLaserScan(ScanOf(clock_.Now(), {}));
      }
      out = governor_.Update();
    }
    return out;
  }

  FakeClock clock_;
  SafetyOptions options_;
  SafetyGovernor governor_{clock_, options_};
  uint64_t sequence_ = 0;
  Duration sender_offset_{0};
  std::optional<Duration> known_offset_ = Duration::zero();
};

TEST_F(SafetyGovernorTest, OptionsAreValidAndValidationNamesTheField) {
  std::string error;
  EXPECT_TRUE(options_.IsValid(&error)) << error;
  SafetyOptions bad;
  bad.slow_distance_m = 0.1;
  EXPECT_FALSE(bad.IsValid(&error));
  EXPECT_NE(error.find("slow_distance_m"), std::string::npos);
}

TEST_F(SafetyGovernorTest, DoesNotMoveUntilArmed) {
  EXPECT_EQ(Drive(0.5, 0, 10).linear_mps, 0.0);
  EXPECT_EQ(governor_.status().state, WatchdogState::kIdle);
  Arm();
  const GovernorOutput out = Drive(0.5, 0, 10);
  EXPECT_GT(out.linear_mps, 0.0);
  EXPECT_EQ(out.state, WatchdogState::kDriving);
}

TEST_F(SafetyGovernorTest, RampsUpAtTheAccelerationLimitAndClampsVelocity) {
  Arm();
  Cycle();  // first cycle has no previous one: no step
  GovernorOutput out = Drive(5.0, 9.0, 10);
  EXPECT_NEAR(out.linear_mps, 10 * 0.02 * options_.max_linear_accel_mps2, 1e-9);
  EXPECT_NEAR(out.angular_radps, 10 * 0.02 * options_.max_angular_accel_radps2, 1e-9);
  out = Drive(5.0, 9.0, 200);
  EXPECT_NEAR(out.linear_mps, options_.max_linear_mps, 1e-9);
  out = Drive(-5.0, 0, 200);
  EXPECT_NEAR(out.linear_mps, -options_.max_reverse_mps, 1e-9);
}

TEST_F(SafetyGovernorTest, DeadmanRampsToZeroWithinPeriodPlusOneCycle) {
  Arm();
  Cycle();
  ASSERT_NEAR(Drive(0.5, 0, 100).linear_mps, 0.5, 1e-9);
  Send(0.5, 0);
  // The pilot goes silent. Until the deadman period has passed, the robot keeps going.
  const SteadyTime silent_since = clock_.SteadyNow();
  GovernorOutput out;
  while (clock_.SteadyNow() - silent_since + kCycle <= options_.deadman_period) {
    out = Cycle();
    EXPECT_NEAR(out.linear_mps, 0.5, 1e-9);
  }
  // Within one more cycle past the period, the ramp down has started.
  out = Cycle();
  EXPECT_NEAR(out.linear_mps, 0.5 - options_.max_linear_decel_mps2 * ToSeconds(kCycle), 1e-9);
  EXPECT_EQ(out.state, WatchdogState::kStopping);
  EXPECT_EQ(governor_.status().counters.deadman_expiries, 1u);
  // And zero is reached after v / decel (+ one cycle).
  const Duration ramp = FromSeconds(0.5 / options_.max_linear_decel_mps2);
  while (clock_.SteadyNow() - silent_since <= options_.deadman_period + ramp + kCycle) {
    out = Cycle();
  }
  EXPECT_EQ(out.linear_mps, 0.0);
  EXPECT_EQ(out.state, WatchdogState::kWaitRearm);
}

TEST_F(SafetyGovernorTest, PilotMustRearmAfterALinkLoss) {
  Arm();
  Drive(0.3, 0, 20);
  for (int i = 0; i < 60; ++i) Cycle();  // 1.2 s of silence
  ASSERT_EQ(governor_.status().state, WatchdogState::kWaitRearm);
  // Commands come back with enable=true: not enough.
  GovernorOutput out = Drive(0.3, 0, 20);
  EXPECT_EQ(out.linear_mps, 0.0);
  EXPECT_EQ(out.state, WatchdogState::kWaitRearm);
  Arm();
  out = Drive(0.3, 0, 20);
  EXPECT_GT(out.linear_mps, 0.0);
  EXPECT_EQ(out.state, WatchdogState::kDriving);
}

TEST_F(SafetyGovernorTest, LinkLossEventStopsAtOnceAndRequiresRearm) {
  Arm();
  Drive(0.3, 0, 20);
  governor_.OnLinkLost("bob");  // not the holder: ignored
  EXPECT_EQ(governor_.status().counters.link_losses, 0u);
  governor_.OnLinkLost("alice");
  EXPECT_EQ(governor_.status().counters.link_losses, 1u);
  const GovernorOutput out = Drive(0.3, 0, 100);
  EXPECT_EQ(out.linear_mps, 0.0);
  EXPECT_EQ(out.state, WatchdogState::kWaitRearm);
}

TEST_F(SafetyGovernorTest, IgnoresStaleCommandsWithAKnownOffset) {
  sender_offset_ = std::chrono::seconds(5);  // the sender's clock is 5 s behind
  known_offset_ = sender_offset_;
  Arm();
  VelocityCommand old = Command(0.5, 0, true);
  old.stamp -= milliseconds(400);
  EXPECT_EQ(governor_.HandleCommand(old, known_offset_), CommandVerdict::kRejectedStale);
  VelocityCommand future = Command(0.5, 0, true);
  future.stamp += milliseconds(400);
  EXPECT_EQ(governor_.HandleCommand(future, known_offset_), CommandVerdict::kRejectedStale);
  EXPECT_EQ(Send(0.5, 0), CommandVerdict::kAccepted);
  EXPECT_EQ(governor_.status().counters.rejected_stale, 2u);
}

TEST_F(SafetyGovernorTest, IgnoresAStaleBurstAfterAnOutageWithoutAnOffset) {
  sender_offset_ = std::chrono::seconds(1000);  // unrelated clocks
  known_offset_.reset();
  const Duration network_delay = milliseconds(15);
  // Commands are created, then delivered `network_delay` later.
  auto deliver = [&](const VelocityCommand& c) { return governor_.HandleCommand(c); };
  std::vector<VelocityCommand> queued;
  for (int i = 0; i < 20; ++i) {
    const VelocityCommand c = Command(0.2, 0, i > 0);
    clock_.Advance(network_delay);
    EXPECT_EQ(deliver(c), CommandVerdict::kAccepted);
    clock_.Advance(milliseconds(35));
    governor_.Update();
  }
  // Outage: 2 s of commands are queued by the transport, then flushed at once.
  for (int i = 0; i < 40; ++i) {
    queued.push_back(Command(0.2, 0, true));
    clock_.Advance(milliseconds(50));
  }
  int accepted = 0;
  for (const VelocityCommand& c : queued) accepted += deliver(c) == CommandVerdict::kAccepted;
  // Only the commands younger than max_command_age (300 ms) pass: the last 6 of 50 ms each.
  EXPECT_LE(accepted, 7);
  EXPECT_GE(governor_.status().counters.rejected_stale, 33u);
}

TEST_F(SafetyGovernorTest, IgnoresOutOfOrderCommands) {
  Arm();
  VelocityCommand c = Command(0.2, 0, true);
  c.sequence = 50;
  EXPECT_EQ(governor_.HandleCommand(c, known_offset_), CommandVerdict::kAccepted);
  c.sequence = 49;
  EXPECT_EQ(governor_.HandleCommand(c, known_offset_), CommandVerdict::kRejectedOutOfOrder);
  c.sequence = 50;
  EXPECT_EQ(governor_.HandleCommand(c, known_offset_), CommandVerdict::kRejectedOutOfOrder);
  EXPECT_EQ(governor_.status().counters.rejected_out_of_order, 2u);
  EXPECT_EQ(governor_.status().last_command_sequence, 50u);
}

TEST_F(SafetyGovernorTest, AcceptsASenderRestartWithANewerStamp) {
  VelocityCommand c = Command(0, 0, false);
  c.sequence = 1000;
  governor_.HandleCommand(c, known_offset_);
  clock_.Advance(std::chrono::seconds(1));
  VelocityCommand restarted = Command(0, 0, false);
  restarted.sequence = 1;
  EXPECT_EQ(governor_.HandleCommand(restarted, known_offset_), CommandVerdict::kAccepted);
  EXPECT_EQ(governor_.status().counters.sender_restarts, 1u);
}

TEST_F(SafetyGovernorTest, IgnoresCommandsFromAnyoneButTheHolder) {
  Arm();
  EXPECT_EQ(governor_.HandleCommand(Command(0.5, 0, true, "bob"), known_offset_),
            CommandVerdict::kRejectedNotHolder);
  EXPECT_EQ(governor_.status().counters.rejected_not_holder, 1u);
  governor_.SetLeaseHolder("");
  EXPECT_EQ(Send(0.5, 0), CommandVerdict::kRejectedNotHolder);
}

TEST_F(SafetyGovernorTest, LeaseChangeDisarms) {
  Arm();
  Drive(0.3, 0, 20);
  governor_.SetLeaseHolder("bob");
  GovernorOutput out;
  for (int i = 0; i < 50; ++i) {
    governor_.HandleCommand(Command(0.3, 0, true, "bob"), known_offset_);
    out = Cycle();
  }
  EXPECT_EQ(out.linear_mps, 0.0);
  EXPECT_FALSE(governor_.status().armed);
}

TEST_F(SafetyGovernorTest, RejectsNonFiniteVelocities) {
  Arm();
  EXPECT_EQ(Send(std::nan(""), 0), CommandVerdict::kRejectedInvalid);
  EXPECT_EQ(Send(0, std::numeric_limits<double>::infinity()), CommandVerdict::kRejectedInvalid);
  EXPECT_EQ(governor_.status().counters.rejected_invalid, 2u);
}

TEST_F(SafetyGovernorTest, EstopLatchesZeroUntilReleasedAndRearmed) {
  Arm();
  ASSERT_GT(Drive(0.4, 0.2, 30).linear_mps, 0.0);
  EmergencyStop estop;
  estop.sender_id = "olga";
  EXPECT_FALSE(governor_.HandleEmergencyStop(estop, /*authorised=*/false));
  EXPECT_EQ(governor_.status().counters.estop_refused, 1u);
  EXPECT_TRUE(governor_.HandleEmergencyStop(estop, true));
  GovernorOutput out = Cycle();
  EXPECT_EQ(out.linear_mps, 0.0);  // no ramp
  EXPECT_EQ(out.angular_radps, 0.0);
  EXPECT_EQ(out.state, WatchdogState::kEstop);
  Arm();  // re-arming during an e-stop does nothing
  out = Drive(0.4, 0, 30);
  EXPECT_EQ(out.linear_mps, 0.0);
  EXPECT_EQ(governor_.status().estop_engaged_by, "olga");
  estop.engage = false;
  EXPECT_TRUE(governor_.HandleEmergencyStop(estop, true));
  out = Drive(0.4, 0, 10);
  EXPECT_EQ(out.linear_mps, 0.0);
  EXPECT_EQ(out.state, WatchdogState::kWaitRearm);
  Arm();
  EXPECT_GT(Drive(0.4, 0, 10).linear_mps, 0.0);
  EXPECT_EQ(governor_.status().counters.estops, 1u);
}

TEST_F(SafetyGovernorTest, RestoredLatchHoldsUntilReleasedAndNamesItsReason) {
  governor_.RestoreEstop("", "the previous run did not stop cleanly");
  Arm();
  GovernorOutput out = Drive(0.4, 0, 10);
  EXPECT_EQ(out.linear_mps, 0.0);
  EXPECT_EQ(out.state, WatchdogState::kEstop);
  const DeviceHealth health = governor_.Health();
  EXPECT_EQ(health.state, DeviceState::kWarn);
  EXPECT_NE(health.message.find("e-stop latched: the previous run did not stop cleanly"),
            std::string::npos)
      << health.message;
  RobotHealth robot;
  governor_.FillRobotHealth(&robot);
  EXPECT_TRUE(robot.estop_engaged);
  EmergencyStop release;
  release.sender_id = "alice";
  release.engage = false;
  EXPECT_TRUE(governor_.HandleEmergencyStop(release, true));
  EXPECT_EQ(governor_.status().estop_reason, "");
  EXPECT_EQ(Drive(0.4, 0, 10).linear_mps, 0.0) << "a release needs a re-arm";
  Arm();
  EXPECT_GT(Drive(0.4, 0, 10).linear_mps, 0.0);
}

TEST_F(SafetyGovernorTest, SlowsDownNearAnObstacleAhead) {
  Arm();
  // Bumper at 0.2 m; wall 0.75 m ahead of it: halfway between stop (0.3) and slow (1.2).
  const LaserScan wall = WallAt(clock_.Now(), 0.95);
  const GovernorOutput out = Drive(0.6, 0, 200, &wall);
  // (Beams are 1 degree apart: the nearest wall point seen is within a few mm of the truth.)
  EXPECT_NEAR(out.free_distance_m, 0.75, 0.01);
  EXPECT_NEAR(out.forward_limit_mps, 0.3, 0.01);
  EXPECT_NEAR(out.linear_mps, out.forward_limit_mps, 1e-9);
}

TEST_F(SafetyGovernorTest, StopsAtTheStopDistanceButAllowsReverseAndRotation) {
  Arm();
  const LaserScan wall = WallAt(clock_.Now(), 0.45);  // 0.25 m free: inside stop distance
  GovernorOutput out = Drive(0.6, 0, 100, &wall);
  EXPECT_EQ(out.linear_mps, 0.0);
  EXPECT_EQ(out.forward_limit_mps, 0.0);
  out = Drive(-0.15, 0, 100, &wall);
  EXPECT_NEAR(out.linear_mps, -0.15, 1e-9);
  out = Drive(0.0, 0.8, 100, &wall);
  EXPECT_NEAR(out.angular_radps, 0.8, 1e-9);
  // Forward and turning: forward speed stays zero, the turn is allowed.
  out = Drive(0.5, 0.8, 100, &wall);
  EXPECT_EQ(out.linear_mps, 0.0);
  EXPECT_NEAR(out.angular_radps, 0.8, 1e-9);
}

TEST_F(SafetyGovernorTest, ObstaclesBesideTheCorridorDoNotSlowStraightMotion) {
  Arm();
  // 0.6 m wide robot + 5 cm margins: corridor |y| <= 0.35 m.
  const LaserScan poles = ScanOf(clock_.Now(), {{0.6, 0.5}, {0.8, -0.45}, {3.0, 0.36}});
  const GovernorOutput out = Drive(0.6, 0, 100, &poles);
  EXPECT_EQ(out.forward_limit_mps, options_.max_linear_mps);
  EXPECT_NEAR(out.linear_mps, 0.6, 1e-9);
}

TEST_F(SafetyGovernorTest, TurningPathSeesAnObstacleOnTheArc) {
  Arm();
  // A pole at (0.6, 0.6): outside the straight corridor, on the arc of radius 0.6 m to the left.
  const LaserScan pole = ScanOf(clock_.Now(), {{0.6, 0.6}});
  GovernorOutput out = Drive(0.3, 0.0, 5, &pole);
  EXPECT_EQ(out.forward_limit_mps, options_.max_linear_mps);
  out = Drive(0.3, 0.5, 5, &pole);
  // Quarter circle of 0.6 m radius, minus the bumper: 0.742 m free.
  EXPECT_NEAR(out.free_distance_m, M_PI / 2 * 0.6 - 0.2, 0.02);
  EXPECT_LT(out.forward_limit_mps, 0.6 * 0.5 + 0.05);
  // Turning right, away from it: clear.
  out = Drive(0.3, -0.5, 5, &pole);
  EXPECT_EQ(out.forward_limit_mps, options_.max_linear_mps);
}

TEST_F(SafetyGovernorTest, MissingOrStaleScanCapsForwardSpeed) {
  Arm();
  GovernorOutput out;
  for (int i = 0; i < 200; ++i) {
    Send(0.6, 0);
    out = Cycle(/*with_clear_scan=*/false);
  }
  EXPECT_FALSE(out.scan_fresh);
  EXPECT_NEAR(out.linear_mps, options_.unknown_scan_speed_factor * options_.max_linear_mps, 1e-9);
  governor_.SetLaserScan(ScanOf(clock_.Now() - milliseconds(600), {}));
  Send(0.6, 0);
  clock_.Advance(kCycle);
  out = governor_.Update();
  EXPECT_FALSE(out.scan_fresh);
  EXPECT_EQ(governor_.Health().state, DeviceState::kWarn);
}

TEST_F(SafetyGovernorTest, ErrorCodedBeamsInThePathCapForwardSpeedLikeAMissingScan) {
  Arm();
  const double capped = options_.unknown_scan_speed_factor * options_.max_linear_mps;
  // A few dazzled beams straight ahead: whatever lies behind them is unknown.
  const LaserScan dazzled = ClearWithBeams(clock_.Now(), {-2, -1, 0, 1, 2}, kErrorRange);
  GovernorOutput out = Drive(0.6, 0, 100, &dazzled);
  EXPECT_TRUE(out.scan_fresh);
  EXPECT_EQ(out.unknown_beams_in_path, 5);
  EXPECT_EQ(out.free_distance_m, std::numeric_limits<double>::infinity());  // no obstacle seen
  EXPECT_NEAR(out.forward_limit_mps, capped, 1e-9);
  EXPECT_NEAR(out.linear_mps, capped, 1e-9);
  DeviceHealth health = governor_.Health();
  EXPECT_EQ(health.state, DeviceState::kWarn);
  EXPECT_NE(health.message.find("5 unknown beams (laser or sonar) in the path"), std::string::npos)
      << health.message;
  EXPECT_EQ(CounterOf(health, "unknown_path_cycles"), 100u);
  EXPECT_EQ(CounterOf(health, "unknown_beams"), 500u);
  // A laser blinded on every beam caps too; it does not stop the robot.
  LaserScan blind = ScanOf(clock_.Now(), {});
  blind.ranges_m.assign(blind.ranges_m.size(), kErrorRange);
  out = Drive(0.6, 0, 50, &blind);
  EXPECT_NEAR(out.linear_mps, capped, 1e-9);
  // Other values that are no range count as unknown space too: -Inf, 0, below range_min_m.
  for (const float odd : {-kInfRange, 0.f, 0.01f}) {
    const LaserScan scan = ClearWithBeams(clock_.Now(), {0}, odd);
    EXPECT_NEAR(Drive(0.6, 0, 5, &scan).forward_limit_mps, capped, 1e-9) << odd;
  }
  // The same beams as "no echo" (+Inf) are free space: the speed comes back.
  const LaserScan no_echo = ClearWithBeams(clock_.Now(), {-2, -1, 0, 1, 2}, kInfRange);
  out = Drive(0.6, 0, 100, &no_echo);
  EXPECT_EQ(out.unknown_beams_in_path, 0);
  EXPECT_NEAR(out.linear_mps, 0.6, 1e-9);
  health = governor_.Health();
  EXPECT_EQ(health.state, DeviceState::kOk) << health.message;
}

TEST_F(SafetyGovernorTest, ErrorCodedBeamsOutsideThePathDoNotSlow) {
  Arm();
  // 0.6 m wide robot + 5 cm margins, bumper 0.2 m ahead: a beam wider than atan(0.35 / 0.2)
  // = 60 deg leaves the corridor before the bumper line.
  const LaserScan sides = ClearWithBeams(clock_.Now(), {-90, -75, -62, 62, 75, 90}, kErrorRange);
  GovernorOutput out = Drive(0.6, 0, 100, &sides);
  EXPECT_EQ(out.unknown_beams_in_path, 0);
  EXPECT_NEAR(out.linear_mps, 0.6, 1e-9);
  EXPECT_EQ(governor_.Health().state, DeviceState::kOk);
  EXPECT_EQ(CounterOf(governor_.Health(), "unknown_path_cycles"), 0u);
  // The boundary: a beam at 58 deg still crosses the corridor ahead of the bumper.
  const LaserScan edge = ClearWithBeams(clock_.Now(), {58}, kErrorRange);
  EXPECT_EQ(Drive(0.6, 0, 5, &edge).unknown_beams_in_path, 1);
}

TEST_F(SafetyGovernorTest, ErrorCodedBeamOnTheArcCapsOnlyTheTurnThatCrossesIt) {
  Arm();
  const double capped = options_.unknown_scan_speed_factor * options_.max_linear_mps;
  // A dazzled beam at +65 deg: outside the straight corridor, across the arc of radius 0.6 m
  // to the left.
  const LaserScan beam = ClearWithBeams(clock_.Now(), {65}, kErrorRange);
  GovernorOutput out = Drive(0.3, 0.0, 50, &beam);
  EXPECT_NEAR(out.linear_mps, 0.3, 1e-9);
  out = Drive(0.3, 0.5, 50, &beam);
  EXPECT_EQ(out.unknown_beams_in_path, 1);
  EXPECT_NEAR(out.linear_mps, capped, 1e-9);
  out = Drive(0.3, -0.5, 50, &beam);  // turning right, away from it
  EXPECT_EQ(out.unknown_beams_in_path, 0);
  EXPECT_NEAR(out.linear_mps, 0.3, 1e-9);
  // Reverse and rotation in place are not limited by the front laser (G13).
  const LaserScan ahead = ClearWithBeams(clock_.Now(), {0}, kErrorRange);
  out = Drive(-0.15, 0, 100, &ahead);
  EXPECT_NEAR(out.linear_mps, -0.15, 1e-9);
  out = Drive(0, 0.8, 100, &ahead);
  EXPECT_NEAR(out.angular_radps, 0.8, 1e-9);
  EXPECT_EQ(out.unknown_beams_in_path, 0);
}

TEST_F(SafetyGovernorTest, HealthSummaryCarriesStateAndCounters) {
  Arm();
  Drive(0.2, 0, 5);
  governor_.HandleCommand(Command(0.5, 0, true, "bob"), known_offset_);
  const DeviceHealth health = governor_.Health();
  EXPECT_EQ(health.name, "drive_safety");
  EXPECT_EQ(health.state, DeviceState::kOk);
  EXPECT_NE(health.message.find("alice"), std::string::npos);
  bool found = false;
  for (const auto& [name, value] : health.counters) {
    if (name == "rejected_not_holder") {
      found = true;
      EXPECT_EQ(value, 1u);
    }
  }
  EXPECT_TRUE(found);
  RobotHealth robot;
  governor_.FillRobotHealth(&robot);
  EXPECT_EQ(robot.lease_holder, "alice");
  EXPECT_EQ(robot.watchdog_state, WatchdogState::kDriving);
  EXPECT_GE(robot.last_command_age_s, 0.f);
  EXPECT_EQ(robot.last_command_sequence, sequence_ - 1);
}

// A sonar reading `range_m` from a mount at (x, y) with axis `yaw_rad` (base frame), 55 deg cone.
SonarRanges SonarOf(Time stamp, double x_m, double y_m, double yaw_rad, float range_m) {
  SonarRange r;
  r.mount = SonarMount{"sonar_0", x_m, y_m, yaw_rad};
  r.stamp = stamp;
  r.range_m = range_m;
  r.min_range_m = 0.03f;
  r.max_range_m = 6.0f;
  r.field_of_view_rad = static_cast<float>(55 * M_PI / 180);
  SonarRanges ranges;
  ranges.ranges.push_back(r);
  return ranges;
}

// The laser sees nothing (a glass pane); the front sonar, 0.2 m ahead of the base origin on the
// bumper line, hears the pane. Its echo is an arc across the cone: the nearest point of the arc
// inside the corridor limits the speed, and a close pane stops the robot.
TEST_F(SafetyGovernorTest, SonarSeesTheGlassPaneTheLaserPasses) {
  Arm();
  GovernorOutput out;
  for (int i = 0; i < 50; ++i) {
    Send(0.6, 0);
    governor_.SetSonarRanges(SonarOf(clock_.Now(), 0.2, 0, 0, 1.0f));
    out = Cycle();
  }
  EXPECT_TRUE(out.sonar_fresh);
  // Corridor half width 0.35 m: the arc's points within it are at most 20.5 deg off the axis,
  // x = 0.2 + cos(20.5 deg) = 1.137 m, so 0.937 m ahead of the bumper.
  EXPECT_NEAR(out.free_distance_m, 0.937, 0.02);
  const double expected_limit = (0.937 - 0.30) / (1.20 - 0.30) * 0.6;
  EXPECT_NEAR(out.forward_limit_mps, expected_limit, 0.02);
  EXPECT_LE(out.linear_mps, expected_limit + 0.02);
  for (int i = 0; i < 100; ++i) {
    Send(0.6, 0);
    governor_.SetSonarRanges(SonarOf(clock_.Now(), 0.2, 0, 0, 0.3f));
    out = Cycle();
  }
  EXPECT_EQ(out.forward_limit_mps, 0.0);
  EXPECT_EQ(out.linear_mps, 0.0) << "stopped before the pane";
  // Reverse and rotation stay allowed.
  EXPECT_LT(Drive(-0.2, 0, 20).linear_mps, 0.0);
}

TEST_F(SafetyGovernorTest, SonarBesideTheCorridorDoesNotSlowStraightMotion) {
  Arm();
  GovernorOutput out;
  for (int i = 0; i < 100; ++i) {
    Send(0.6, 0);
    // The left sensor at (0, 0.3), facing left, hears a wall 0.5 m away: the arc lies at
    // y >= 0.3 + 0.5 cos(27.5 deg) = 0.74 m, outside the corridor.
    governor_.SetSonarRanges(SonarOf(clock_.Now(), 0, 0.3, M_PI / 2, 0.5f));
    out = Cycle();
  }
  EXPECT_EQ(out.forward_limit_mps, options_.max_linear_mps);
  EXPECT_NEAR(out.linear_mps, 0.6, 1e-9);
}

// A sonar cycle older than sonar_max_age is not used: its obstacle does not stop the robot for
// ever, but the belt, once heard, is unknown: forward speed is capped as for a missing scan.
TEST_F(SafetyGovernorTest, StaleSonarIsNotTrustedAndCapsForwardSpeed) {
  Arm();
  const double capped = options_.unknown_scan_speed_factor * options_.max_linear_mps;
  governor_.SetSonarRanges(SonarOf(clock_.Now(), 0.2, 0, 0, 0.3f));
  GovernorOutput out;
  for (int i = 0; i < 150; ++i) {  // 3 s without a new sonar cycle
    Send(0.6, 0);
    out = Cycle();
  }
  EXPECT_FALSE(out.sonar_fresh);
  EXPECT_NEAR(out.forward_limit_mps, capped, 1e-9);
  EXPECT_NEAR(out.linear_mps, capped, 1e-9) << "the stale obstacle is not used, speed capped";
  EXPECT_EQ(governor_.Health().state, DeviceState::kWarn);
  EXPECT_NE(governor_.Health().message.find("no fresh sonar"), std::string::npos);
  EXPECT_GT(CounterOf(governor_.Health(), "sonar_stale_cycles"), 0u);
  // Fresh again: the obstacle stops the robot.
  for (int i = 0; i < 50; ++i) {
    Send(0.6, 0);
    governor_.SetSonarRanges(SonarOf(clock_.Now(), 0.2, 0, 0, 0.3f));
    out = Cycle();
  }
  EXPECT_TRUE(out.sonar_fresh);
  EXPECT_EQ(out.linear_mps, 0.0);
}

TEST_F(SafetyGovernorTest, AnExpectedBeltThatNeverSpokeCapsForwardSpeed) {
  SafetyOptions options;
  options.sonar_expected = true;
  SafetyGovernor governor(clock_, options);
  governor.SetLeaseHolder("alice");
  governor.HandleCommand(Command(0, 0, false), known_offset_);
  GovernorOutput out;
  for (int i = 0; i < 100; ++i) {
    governor.HandleCommand(Command(0.6, 0, true), known_offset_);
    clock_.Advance(kCycle);
    governor.SetLaserScan(ScanOf(clock_.Now(), {}));
    out = governor.Update();
  }
  EXPECT_FALSE(out.sonar_fresh);
  EXPECT_NEAR(out.linear_mps, options.unknown_scan_speed_factor * options.max_linear_mps, 1e-9);
}

TEST_F(SafetyGovernorTest, AFailedSonarAheadCapsForwardSpeedLikeAnUnknownBeam) {
  Arm();
  GovernorOutput out;
  for (int i = 0; i < 100; ++i) {
    Send(0.6, 0);
    governor_.SetSonarRanges(
        SonarOf(clock_.Now(), 0.2, 0, 0, std::numeric_limits<float>::quiet_NaN()));
    out = Cycle();
  }
  EXPECT_GT(out.unknown_beams_in_path, 0);
  EXPECT_NEAR(out.linear_mps, options_.unknown_scan_speed_factor * options_.max_linear_mps, 1e-9);
  EXPECT_GT(CounterOf(governor_.Health(), "sonar_failed_readings"), 0u);
}

// A contact stops the robot in the same cycle (no ramp) and latches until the pilot re-arms,
// even after the segment is released; health names the segment.
TEST_F(SafetyGovernorTest, BumperContactStopsAtOnceAndLatchesUntilTheRearm) {
  Arm();
  governor_.SetBumpers(0, 16, true);
  GovernorOutput out = Drive(0.5, 0, 100);
  ASSERT_NEAR(out.linear_mps, 0.5, 1e-9);
  governor_.SetBumpers(1u << 1, 16, true);  // segment 1, 22.5 deg left of ahead
  Send(0.5, 0);
  out = Cycle();
  EXPECT_EQ(out.linear_mps, 0.0) << "no ramp";
  EXPECT_EQ(out.state, WatchdogState::kWaitRearm);
  SafetyStatus status = governor_.status();
  EXPECT_EQ(status.bumper_latched, 1u << 1);
  EXPECT_FALSE(status.armed);
  const DeviceHealth health = governor_.Health();
  EXPECT_EQ(health.state, DeviceState::kWarn);
  EXPECT_NE(health.message.find("bumper contact on segment 1 (23 deg)"), std::string::npos)
      << health.message;
  EXPECT_EQ(CounterOf(health, "bumper_contacts"), 1u);
  // Released, but still latched: commands with enable held do not move it.
  governor_.SetBumpers(0, 16, true);
  out = Drive(0.5, 0, 50);
  EXPECT_EQ(out.linear_mps, 0.0);
  EXPECT_EQ(governor_.status().bumper_latched, 1u << 1);
  EXPECT_EQ(out.state, WatchdogState::kWaitRearm);
  // The re-arm clears the latch.
  Arm();
  EXPECT_EQ(governor_.status().bumper_latched, 0u);
  out = Drive(0.5, 0, 100);
  EXPECT_NEAR(out.linear_mps, 0.5, 1e-9);
  EXPECT_EQ(out.state, WatchdogState::kDriving);
}

// After the re-arm a segment still pressed blocks linear motion towards it only, so that the
// pilot can back away from the obstacle or turn.
TEST_F(SafetyGovernorTest, ASegmentStillPressedAfterTheRearmBlocksMotionTowardsIt) {
  Arm();
  governor_.SetBumpers(1u << 0, 16, true);  // front
  Drive(0.5, 0, 5);
  EXPECT_EQ(governor_.status().bumper_latched, 1u);
  Arm();
  EXPECT_EQ(governor_.status().bumper_latched, 0u) << "re-armed";
  EXPECT_EQ(Drive(0.5, 0, 50).linear_mps, 0.0) << "not forward into the contact";
  EXPECT_GT(Drive(0, 0.5, 50).angular_radps, 0.0) << "rotation allowed";
  EXPECT_LT(Drive(-0.2, 0, 50).linear_mps, 0.0) << "backing away allowed";
  EXPECT_EQ(governor_.status().bumper_latched, 0u) << "a held contact does not latch again";
  // A rear contact blocks reverse and latches (a new contact).
  governor_.SetBumpers((1u << 0) | (1u << 8), 16, true);
  EXPECT_EQ(Drive(-0.2, 0, 5).linear_mps, 0.0);
  EXPECT_EQ(governor_.status().bumper_latched, 1u << 8);
}

TEST_F(SafetyGovernorTest, AnUnreadableBumperBeltStopsAndArmingWaitsUntilItReadsAgain) {
  Arm();
  GovernorOutput out = Drive(0.5, 0, 100);
  ASSERT_GT(out.linear_mps, 0.4);
  governor_.SetBumpers(0, 16, false, "gpiochip0: read failed");
  Send(0.5, 0);
  out = Cycle();
  EXPECT_EQ(out.linear_mps, 0.0);
  EXPECT_EQ(out.state, WatchdogState::kWaitRearm);
  EXPECT_NE(governor_.Health().message.find("bumpers unreadable (gpiochip0: read failed)"),
            std::string::npos)
      << governor_.Health().message;
  Arm();
  EXPECT_FALSE(governor_.status().armed) << "no arming while the belt is unknown";
  EXPECT_EQ(Drive(0.5, 0, 20).linear_mps, 0.0);
  governor_.SetBumpers(0, 16, true);
  Arm();
  EXPECT_TRUE(governor_.status().armed);
  EXPECT_GT(Drive(0.5, 0, 20).linear_mps, 0.0);
  EXPECT_EQ(CounterOf(governor_.Health(), "bumper_read_failures"), 1u);
}

TEST_F(SafetyGovernorTest, BumperSegmentListNamesSegmentsAndAngles) {
  EXPECT_EQ(BumperSegmentList(0, 16), "");
  EXPECT_EQ(BumperSegmentList((1u << 0) | (1u << 15), 16), "0 (0 deg), 15 (338 deg)");
  EXPECT_EQ(BumperSegmentList(1u << 2, 8), "2 (90 deg)");
}

}  // namespace
}  // namespace mostar::drive
