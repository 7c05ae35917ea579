#include "robot_server/laser/lms200_session.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "common/time/fake_clock.h"
#include "robot_server/laser/fake_byte_stream.h"

namespace mostar::laser {
namespace {

using Bytes = std::vector<uint8_t>;

uint64_t Counter(const DeviceHealth& health, const std::string& name) {
  uint64_t total = 0;
  for (const auto& c : health.counters) {
    if (c.first == name) total += c.second;
  }
  return total;
}

Bytes Reply(const Bytes& payload) { return BuildReplyTelegram(0x80, payload); }

Bytes ScanTelegram(uint16_t range_mm) {
  Bytes payload{0xB0, 181 & 0xFF, static_cast<uint8_t>((181 >> 8) | 0x40)};
  for (int i = 0; i < 181; ++i) {
    payload.push_back(static_cast<uint8_t>(range_mm & 0xFF));
    payload.push_back(static_cast<uint8_t>(range_mm >> 8));
  }
  payload.push_back(0x10);
  return Reply(payload);
}

// A minimal scripted LMS200: answers the start-up requests and, on "start continuous",
// queues `scans_per_start` scans and then falls silent. It listens at one baud rate (requests
// written at another are garbage to it and go unanswered) and moves to the rate a mode-change
// request asks for after replying at the old one, as the real scanner does.
class ScriptedDevice {
 public:
  ScriptedDevice(FakeByteStream* stream, int device_baud) : device_baud_(device_baud) {
    stream->set_on_write([this](const Bytes& w, FakeByteStream* s) { OnWrite(w, s); });
  }
  int scans_per_start = 5;
  int nak_first = 0;                 // answer the first n requests with NAK
  bool corrupt_start_reply = false;  // the A0 to "start continuous" arrives with a bad CRC
  int starts = 0;
  int config_writes = 0;
  std::vector<uint8_t> commands;
  std::vector<int> write_bauds;   // the host's line rate at each request written, answered or not
  std::vector<int> baud_changes;  // rates the host told the device to move to, in order
  std::vector<Duration> write_gaps;  // the stream's byte pacing at each request written
  int device_baud() const { return device_baud_; }

 private:
  void OnWrite(const Bytes& w, FakeByteStream* s) {
    write_bauds.push_back(s->baud_rate());
    write_gaps.push_back(s->write_byte_gap());
    if (s->baud_rate() != device_baud_ || w.size() < 5) return;  // wrong rate: garbage
    if (nak_first > 0) {
      --nak_first;
      s->QueueInput({kLms200Nak});
      return;
    }
    const uint8_t cmd = w[4];
    commands.push_back(cmd);
    Bytes out{kLms200Ack};
    Bytes reply;
    if (cmd == 0x20 && w[5] == 0x24) {
      ++starts;
      reply = Reply({0xA0, 0x00, 0x10});
      if (corrupt_start_reply) reply.back() ^= 0x5A;
      out.insert(out.end(), reply.begin(), reply.end());
      for (int i = 0; i < scans_per_start; ++i) {
        const Bytes scan = ScanTelegram(static_cast<uint16_t>(1000 + i));
        out.insert(out.end(), scan.begin(), scan.end());
      }
      s->QueueInput(out);
      return;
    }
    if (cmd == 0x20) {
      reply = Reply({0xA0, 0x00, 0x10});
      int new_baud = 0;
      if (w[5] == kModeBaud38400) new_baud = 38400;
      if (w[5] == kModeBaud19200) new_baud = 19200;
      if (w[5] == kModeBaud9600) new_baud = 9600;
      if (w[5] == kModeBaud500000) new_baud = 500000;
      if (new_baud != 0) {
        device_baud_ = new_baud;
        baud_changes.push_back(new_baud);
      }  // the reply above still goes out at the old rate
    } else if (cmd == 0x3A) {
      reply = Reply({0xBA, 'L', 'M', 'S', '2', '0', '0', 0x10});
    } else if (cmd == 0x74) {
      Bytes p{0xF4};
      Bytes block(34, 0);
      block[6] = 0x01;  // mm
      p.insert(p.end(), block.begin(), block.end());
      p.push_back(0x10);
      reply = Reply(p);
    } else if (cmd == 0x3B) {
      reply = Reply({0xBB, 0x01, w[5], w[6], w[7], w[8], 0x10});
    } else if (cmd == 0x77) {
      ++config_writes;
      Bytes p{0xF7, 0x01};
      p.insert(p.end(), w.begin() + 5, w.end() - 2);
      p.push_back(0x10);
      reply = Reply(p);
    } else {
      reply = Reply({0x92, 0x10});
    }
    out.insert(out.end(), reply.begin(), reply.end());
    s->QueueInput(out);
  }
  int device_baud_;
};

struct Fixture {
  FakeClock clock;
  FakeByteStream stream{&clock};
  Lms200Config config;
  Lms200SessionOptions options;
  std::vector<LaserScan> scans;
  Fixture() {
    config.set_baud(38400);
    options.sleep = [this](Duration d) { clock.Advance(d); };
  }
};

TEST(Lms200SessionTest, StartsUpAtDeviceRateAndDeliversStampedScans) {
  Fixture f;
  ScriptedDevice device(&f.stream, 38400);
  Lms200Session session(&f.stream, &f.clock, f.config, f.options);
  for (int i = 0; i < 10 && f.scans.size() < 5; ++i) {
    session.Step([&](const LaserScan& s) { f.scans.push_back(s); });
  }
  ASSERT_EQ(f.scans.size(), 5u);
  EXPECT_EQ(session.state(), Lms200Session::State::kStreaming);
  EXPECT_FLOAT_EQ(f.scans[0].ranges_m[0], 1.0f);
  EXPECT_EQ(f.scans[4].sequence, 4u);
  // Stamp: before arrival by the wire time of 372 bytes at 38400 Bd plus half a revolution.
  EXPECT_LT(f.scans[0].stamp, f.clock.Now() - std::chrono::milliseconds(96));
  // The device was already at 38400 in mm: no config write, no baud switch.
  EXPECT_EQ(device.config_writes, 0);
  EXPECT_EQ(Counter(session.Health(), "baud_switches"), 0u);
  EXPECT_EQ(session.Health().state, DeviceState::kOk);
}

TEST(Lms200SessionTest, ResendsAfterNakAndCountsIt) {
  Fixture f;
  ScriptedDevice device(&f.stream, 38400);
  device.nak_first = 2;
  Lms200Session session(&f.stream, &f.clock, f.config, f.options);
  for (int i = 0; i < 10 && f.scans.empty(); ++i) {
    session.Step([&](const LaserScan& s) { f.scans.push_back(s); });
  }
  EXPECT_FALSE(f.scans.empty());
  EXPECT_EQ(Counter(session.Health(), "naks"), 2u);
  EXPECT_GE(Counter(session.Health(), "resends"), 2u);
}

TEST(Lms200SessionTest, WatchdogRestartsSilentStreamAfterOneSecond) {
  Fixture f;
  ScriptedDevice device(&f.stream, 38400);
  Lms200Session session(&f.stream, &f.clock, f.config, f.options);
  for (int i = 0; i < 10 && f.scans.size() < 5; ++i) {
    session.Step([&](const LaserScan& s) { f.scans.push_back(s); });
  }
  ASSERT_EQ(device.starts, 1);
  const SteadyTime silent_since = f.clock.SteadyNow();
  while (session.state() == Lms200Session::State::kStreaming &&
         f.clock.SteadyNow() - silent_since < std::chrono::seconds(5)) {
    session.Step(nullptr);
  }
  const Duration waited = f.clock.SteadyNow() - silent_since;
  EXPECT_GE(waited, std::chrono::seconds(1));
  EXPECT_LT(waited, std::chrono::milliseconds(1200));
  EXPECT_EQ(Counter(session.Health(), "watchdog_restarts"), 1u);
  for (int i = 0; i < 5 && session.state() != Lms200Session::State::kStreaming; ++i) {
    session.Step(nullptr);
  }
  EXPECT_EQ(device.starts, 2);
}

TEST(Lms200SessionTest, KeepsReopeningAMissingPortAndRecovers) {
  Fixture f;
  ScriptedDevice device(&f.stream, 38400);
  f.stream.SetUnplugged(true);
  Lms200Session session(&f.stream, &f.clock, f.config, f.options);
  for (int i = 0; i < 20; ++i) session.Step(nullptr);
  EXPECT_EQ(session.state(), Lms200Session::State::kClosed);
  EXPECT_EQ(session.Health().state, DeviceState::kError);
  EXPECT_EQ(Counter(session.Health(), "open_failures"), 20u);
  f.stream.SetUnplugged(false);
  for (int i = 0; i < 10 && f.scans.empty(); ++i) {
    session.Step([&](const LaserScan& s) { f.scans.push_back(s); });
  }
  EXPECT_FALSE(f.scans.empty());
}

TEST(Lms200SessionTest, DetectsBaudByProbingAndSwitchesToConfiguredRate) {
  Fixture f;
  // Configured for 38400; the device sits at 19200, the last rate the session probes.
  ASSERT_EQ(f.config.baud(), 38400);
  ScriptedDevice device(&f.stream, 19200);
  Lms200Session session(&f.stream, &f.clock, f.config, f.options);
  for (int i = 0; i < 10 && f.scans.empty(); ++i) {
    session.Step([&](const LaserScan& s) { f.scans.push_back(s); });
  }
  EXPECT_FALSE(f.scans.empty());
  // Probed 38400 (the last good rate, i.e. the configured one) and 9600 without an answer,
  // found the device at 19200, told it to move and followed it to the configured rate.
  std::vector<int> probe_bauds;
  for (int baud : device.write_bauds) {
    if (probe_bauds.empty() || probe_bauds.back() != baud) probe_bauds.push_back(baud);
  }
  EXPECT_EQ(probe_bauds, (std::vector<int>{38400, 9600, 19200, 38400}));
  ASSERT_FALSE(device.commands.empty());
  EXPECT_EQ(device.commands[0], 0x20);  // "stop streaming": the probe that 19200 answered
  EXPECT_EQ(device.baud_changes, (std::vector<int>{38400}));
  EXPECT_EQ(device.device_baud(), 38400);
  EXPECT_EQ(f.stream.baud_rate(), 38400);
  EXPECT_EQ(Counter(session.Health(), "baud_switches"), 1u);
  EXPECT_EQ(session.state(), Lms200Session::State::kStreaming);
}

TEST(Lms200SessionTest, AScanConfirmsStreamingWhenTheStartReplyIsLost) {
  Fixture f;
  ScriptedDevice device(&f.stream, 38400);
  device.corrupt_start_reply = true;
  Lms200Session session(&f.stream, &f.clock, f.config, f.options);
  for (int i = 0; i < 10 && f.scans.size() < 5; ++i) {
    session.Step([&](const LaserScan& s) { f.scans.push_back(s); });
  }
  // All five scans, the first included; "start continuous" was not sent again.
  ASSERT_EQ(f.scans.size(), 5u);
  EXPECT_FLOAT_EQ(f.scans[0].ranges_m[0], 1.0f);
  EXPECT_EQ(device.starts, 1);
  const DeviceHealth health = session.Health();
  EXPECT_EQ(Counter(health, "start_confirmed_by_scan"), 1u);
  EXPECT_EQ(Counter(health, "crc_errors"), 1u);
}

TEST(Lms200SessionTest, SwitchesTo500kBdWithPacedRequests) {
  Fixture f;
  f.config.set_baud(500000);
  f.config.set_rs422(true);
  ScriptedDevice device(&f.stream, 9600);  // power-on rate
  Lms200Session session(&f.stream, &f.clock, f.config, f.options);
  for (int i = 0; i < 10 && f.scans.empty(); ++i) {
    session.Step([&](const LaserScan& s) { f.scans.push_back(s); });
  }
  ASSERT_FALSE(f.scans.empty());
  EXPECT_EQ(device.baud_changes, (std::vector<int>{500000}));  // telegram 20 48
  EXPECT_EQ(f.stream.baud_rate(), 500000);
  ASSERT_EQ(device.write_bauds.size(), device.write_gaps.size());
  int paced = 0;
  for (size_t i = 0; i < device.write_bauds.size(); ++i) {
    // Paced exactly at 500 kBd, back to back at the RS-232 rates.
    if (device.write_bauds[i] == 500000) {
      EXPECT_GE(device.write_gaps[i], std::chrono::microseconds(55));
      EXPECT_LE(device.write_gaps[i], std::chrono::milliseconds(6));
      ++paced;
    } else {
      EXPECT_EQ(device.write_gaps[i], Duration::zero());
    }
  }
  EXPECT_GE(paced, 2);  // the check after the switch and "start continuous"
  // The scan period is one mirror turn: the wire (7.4 ms) is faster than the mirror.
  EXPECT_NEAR(f.scans[0].scan_time_s, kLms200MirrorPeriodS, 1e-6);
}

TEST(Lms200SessionTest, RefusesARateTheAdapterCannotProduceBeforeTheScannerMoves) {
  Fixture f;
  f.config.set_baud(500000);
  f.config.set_rs422(true);
  f.stream.set_max_baud(38400);
  ScriptedDevice device(&f.stream, 9600);
  Lms200Session session(&f.stream, &f.clock, f.config, f.options);
  for (int i = 0; i < 6; ++i) session.Step([&](const LaserScan& s) { f.scans.push_back(s); });
  EXPECT_TRUE(f.scans.empty());
  EXPECT_TRUE(device.baud_changes.empty());  // the scanner stays reachable at 9600
  EXPECT_EQ(device.device_baud(), 9600);
  const DeviceHealth health = session.Health();
  EXPECT_GE(Counter(health, "startup_failures"), 1u);
  EXPECT_NE(health.message.find("500000"), std::string::npos) << health.message;
}

TEST(Lms200SessionTest, ValidatesConfiguration) {
  Lms200Config config;
  std::string error;
  EXPECT_TRUE(ValidateLms200Config(config, &error)) << error;
  config.set_baud(500000);
  EXPECT_FALSE(ValidateLms200Config(config, &error));
  EXPECT_NE(error.find("rs422"), std::string::npos);
  config.set_rs422(true);
  EXPECT_TRUE(ValidateLms200Config(config, &error));
  config.set_angle_deg(180);
  config.set_resolution_cdeg(25);
  EXPECT_FALSE(ValidateLms200Config(config, &error));
  EXPECT_NE(error.find("variant"), std::string::npos);
}

}  // namespace
}  // namespace mostar::laser
