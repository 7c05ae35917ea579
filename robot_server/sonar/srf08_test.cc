#include "robot_server/sonar/srf08.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <map>
#include <mutex>

#include "robot_server/sonar/srf08_emulator.h"

namespace mostar::sonar {
namespace {

TEST(Srf08Test, RangeRegisterCoversTheWindowIn43MillimetreSteps) {
  EXPECT_EQ(Srf08RangeRegisterFor(11.008), 255);
  EXPECT_EQ(Srf08RangeRegisterFor(20), 255);
  EXPECT_EQ(Srf08RangeRegisterFor(0.043), 0);
  EXPECT_EQ(Srf08RangeRegisterFor(1.0), 23);  // 24 x 43 mm = 1.032 m
  EXPECT_GE(Srf08WindowMetres(Srf08RangeRegisterFor(6.0)), 6.0);
  EXPECT_LT(Srf08WindowMetres(Srf08RangeRegisterFor(6.0)) - 0.043, 6.0);
}

TEST(Srf08Test, EchoBytesAreCentimetresAndZeroIsNoEcho) {
  EXPECT_FLOAT_EQ(Srf08EchoMetres(0x01, 0x2C), 3.0f);
  EXPECT_TRUE(std::isinf(Srf08EchoMetres(0, 0)));
}

Srf08RingOptions EightSensors() {
  Srf08RingOptions o;
  for (int i = 0; i < 8; ++i) {
    Srf08Sensor s;
    s.address = static_cast<uint8_t>(kSrf08MinAddress + i);
    s.mount.frame_id = "sonar_" + std::to_string(i);
    s.mount.yaw_rad = i * M_PI / 4;
    o.sensors.push_back(s);
  }
  o.ping_groups = {{0, 4}, {1, 5}, {2, 6}, {3, 7}};  // opposite sides fire together
  o.max_range_m = 3.0;
  o.ranging_time = std::chrono::milliseconds(20);  // the 3 m window's echo time is 18 ms
  return o;
}

TEST(Srf08Test, OptionsValidationNamesTheProblem) {
  std::string error;
  Srf08RingOptions o = EightSensors();
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o.ping_groups = {{0, 4}, {1, 5}, {2, 6}, {3}};
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("exactly one group"), std::string::npos) << error;
  o = EightSensors();
  o.sensors[3].address = o.sensors[2].address;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("address used twice"), std::string::npos) << error;
  o = EightSensors();
  o.sensors[0].address = 0x10;
  EXPECT_FALSE(o.IsValid(&error));
  o = EightSensors();
  o.gain = 40;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("gain"), std::string::npos);
}

// Collects the ring's cycles.
class Cycles {
 public:
  void Add(const SonarRanges& r) {
    std::lock_guard<std::mutex> lock(mutex_);
    all_.push_back(r);
    cv_.notify_all();
  }
  // The n-th cycle (1-based), waiting up to 5 s.
  std::optional<SonarRanges> Wait(size_t n) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!cv_.wait_for(lock, std::chrono::seconds(5), [&] { return all_.size() >= n; })) {
      return std::nullopt;
    }
    return all_[n - 1];
  }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<SonarRanges> all_;
};

TEST(Srf08Test, RangesTheBeltGroupByGroupWithoutCrossTalk) {
  const std::map<uint8_t, float> truth = {{0x70, 0.5f}, {0x71, 1.25f}, {0x72, INFINITY},
                                          {0x73, 2.0f}, {0x74, 0.3f},  {0x75, 2.99f},
                                          {0x76, 5.0f}, {0x77, 0.04f}};
  auto bus = std::make_unique<Srf08BusEmulator>(SystemClock::Instance(),
                                                [&](uint8_t a) { return truth.at(a); });
  for (const auto& [address, range] : truth) bus->AddSensor(address);
  Srf08BusEmulator* emulator = bus.get();
  Srf08Ring ring(std::move(bus), EightSensors(), SystemClock::Instance());
  Cycles cycles;
  std::string error;
  ASSERT_TRUE(ring.Start([&](const SonarRanges& r) { cycles.Add(r); }, &error)) << error;
  const std::optional<SonarRanges> second = cycles.Wait(2);
  ring.Stop();
  ASSERT_TRUE(second.has_value());
  ASSERT_EQ(second->ranges.size(), 8u);
  for (size_t i = 0; i < 8; ++i) {
    const SonarRange& r = second->ranges[i];
    EXPECT_EQ(r.mount.frame_id, "sonar_" + std::to_string(i));
    EXPECT_FLOAT_EQ(r.max_range_m, 3.0f);
    EXPECT_FLOAT_EQ(r.min_range_m, 0.03f);
    const float expected = truth.at(static_cast<uint8_t>(0x70 + i));
    if (expected > 3.0f) {
      EXPECT_TRUE(std::isinf(r.range_m)) << i << ": beyond the window is no echo";
    } else {
      EXPECT_NEAR(r.range_m, expected, 0.006) << i;
    }
  }
  // Range and gain registers written, and never more than one group ranging at once.
  EXPECT_EQ(emulator->State(0x73).range_register, Srf08RangeRegisterFor(3.0));
  EXPECT_EQ(emulator->State(0x73).gain, 31);
  EXPECT_EQ(emulator->max_simultaneous(), 2);
  const DeviceHealth health = ring.Health();
  EXPECT_EQ(health.state, DeviceState::kOk) << health.message;
  EXPECT_GT(health.rate_hz, 0);
}

TEST(Srf08Test, ASilentSensorReadsNaNIsNamedInHealthAndIsConfiguredAgainWhenBack) {
  auto bus =
      std::make_unique<Srf08BusEmulator>(SystemClock::Instance(), [](uint8_t) { return 1.0f; });
  Srf08RingOptions options = EightSensors();
  for (const Srf08Sensor& s : options.sensors) bus->AddSensor(s.address);
  bus->SetAnswering(0x72, false);  // unplugged
  Srf08BusEmulator* emulator = bus.get();
  Srf08Ring ring(std::move(bus), options, SystemClock::Instance());
  Cycles cycles;
  std::string error;
  ASSERT_TRUE(ring.Start([&](const SonarRanges& r) { cycles.Add(r); }, &error)) << error;
  const std::optional<SonarRanges> first = cycles.Wait(1);
  ASSERT_TRUE(first.has_value());
  EXPECT_TRUE(std::isnan(first->ranges[2].range_m));
  EXPECT_NEAR(first->ranges[3].range_m, 1.0, 0.006) << "the others go on";
  DeviceHealth health = ring.Health();
  EXPECT_EQ(health.state, DeviceState::kWarn);
  EXPECT_NE(health.message.find("sonar_2"), std::string::npos) << health.message;

  emulator->SetAnswering(0x72, true);
  std::optional<SonarRanges> later;
  for (size_t n = 2; n < 10; ++n) {
    later = cycles.Wait(n);
    if (later && !std::isnan(later->ranges[2].range_m)) break;
  }
  ring.Stop();
  ASSERT_TRUE(later.has_value());
  EXPECT_NEAR(later->ranges[2].range_m, 1.0, 0.006) << "back after the replug";
  EXPECT_EQ(emulator->State(0x72).range_register, Srf08RangeRegisterFor(3.0)) << "configured again";
  health = ring.Health();
  bool counted = false;
  for (const auto& [name, value] : health.counters) {
    if (name == "bus_errors" && value > 0) counted = true;
  }
  EXPECT_TRUE(counted);
}

TEST(Srf08Test, StopEndsTheThreadPromptlyAndAStartedRingRefusesASecondStart) {
  auto bus =
      std::make_unique<Srf08BusEmulator>(SystemClock::Instance(), [](uint8_t) { return 1.0f; });
  Srf08RingOptions options = EightSensors();
  options.ranging_time = std::chrono::seconds(10);  // Stop must not wait for it
  for (const Srf08Sensor& s : options.sensors) bus->AddSensor(s.address);
  Srf08Ring ring(std::move(bus), options, SystemClock::Instance());
  std::string error;
  ASSERT_TRUE(ring.Start(nullptr, &error)) << error;
  EXPECT_FALSE(ring.Start(nullptr, &error));
  const auto start = std::chrono::steady_clock::now();
  ring.Stop();
  ring.Stop();
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
}

}  // namespace
}  // namespace mostar::sonar
