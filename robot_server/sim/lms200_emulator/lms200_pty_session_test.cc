// The LMS200 driver (session + libserial) against the emulator over a real pseudo-terminal.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "robot_server/laser/lms200_scanner.h"
#include "robot_server/laser/serial_byte_stream.h"
#include "robot_server/sim/lms200_emulator/lms200_pty.h"

namespace mostar::sim {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

uint64_t Counter(const DeviceHealth& health, const std::string& name) {
  for (const auto& c : health.counters) {
    if (c.first == name) return c.second;
  }
  return 0;
}

class PtyFixture {
 public:
  PtyFixture(const Lms200EmulatorOptions& emulator_options, laser::Lms200Config config,
             RangeSource* source = nullptr)
      : room_(10.0, 6.0, 5.0, 3.0),
        emulator_(emulator_options, source ? source : &room_, std::chrono::steady_clock::now()) {
    char dir[] = "/tmp/lms200_test_XXXXXX";
    dir_ = mkdtemp(dir);
    runner_ = std::make_unique<Lms200PtyRunner>(&emulator_, dir_ + "/lms200");
    std::string error;
    EXPECT_TRUE(runner_->Start(&error)) << error;
    config.set_port(runner_->device_path());
    scanner_ = std::make_unique<laser::Lms200Scanner>(
        std::make_unique<laser::SerialByteStream>(config.port(), config.baud()),
        &SystemClock::Instance(), config);
  }
  ~PtyFixture() {
    scanner_->Stop();
    runner_->Stop();
    ::rmdir(dir_.c_str());
  }
  void Start() {
    std::string error;
    ASSERT_TRUE(scanner_->Start(
        [this](const LaserScan& scan) {
          std::lock_guard<std::mutex> lock(mutex_);
          scans_.push_back(scan);
          cv_.notify_all();
        },
        &error))
        << error;
  }
  // Waits until at least `count` scans arrived; true on success.
  bool WaitForScans(size_t count, Duration timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, timeout, [&] { return scans_.size() >= count; });
  }
  size_t scan_count() {
    std::lock_guard<std::mutex> lock(mutex_);
    return scans_.size();
  }
  LaserScan last_scan() {
    std::lock_guard<std::mutex> lock(mutex_);
    return scans_.back();
  }
  Lms200Emulator& emulator() { return emulator_; }
  Lms200PtyRunner& runner() { return *runner_; }
  laser::Lms200Scanner& scanner() { return *scanner_; }

 private:
  RoomRangeSource room_;
  Lms200Emulator emulator_;
  std::string dir_;
  std::unique_ptr<Lms200PtyRunner> runner_;
  std::unique_ptr<laser::Lms200Scanner> scanner_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<LaserScan> scans_;
};

laser::Lms200Config Config38400() {
  laser::Lms200Config config;
  config.set_baud(38400);
  return config;
}

class Lms200PtySessionBaudTest : public ::testing::TestWithParam<int> {};

TEST_P(Lms200PtySessionBaudTest, StartsAtAnyDeviceBaudAndStreamsAtConfiguredRate) {
  Lms200EmulatorOptions options;
  options.initial_baud = GetParam();
  PtyFixture f(options, Config38400());
  f.Start();
  ASSERT_TRUE(f.WaitForScans(5, seconds(10)));
  EXPECT_EQ(f.emulator().baud(), 38400);
  EXPECT_EQ(f.emulator().variant(), (laser::Lms200Variant{180, 100}));
  EXPECT_EQ(f.emulator().eeprom_writes(), 0);  // already mm / mode 0
  const LaserScan scan = f.last_scan();
  ASSERT_EQ(scan.ranges_m.size(), 181u);
  EXPECT_NEAR(scan.ranges_m[90], 5.0, 0.002);  // wall ahead
  EXPECT_NEAR(scan.ranges_m[0], 3.0, 0.002);   // wall on the right
  EXPECT_EQ(f.scanner().Health().state, DeviceState::kOk);
}

INSTANTIATE_TEST_SUITE_P(DeviceBauds, Lms200PtySessionBaudTest,
                         ::testing::Values(9600, 19200, 38400));

TEST(Lms200PtySessionTest, SurvivesNaksSilenceAndLineFaults) {
  Lms200EmulatorOptions options;
  options.initial_baud = 38400;
  options.variant = {180, 100};
  options.garbage_rate = 0.1;
  options.crc_error_rate = 0.1;
  options.truncate_rate = 0.05;
  PtyFixture f(options, Config38400());
  f.emulator().NakNextRequests(2);
  f.Start();
  ASSERT_TRUE(f.WaitForScans(10, seconds(10)));
  // Silence: the watchdog restarts the link after max(3 periods, 1 s).
  f.emulator().SetSilent(true);
  std::this_thread::sleep_for(milliseconds(1500));
  f.emulator().SetSilent(false);
  const size_t before = f.scan_count();
  ASSERT_TRUE(f.WaitForScans(before + 5, seconds(10)));
  const DeviceHealth health = f.scanner().Health();
  EXPECT_GE(Counter(health, "naks"), 2u);
  EXPECT_GE(Counter(health, "watchdog_restarts"), 1u);
  EXPECT_GT(Counter(health, "crc_errors"), 0u);
}

TEST(Lms200PtySessionTest, ScansComeBackWithinTwoSecondsAfterReplug) {
  Lms200EmulatorOptions options;
  options.initial_baud = 38400;
  options.variant = {180, 100};
  PtyFixture f(options, Config38400());
  f.Start();
  ASSERT_TRUE(f.WaitForScans(5, seconds(10)));
  f.runner().Unplug();
  std::this_thread::sleep_for(milliseconds(800));
  EXPECT_EQ(f.scanner().Health().state, DeviceState::kError);
  const size_t before = f.scan_count();
  std::string error;
  ASSERT_TRUE(f.runner().Replug(&error)) << error;
  EXPECT_TRUE(f.WaitForScans(before + 1, seconds(2)));
  EXPECT_GE(Counter(f.scanner().Health(), "port_lost"), 1u);
}

TEST(Lms200PtySessionTest, WritesConfigOnceForMeasuringModeAndDecodesItsMask) {
  // The scanner holds cm / mode 0; the driver wants mm / mode 3 (16 m, 14 distance bits).
  Lms200EmulatorOptions options;
  options.initial_baud = 38400;
  options.unit = laser::Lms200Unit::kCm;
  laser::Lms200Config config = Config38400();
  config.set_measuring_mode(3);
  RoomRangeSource big_room(24.0, 6.0, 12.0, 3.0);
  PtyFixture f(options, config, &big_room);
  f.Start();
  ASSERT_TRUE(f.WaitForScans(3, seconds(10)));
  EXPECT_EQ(f.emulator().eeprom_writes(), 1);
  EXPECT_EQ(f.emulator().config().measuring_mode(), 3);
  const LaserScan scan = f.last_scan();
  EXPECT_NEAR(scan.ranges_m[90], 12.0, 0.002);  // beyond 8 m: needs the 14-bit mask
  EXPECT_NEAR(scan.range_max_m, 16.374, 0.001);
}

TEST(Lms200PtySessionTest, ErrorCodesBecomeUnknownBeamsAndNoEchoFreeSpace) {
  Lms200EmulatorOptions options;
  options.initial_baud = 38400;
  options.variant = {180, 100};
  FunctionRangeSource source([](SteadyTime, float a) { return a > 1.0f ? INFINITY : 4.0f; });
  PtyFixture f(options, Config38400(), &source);
  f.emulator().SetBeamCode(45, 0x1FFE);  // dazzle
  f.emulator().SetBeamCode(46, 0x1FFD);  // overflow
  f.Start();
  ASSERT_TRUE(f.WaitForScans(3, seconds(10)));
  const LaserScan scan = f.last_scan();
  EXPECT_TRUE(std::isnan(scan.ranges_m[45]));
  EXPECT_TRUE(std::isnan(scan.ranges_m[46]));
  EXPECT_TRUE(LaserScan::IsFreeRange(scan.ranges_m[180]));  // no echo
  EXPECT_FLOAT_EQ(scan.ranges_m[44], 4.0f);
  const DeviceHealth health = f.scanner().Health();
  const uint64_t scans = Counter(health, "scans");
  EXPECT_GE(scans, 3u);
  // Two error-coded beams per scan (the scan being counted may not have its beams counted yet).
  EXPECT_GE(Counter(health, "invalid_beams"), 2 * (scans - 1));
  EXPECT_GE(Counter(health, "beams_dazzle"), scans - 1);
  EXPECT_GE(Counter(health, "beams_overflow"), scans - 1);
  EXPECT_GE(Counter(health, "beams_no_echo"), scans - 1);
}

}  // namespace
}  // namespace mostar::sim
