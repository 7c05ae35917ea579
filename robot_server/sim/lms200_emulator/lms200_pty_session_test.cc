// The LMS200 driver (session + libserial) against the emulator over a real pseudo-terminal.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <thread>
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
  std::vector<LaserScan> scans() {
    std::lock_guard<std::mutex> lock(mutex_);
    return scans_;
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

laser::Lms200Config Config500k() {
  laser::Lms200Config config;
  config.set_baud(500000);
  config.set_rs422(true);
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

TEST(Lms200PtySessionTest, SwitchesFromPowerOnTo500kBdAndStreams181BeamScans) {
  Lms200EmulatorOptions options;  // factory state: 9600 Bd, 180 x 0.5 deg
  PtyFixture f(options, Config500k());
  f.Start();
  ASSERT_TRUE(f.WaitForScans(20, seconds(15)));
  EXPECT_EQ(f.emulator().baud(), 500000);  // moved there by 20 48
  EXPECT_EQ(f.emulator().variant(), (laser::Lms200Variant{180, 100}));
  const LaserScan scan = f.last_scan();
  ASSERT_EQ(scan.ranges_m.size(), 181u);
  EXPECT_NEAR(scan.ranges_m[90], 5.0, 0.002);
  EXPECT_NEAR(scan.scan_time_s, laser::kLms200MirrorPeriodS, 1e-6);  // every mirror turn
  const DeviceHealth health = f.scanner().Health();
  EXPECT_EQ(Counter(health, "baud_switches"), 1u);
  EXPECT_NE(health.message.find("500000"), std::string::npos) << health.message;
  EXPECT_EQ(f.runner().bytes_overrun(), 0u);
}

// The fault mix at 500 kBd: garbage before telegrams, bad CRCs, truncated telegrams and an
// unplug/replug. Every scan telegram the emulator sent complete, with a valid CRC, at the
// host's rate, is delivered exactly once, except those still in flight when the adapter was
// pulled: the tail of the stream the unplug ended (in the pty's buffer, or sent after the
// replug before the driver stopped and restarted the stream).
TEST(Lms200PtySessionTest, FaultMixAt500kBdLosesNoValidScan) {
  Lms200EmulatorOptions options;
  options.garbage_rate = 0.1;
  options.crc_error_rate = 0.1;
  options.truncate_rate = 0.05;
  NumberedRangeSource numbered;
  PtyFixture f(options, Config500k(), &numbered);
  f.Start();
  ASSERT_TRUE(f.WaitForScans(60, seconds(15)));
  const uint64_t unplugged_stream = f.emulator().stream_starts();
  f.runner().Unplug();
  std::this_thread::sleep_for(milliseconds(300));
  std::string error;
  ASSERT_TRUE(f.runner().Replug(&error)) << error;
  ASSERT_TRUE(f.WaitForScans(f.scan_count() + 60, seconds(15)));
  // Quiesce: no new scans; the telegram in flight leaves within 10 ms at 500 kBd.
  f.emulator().SetSilent(true);
  std::this_thread::sleep_for(milliseconds(100));
  const std::vector<Lms200Emulator::IntactScan> intact = f.emulator().IntactScans();
  const std::vector<uint64_t> stalled_list = f.emulator().StalledScans();
  const std::set<uint64_t> stalled(stalled_list.begin(), stalled_list.end());
  ASSERT_FALSE(intact.empty());
  ASSERT_LT(intact.back().id, NumberedRangeSource::kModulus);  // numbers are unique
  auto delivered_numbers = [&f] {
    std::multiset<uint64_t> numbers;
    for (const LaserScan& scan : f.scans())
      numbers.insert(NumberedRangeSource::Number(scan.ranges_m));
    return numbers;
  };
  // The last intact scan arrives (bounded wait), unless it is lost: then the check below says so.
  for (int i = 0; i < 100 && delivered_numbers().count(intact.back().id) == 0; ++i) {
    std::this_thread::sleep_for(milliseconds(50));
  }
  const std::multiset<uint64_t> delivered = delivered_numbers();
  const DeviceHealth health = f.scanner().Health();

  std::set<uint64_t> intact_ids;
  std::map<uint64_t, uint64_t> newest_delivered;  // per stream (20 24): the newest id delivered
  for (const auto& scan : intact) {
    intact_ids.insert(scan.id);
    if (delivered.count(scan.id) > 0) newest_delivered[scan.stream_starts] = scan.id;
  }
  std::vector<uint64_t> lost;
  int in_flight_at_unplug = 0;
  for (const auto& scan : intact) {
    if (delivered.count(scan.id) > 0) continue;
    if (scan.stream_starts == unplugged_stream && scan.id > newest_delivered[unplugged_stream]) {
      ++in_flight_at_unplug;
    } else {
      lost.push_back(scan.id);
    }
  }
  EXPECT_TRUE(lost.empty()) << lost.size() << " valid scans lost, the first "
                            << (lost.empty() ? 0 : lost.front());
  for (uint64_t number : delivered) {
    EXPECT_EQ(delivered.count(number), 1u) << "scan " << number << " delivered twice";
    EXPECT_EQ(intact_ids.count(number) + stalled.count(number), 1u)
        << "scan " << number << " was not sent intact";
  }
  size_t stalled_delivered = 0;
  for (uint64_t number : stalled) stalled_delivered += delivered.count(number);
  EXPECT_EQ(delivered.size() - stalled_delivered + lost.size() + in_flight_at_unplug,
            intact.size());
  EXPECT_EQ(newest_delivered.size(), 2u);  // before the unplug and after the replug
  // The faults happened and were counted; nothing was overrun.
  EXPECT_GT(Counter(health, "crc_errors"), 0u);
  EXPECT_GT(Counter(health, "resyncs"), 0u);
  EXPECT_GE(Counter(health, "port_lost"), 1u);
  EXPECT_EQ(Counter(health, "watchdog_restarts"), 0u);
  EXPECT_EQ(f.runner().bytes_overrun(), 0u);
  std::printf(
      "fault mix at 500 kBd: %zu intact, %zu delivered, %d in flight at the unplug, %zu stalled "
      "by the emulator's host (%zu of them delivered), %llu partials abandoned, %s\n",
      intact.size(), delivered.size(), in_flight_at_unplug, stalled.size(), stalled_delivered,
      static_cast<unsigned long long>(Counter(health, "truncated_frames")), health.message.c_str());
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
