// SerialDriveMotors against a board emulator on a pseudo-terminal (real serial I/O, threads,
// the system clock). Waits are bounded polls on observable state, never fixed sleeps.
#include "robot_server/drive/serial_drive_motors.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <mutex>
#include <thread>

#include "common/testing/subprocess.h"
#include "common/time/fake_clock.h"

namespace mostar::drive {
namespace {

// Polls `condition` until it holds or 3 s pass.
bool WaitFor(const std::function<bool()>& condition) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(3);
  while (std::chrono::steady_clock::now() < deadline) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return condition();
}

// The board side: answers each SetVelocity and Heartbeat with line noise, an encoder report
// and a status frame (and echoes heartbeats), unless set silent: then it reads and ignores.
class BoardEmulator {
 public:
  BoardEmulator() {
    master_ = posix_openpt(O_RDWR | O_NOCTTY);
    if (master_ < 0 || grantpt(master_) != 0 || unlockpt(master_) != 0) return;
    termios tio{};
    tcgetattr(master_, &tio);
    cfmakeraw(&tio);
    tcsetattr(master_, TCSANOW, &tio);
    slave_name_ = ptsname(master_);
    thread_ = std::thread([this] { Run(); });
  }
  ~BoardEmulator() {
    running_ = false;
    if (thread_.joinable()) thread_.join();
    if (master_ >= 0) close(master_);
  }
  const std::string& slave_name() const { return slave_name_; }

  std::optional<SetVelocityMsg> last_set_velocity() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return last_set_velocity_;
  }
  int stops() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return stops_;
  }
  void set_fault(uint16_t flags) {
    std::lock_guard<std::mutex> lock(mutex_);
    fault_flags_ = flags;
  }
  void set_silent(bool silent) {
    std::lock_guard<std::mutex> lock(mutex_);
    silent_ = silent;
  }
  int requests_ignored() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return requests_ignored_;
  }

 private:
  void Send(const MotorMessage& m) {
    const std::vector<uint8_t> bytes = EncodeMessage(m);
    const uint8_t noise[] = {0x00, 0xAA, 0x13};
    ssize_t ignored = write(master_, noise, sizeof(noise));
    ignored = write(master_, bytes.data(), bytes.size());
    (void)ignored;
  }
  void Run() {
    MotorFrameDecoder decoder;
    while (running_) {
      pollfd pfd{master_, POLLIN, 0};
      if (poll(&pfd, 1, 10) <= 0 || !(pfd.revents & POLLIN)) continue;
      uint8_t buf[256];
      const ssize_t n = read(master_, buf, sizeof(buf));
      if (n <= 0) continue;
      decoder.Push(buf, static_cast<size_t>(n));
      while (auto frame = decoder.Next()) {
        MotorMessage m;
        std::string error;
        if (!DecodeMessage(*frame, &m, &error)) continue;
        std::lock_guard<std::mutex> lock(mutex_);
        if (silent_) {
          ++requests_ignored_;
          continue;
        }
        if (const auto* v = std::get_if<SetVelocityMsg>(&m)) {
          last_set_velocity_ = *v;
          left_ += static_cast<uint32_t>(v->left_ticks_per_s / 10);
          right_ += static_cast<uint32_t>(v->right_ticks_per_s / 10);
        } else if (std::get_if<StopMsg>(&m)) {
          ++stops_;
        }
        Send(EncoderReportMsg{++board_time_us_, left_, right_});
        StatusMsg status;
        status.state = fault_flags_ ? BoardState::kFault : BoardState::kDriving;
        status.fault_flags = fault_flags_;
        status.battery_mv = 24100;
        Send(status);
        if (const auto* h = std::get_if<HeartbeatMsg>(&m)) Send(*h);
      }
    }
  }

  int master_ = -1;
  std::string slave_name_;
  std::atomic<bool> running_{true};
  std::thread thread_;
  mutable std::mutex mutex_;
  std::optional<SetVelocityMsg> last_set_velocity_;
  int stops_ = 0;
  uint16_t fault_flags_ = 0;
  bool silent_ = false;
  int requests_ignored_ = 0;
  uint32_t board_time_us_ = 0;
  uint32_t left_ = 0xFFF0;  // near the 16-bit wrap
  uint32_t right_ = 5;
};

SerialDriveMotorsOptions OptionsFor(const std::string& port) {
  SerialDriveMotorsOptions o;
  o.port = port;
  o.wheel_radius_m = 0.1;
  o.ticks_per_turn = 500;
  o.track_width_m = 0.5;
  o.link_timeout = std::chrono::seconds(2);
  return o;
}

TEST(SerialDriveMotorsTest, RefusesInvalidOptionsWithAMessage) {
  std::string error;
  SerialDriveMotorsOptions o = OptionsFor("/dev/nonexistent-mostar-port");
  o.baud = 12345;
  EXPECT_EQ(SerialDriveMotors::Open(SystemClock::Instance(), o, &error), nullptr);
  EXPECT_NE(error.find("baud"), std::string::npos);
  o = OptionsFor("");
  EXPECT_EQ(SerialDriveMotors::Open(SystemClock::Instance(), o, &error), nullptr);
  EXPECT_NE(error.find("port"), std::string::npos);
}

// Polls `condition` for up to 6 s while sending heartbeats (reopening takes up to 1 s).
bool WaitForLink(SerialDriveMotors* motors) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(6);
  std::string error;
  while (std::chrono::steady_clock::now() < deadline) {
    motors->SendHeartbeat(&error);
    if (motors->Status().link_ok) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

// The board's port is missing at start (a udev symlink not there yet), appears, vanishes
// (unplugged) and comes back: the motors open it each time, and meanwhile say why they fail.
TEST(SerialDriveMotorsTest, OpensThePortWhenItAppearsAndAgainAfterItVanishes) {
  const std::string dir = testing::MakeTempDir("mostar_drive_port_");
  ASSERT_FALSE(dir.empty());
  const std::string link = dir + "/mostar-drive";
  std::string error;
  auto motors = SerialDriveMotors::Open(SystemClock::Instance(), OptionsFor(link), &error);
  ASSERT_NE(motors, nullptr) << error;
  EXPECT_FALSE(motors->port_open());
  EXPECT_FALSE(motors->Status().link_ok);
  EXPECT_FALSE(motors->SetVelocity(0.1, 0, &error));
  EXPECT_NE(error.find("not open"), std::string::npos) << error;

  {
    BoardEmulator board;
    ASSERT_EQ(symlink(board.slave_name().c_str(), link.c_str()), 0);
    EXPECT_TRUE(WaitForLink(motors.get())) << "the port was not opened once it appeared";
    EXPECT_TRUE(motors->port_open());
    EXPECT_EQ(motors->port_opens(), 1);
    unlink(link.c_str());
  }  // the board goes away: its pty closes under the open port

  BoardEmulator replugged;
  ASSERT_EQ(symlink(replugged.slave_name().c_str(), link.c_str()), 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(6);
  while (motors->port_opens() < 2 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_EQ(motors->port_opens(), 2) << "the vanished port was not opened again";
  EXPECT_TRUE(WaitForLink(motors.get()));
  EXPECT_TRUE(motors->SetVelocity(0.1, 0, &error)) << error;
  EXPECT_TRUE(WaitFor([&] { return replugged.last_set_velocity().has_value(); }));
  motors.reset();
  unlink(link.c_str());
}

TEST(SerialDriveMotorsTest, TalksToTheBoardOverAPty) {
  BoardEmulator board;
  ASSERT_FALSE(board.slave_name().empty());
  std::string error;
  auto motors =
      SerialDriveMotors::Open(SystemClock::Instance(), OptionsFor(board.slave_name()), &error);
  ASSERT_NE(motors, nullptr) << error;

  EncoderReading reading;
  EXPECT_FALSE(motors->ReadEncoders(&reading, &error));  // nothing heard yet

  // 0.1 m/s forward, 0.4 rad/s: wheels 0.0 and 0.2 m/s; 795.8 ticks per metre.
  ASSERT_TRUE(motors->SetVelocity(0.1, 0.4, &error)) << error;
  ASSERT_TRUE(WaitFor([&] { return board.last_set_velocity().has_value(); }));
  EXPECT_EQ(board.last_set_velocity()->left_ticks_per_s, 0);
  EXPECT_EQ(board.last_set_velocity()->right_ticks_per_s, 159);

  ASSERT_TRUE(WaitFor([&] { return motors->ReadEncoders(&reading, &error); })) << error;
  EXPECT_EQ(reading.left_count, 0xFFF0u);
  EXPECT_EQ(reading.right_count, 5u + 15u);
  EXPECT_EQ(motors->counter_bits(), 16);

  // The link is up from the first frame of any kind; the board's status report comes on its own.
  ASSERT_TRUE(WaitFor([&] { return motors->Status().link_ok && motors->Status().battery_v > 0; }));
  EXPECT_FALSE(motors->Status().fault);
  EXPECT_NEAR(motors->Status().battery_v, 24.1, 1e-9);
  // The emulator's line noise was skipped, no frame lost.
  EXPECT_GT(motors->decoder_stats().discarded_bytes, 0u);

  board.set_fault(kFaultOvercurrentLeft);
  ASSERT_TRUE(motors->SendHeartbeat(&error));
  ASSERT_TRUE(WaitFor([&] { return motors->Status().fault; }));
  EXPECT_EQ(motors->Status().fault_flags, kFaultOvercurrentLeft);

  ASSERT_TRUE(motors->Stop(&error, /*clear_faults=*/true));
  ASSERT_TRUE(WaitFor([&] { return board.stops() == 1; }));
  // Closing sends one more stop.
  motors.reset();
  EXPECT_TRUE(WaitFor([&] { return board.stops() == 2; }));
}

TEST(SerialDriveMotorsTest, ClampsSetPointsToTheWheelSpeedLimit) {
  BoardEmulator board;
  std::string error;
  SerialDriveMotorsOptions o = OptionsFor(board.slave_name());
  o.max_wheel_speed_mps = 1.0;
  auto motors = SerialDriveMotors::Open(SystemClock::Instance(), o, &error);
  ASSERT_NE(motors, nullptr) << error;
  ASSERT_TRUE(motors->SetWheelVelocities({5.0, -5.0}, &error));
  ASSERT_TRUE(WaitFor([&] { return board.last_set_velocity().has_value(); }));
  EXPECT_EQ(board.last_set_velocity()->left_ticks_per_s, 796);
  EXPECT_EQ(board.last_set_velocity()->right_ticks_per_s, -796);
  EXPECT_FALSE(motors->SetWheelVelocities({std::nan(""), 0}, &error));
}

// docs/safety.md M3: with the default link timeout (200 ms), a board silent for longer than it
// takes the link down and encoder readings are refused; the board answering again brings both
// back. The motors run on a fake clock, so the boundary is exact and the test never sleeps for
// the timeout; the board still talks over a real pty.
TEST(SerialDriveMotorsTest, LinkGoesDownAndEncodersAreRefusedWhenTheBoardFallsSilent) {
  BoardEmulator board;
  ASSERT_FALSE(board.slave_name().empty());
  FakeClock clock;
  SerialDriveMotorsOptions o = OptionsFor(board.slave_name());
  o.link_timeout = SerialDriveMotorsOptions().link_timeout;
  ASSERT_EQ(o.link_timeout, std::chrono::milliseconds(200));
  std::string error;
  auto motors = SerialDriveMotors::Open(clock, o, &error);
  ASSERT_NE(motors, nullptr) << error;

  // One heartbeat: the board answers with a report, a status and the echo (3 frames).
  ASSERT_TRUE(motors->SendHeartbeat(&error)) << error;
  ASSERT_TRUE(WaitFor([&] { return motors->Status().frames_received == 3; }));
  EncoderReading reading;
  ASSERT_TRUE(motors->ReadEncoders(&reading, &error)) << error;
  EXPECT_TRUE(motors->Status().link_ok);

  // The board falls silent: asked, it no longer answers.
  board.set_silent(true);
  ASSERT_TRUE(motors->SendHeartbeat(&error)) << error;
  ASSERT_TRUE(WaitFor([&] { return board.requests_ignored() == 1; }));
  clock.Advance(std::chrono::milliseconds(200));
  EXPECT_TRUE(motors->Status().link_ok) << "down before the timeout";
  EXPECT_TRUE(motors->ReadEncoders(&reading, &error)) << error;
  clock.Advance(std::chrono::milliseconds(1));
  EXPECT_FALSE(motors->Status().link_ok) << "still up 201 ms after the last frame";
  error.clear();
  EXPECT_FALSE(motors->ReadEncoders(&reading, &error));
  EXPECT_NE(error.find("silent"), std::string::npos) << error;
  clock.Advance(std::chrono::seconds(5));
  EXPECT_FALSE(motors->Status().link_ok);
  EXPECT_FALSE(motors->ReadEncoders(&reading, &error));
  EXPECT_EQ(motors->Status().frames_received, 3u);

  // It answers again: the link and the readings come back, stamped now.
  board.set_silent(false);
  ASSERT_TRUE(motors->SendHeartbeat(&error)) << error;
  ASSERT_TRUE(WaitFor([&] { return motors->Status().frames_received == 6; }));
  EXPECT_TRUE(motors->Status().link_ok);
  ASSERT_TRUE(motors->ReadEncoders(&reading, &error)) << error;
  EXPECT_EQ(reading.steady_stamp, clock.SteadyNow());
}

}  // namespace
}  // namespace mostar::drive
