#include "operator_client/net/robot_state.h"

#include <gtest/gtest.h>

#include "common/time/fake_clock.h"

namespace mostar::client {
namespace {

LaserScan ScanAt(Time t, float range) {
  LaserScan s;
  s.stamp = t;
  s.ranges_m = {range};
  return s;
}

TEST(RobotStateTest, NearestScanByStamp) {
  FakeClock clock;
  RobotState state(&clock);
  const Time t0 = clock.Now();
  state.AddScan(ScanAt(t0, 1));
  state.AddScan(ScanAt(t0 + std::chrono::milliseconds(100), 2));
  state.AddScan(ScanAt(t0 + std::chrono::milliseconds(200), 3));
  EXPECT_EQ(state.NearestScan(t0 + std::chrono::milliseconds(140))->ranges_m[0], 2);
  EXPECT_EQ(state.NearestScan(t0 + std::chrono::milliseconds(160))->ranges_m[0], 3);
  EXPECT_EQ(state.NearestScan(t0 - std::chrono::seconds(5))->ranges_m[0], 1);
}

TEST(RobotStateTest, OdometryHistoryMovesAScanToTheImageTime) {
  FakeClock clock;
  RobotState state(&clock);
  const Time t0 = clock.Now();
  const LaserScan scan = ScanAt(t0 + std::chrono::milliseconds(100), 2);  // one beam, ahead
  fusion::MovedScan moved;
  state.MoveScanToImageTime(scan, t0 + std::chrono::milliseconds(150), {}, &moved);
  EXPECT_FALSE(moved.moved);  // no odometry yet
  // Driving ahead at 1 m/s, odometry at 50 Hz, delivered out of order.
  for (int i : {1, 0, 3, 2, 5, 4, 7, 6, 9, 8}) {
    Odometry o;
    o.stamp = t0 + i * std::chrono::milliseconds(20);
    o.pose.x_m = 0.02 * i;
    o.linear_mps = 1.0;
    state.SetOdometry(o);
  }
  EXPECT_EQ(state.Snapshot().odometry->stamp, t0 + std::chrono::milliseconds(180));
  state.MoveScanToImageTime(scan, t0 + std::chrono::milliseconds(150), {}, &moved);
  ASSERT_TRUE(moved.moved) << moved.reason;
  EXPECT_NEAR(moved.points[0].x_m, 1.95, 1e-6);  // 5 cm nearer 50 ms later
  // Memory stays bounded however long the robot drives.
  for (int i = 10; i < 2000; ++i) {
    Odometry o;
    o.stamp = t0 + i * std::chrono::milliseconds(20);
    state.SetOdometry(o);
  }
  state.MoveScanToImageTime(scan, t0 + std::chrono::milliseconds(150), {}, &moved);
  EXPECT_FALSE(moved.moved);  // those samples are gone
}

TEST(RobotStateTest, EstopStateOfTheLatestHealthWithItsArrival) {
  FakeClock clock;
  RobotState state(&clock);
  SteadyTime received;
  EXPECT_FALSE(state.EstopEngaged(&received).has_value());
  RobotHealth health;
  health.estop_engaged = true;
  clock.Advance(std::chrono::seconds(1));
  state.SetHealth(health);
  EXPECT_EQ(state.EstopEngaged(&received), std::optional<bool>(true));
  EXPECT_EQ(received, clock.SteadyNow());
  health.estop_engaged = false;
  clock.Advance(std::chrono::seconds(1));
  state.SetHealth(health);
  EXPECT_EQ(state.EstopEngaged(&received), std::optional<bool>(false));
  EXPECT_EQ(received, clock.SteadyNow());
}

TEST(RobotStateTest, LatestSonarAndBumpersWithTheirArrival) {
  FakeClock clock;
  RobotState state(&clock);
  EXPECT_FALSE(state.Snapshot().sonar.has_value());
  EXPECT_FALSE(state.Snapshot().bumpers.has_value());
  SonarRanges sonar;
  sonar.cycle = 7;
  sonar.ranges.resize(8);
  clock.Advance(std::chrono::seconds(1));
  state.SetSonar(sonar);
  const SteadyTime sonar_at = clock.SteadyNow();
  BumperState bumpers;
  bumpers.segment_count = 16;
  bumpers.latched = 1u << 3;
  clock.Advance(std::chrono::seconds(1));
  state.SetBumpers(bumpers);
  const RobotSnapshot snapshot = state.Snapshot();
  ASSERT_TRUE(snapshot.sonar.has_value());
  EXPECT_EQ(snapshot.sonar->cycle, 7u);
  EXPECT_EQ(snapshot.sonar->ranges.size(), 8u);
  EXPECT_EQ(snapshot.last_sonar_received, sonar_at);
  ASSERT_TRUE(snapshot.bumpers.has_value());
  EXPECT_EQ(snapshot.bumpers->latched, 1u << 3);
  EXPECT_EQ(snapshot.last_bumpers_received, clock.SteadyNow());
}

TEST(RobotStateTest, FrameTimingsAreFoundByCaptureStampAmongTheRecentOnes) {
  FakeClock clock;
  RobotState state(&clock);
  const Time t0 = clock.Now();
  auto at = [&](int i) { return t0 + std::chrono::milliseconds(33 * i); };
  for (int i = 0; i < 100; ++i) {
    state.AddFrameTiming(
        {at(i), at(i) + std::chrono::milliseconds(2), at(i) + std::chrono::milliseconds(3)});
  }
  const std::optional<FrameTiming> recent = state.TimingOf(at(99));
  ASSERT_TRUE(recent.has_value());
  EXPECT_EQ(recent->encoded, at(99) + std::chrono::milliseconds(2));
  EXPECT_EQ(recent->written, at(99) + std::chrono::milliseconds(3));
  EXPECT_TRUE(state.TimingOf(at(100 - RobotState::kTimingHistory)).has_value());
  EXPECT_FALSE(state.TimingOf(at(99 - RobotState::kTimingHistory)).has_value()) << "forgotten";
  EXPECT_FALSE(state.TimingOf(at(50) + std::chrono::milliseconds(1)).has_value());
}

TEST(RobotStateTest, EmptyHistoryGivesNothing) {
  FakeClock clock;
  RobotState state(&clock);
  EXPECT_FALSE(state.NearestScan(clock.Now()).has_value());
  EXPECT_FALSE(state.Snapshot().latest_scan.has_value());
}

TEST(RobotStateTest, KeepsOnlyRecentScans) {
  FakeClock clock;
  RobotState state(&clock);
  const Time t0 = clock.Now();
  for (int i = 0; i < 100; ++i) {
    state.AddScan(ScanAt(t0 + std::chrono::milliseconds(100 * i), static_cast<float>(i)));
  }
  // 10 Hz: the oldest scan kept is the first stamped within 3 s of the newest (9.9 s).
  EXPECT_EQ(state.NearestScan(t0)->ranges_m[0], 69);
  EXPECT_EQ(state.Snapshot().scans, 100u);
}

TEST(RobotStateTest, KeepsTheSameTimeSpanOfScansAt75Hz) {
  FakeClock clock;
  RobotState state(&clock);
  const Time t0 = clock.Now();
  const Duration period = FromSeconds(0.01332);  // LMS200 at 500 kBd: every mirror turn
  for (int i = 0; i < 300; ++i) state.AddScan(ScanAt(t0 + i * period, static_cast<float>(i)));
  // Newest at 3.98 s: scans from 0.98 s on are kept (index 74), not just the last 32.
  EXPECT_EQ(state.NearestScan(t0)->ranges_m[0], 74);
  EXPECT_EQ(state.NearestScan(t0 + 200 * period + period / 3)->ranges_m[0], 200);
  // A burst faster than any scanner is still bounded in count.
  for (int i = 0; i < 1000; ++i) {
    state.AddScan(ScanAt(t0 + 300 * period + std::chrono::microseconds(i), 1000.0f + i));
  }
  EXPECT_EQ(state.NearestScan(t0)->ranges_m[0], 1000.0f + 1000 - 256);
}

TEST(RobotStateTest, ClockOffsetFromPongs) {
  FakeClock clock;
  RobotState state(&clock);
  // The robot's clock is 2 s ahead; 10 ms each way.
  for (int i = 0; i < 5; ++i) {
    ClockProbe p;
    p.t0 = clock.Now();
    clock.Advance(std::chrono::milliseconds(10));
    p.t1 = clock.Now() + std::chrono::seconds(2);
    p.t2 = p.t1;
    clock.Advance(std::chrono::milliseconds(10));
    state.AddClockSample(p);
  }
  const auto estimate = state.Snapshot().clock;
  ASSERT_TRUE(estimate.known);
  EXPECT_NEAR(ToSeconds(estimate.responder_minus_requester), 2.0, 1e-6);
}

TEST(RobotStateTest, PingLossFromMissingPongSequences) {
  FakeClock clock;
  RobotState state(&clock);
  EXPECT_LT(state.Snapshot().ping_loss, 0);  // unknown before two pongs
  auto pong = [&](uint64_t sequence) {
    ClockProbe p;
    p.sequence = sequence;
    p.t0 = clock.Now();
    p.t1 = p.t0;
    p.t2 = p.t0;
    state.AddClockSample(p);
  };
  for (uint64_t s = 1; s <= 10; ++s) pong(s);
  EXPECT_DOUBLE_EQ(state.Snapshot().ping_loss, 0.0);
  for (uint64_t s = 11; s <= 20; ++s) {
    if (s % 5 != 0) pong(s);  // 15 and 20 lost; 19 is the newest pong
  }
  // Sequences 1..19 seen except 15: 1 lost of 19.
  EXPECT_NEAR(state.Snapshot().ping_loss, 1.0 / 19.0, 1e-9);
  // The window forgets old losses: 100 more pongs without loss.
  for (uint64_t s = 21; s <= 120; ++s) pong(s);
  EXPECT_DOUBLE_EQ(state.Snapshot().ping_loss, 0.0);
}

}  // namespace
}  // namespace mostar::client
