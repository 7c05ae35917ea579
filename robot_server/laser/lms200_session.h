// The LMS200 link: start-up sequence, command transactions, streaming and its watchdog.
//
// Start-up (each step is skipped when the scanner is already as wanted):
//  1. baud detection: at the last good rate, then 9600, 38400, 19200 (and 500000 when the link
//     is RS-422) send "stop streaming" (20 25) and wait for its A0 reply; a scanner left
//     streaming by a crashed driver is silenced this way;
//  2. device type (3A) and status (31) read;
//  3. configuration (74) read; written (installation mode + 77) only when unit, measuring
//     mode or real-time indices differ, since every write wears the EEPROM;
//  4. variant (3B) set only when it differs from the status;
//  5. baud switched (20 4x): the reply comes at the old rate, then the host follows and
//     verifies at the new rate;
//  6. continuous output (20 24) started.
// Requests at 500000 Bd are paced byte by byte (`fast_byte_gap`), as the telegram listing asks.
// Transactions wait for the ACK byte, resend after a NAK (after >= 30 ms), treat a 0x92 reply
// as a rejection (not retried) and use the listing's timeouts (3 s for mode changes, 15 s
// for EEPROM writes).
//
// Streaming watchdog: no valid scan within max(3 scan periods, 1 s) -> stop, flush, redetect
// and resume, forever. A vanished port is reopened every `reopen_interval` until it is back.
//
// Stamps: a scan is stamped with the wall time its first beam was measured: the arrival of
// its last byte minus the frame's transfer time at the current baud minus the mirror time
// from the first to the last beam. The remaining error is the unknown delay between the end
// of the sweep and the start of transmission (at most one mirror period, 13.3 ms) plus the
// serial adapter's latency.
//
// Threading: `Step` and `Shutdown` run on one thread (the device thread). `Health`,
// `RequestCancel` and `state` may be called from any thread.
#pragma once

#include <atomic>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "common/time/rate_meter.h"
#include "common/time/time.h"
#include "common/types/health.h"
#include "common/types/laser_scan.h"
#include "robot_server/laser/byte_stream.h"
#include "robot_server/laser/lms200_config.pb.h"
#include "robot_server/laser/lms200_framer.h"
#include "robot_server/laser/lms200_telegrams.h"

namespace mostar::laser {

// Checks the values protobuf ranges cannot express (baud set, variant combinations, mode
// codes, RS-422 for 500 kBd). False with a message naming the key.
bool ValidateLms200Config(const Lms200Config& config, std::string* error);

struct Lms200SessionOptions {
  Duration ack_timeout = std::chrono::milliseconds(250);  // spec: 60 ms; USB slack
  Duration reply_timeout = std::chrono::seconds(1);
  Duration mode_timeout = std::chrono::seconds(3);           // 20 xx, 3B
  Duration eeprom_timeout = std::chrono::seconds(15);        // 77
  Duration detect_timeout = std::chrono::milliseconds(400);  // per send while probing a rate
  Duration nak_pause = std::chrono::milliseconds(35);        // spec: >= 30 ms
  Duration baud_settle = std::chrono::milliseconds(50);
  Duration reopen_interval = std::chrono::milliseconds(250);
  Duration retry_pause = std::chrono::milliseconds(200);  // after a failed start-up
  Duration min_watchdog = std::chrono::seconds(1);
  // Quiet line after which a held partial telegram is abandoned (LMS gap <= 14 ms), during
  // transactions. While streaming, a partial is only abandoned after `streaming_idle_gap`: a
  // scan whose bytes pause longer than the LMS's own gaps (a USB adapter's latency timer, a
  // busy host) is still delivered, and the next telegram completes and resolves any false or
  // truncated candidate sooner than that anyway.
  Duration idle_gap = std::chrono::milliseconds(20);
  Duration streaming_idle_gap = std::chrono::milliseconds(200);
  // Idle time between the bytes of a request at 500000 Bd (spec: >= 55 us; at most 6 ms or
  // the scanner ignores the telegram). At 38400 Bd and below a byte lasts >= 260 us: none.
  Duration fast_byte_gap = std::chrono::microseconds(60);
  int max_sends = 3;
  // Pauses the device thread; tests pass FakeClock::Advance. Default: real sleep.
  std::function<void(Duration)> sleep;
};

class Lms200Session {
 public:
  enum class State { kClosed, kDetecting, kStreaming };
  using ScanCallback = std::function<void(const LaserScan&)>;

  // `stream` and `clock` must outlive the session. `config` must pass ValidateLms200Config.
  Lms200Session(ByteStream* stream, const Clock* clock, const Lms200Config& config,
                Lms200SessionOptions options = {});
  Lms200Session(const Lms200Session&) = delete;
  Lms200Session& operator=(const Lms200Session&) = delete;

  // Advances the state machine by one step: opens the port, runs a complete start-up, or
  // reads for up to ~50 ms while streaming. Scans go to `on_scan` on the calling thread.
  void Step(const ScanCallback& on_scan);
  // Best effort: stops the stream (20 25) and closes the port.
  void Shutdown();
  // Makes a running Step return soon (start-up aborted); thread-safe.
  void RequestCancel() { cancel_.store(true); }
  void ClearCancel() { cancel_.store(false); }

  State state() const { return state_.load(); }
  int baud() const { return stream_->baud_rate(); }
  DeviceHealth Health() const;

 private:
  enum class TxResult { kOk, kTimeout, kNak, kRejected, kIoError, kCancelled };
  struct TimedEvent {
    FramerEvent event;
    Time arrival;
  };

  bool StartUp(std::string* error);
  bool DetectBaud(std::string* error);
  bool ConfigureDevice(std::string* error);
  bool SwitchBaud(int baud, std::string* error);
  // Sets the host's line rate and the byte pacing the scanner needs at that rate.
  bool SetLineBaud(int baud, std::string* error);
  // `scan_confirms`: a scan telegram also answers the request (start continuous: the scanner
  // streams, whatever happened to its reply); the scan stays pending for delivery.
  TxResult Transact(const std::vector<uint8_t>& request, uint8_t reply_code, Duration timeout,
                    int max_sends, Lms200Frame* reply, std::string* error,
                    bool scan_confirms = false);
  // Reads until at least one event is pending or `deadline`; false on I/O failure/cancel.
  // A partial telegram is abandoned after `idle_gap` of quiet line.
  bool Pump(SteadyTime deadline, std::string* error, Duration idle_gap);
  void HandleScanFrame(const TimedEvent& event, const ScanCallback& on_scan);
  void StepStreaming(const ScanCallback& on_scan);
  void Sleep(Duration d);
  void LostPort(const std::string& why);
  void SetMessage(DeviceState state, const std::string& message);
  void Count(const char* name, uint64_t n = 1);
  Duration ExpectedScanPeriod() const;
  Duration WatchdogTimeout() const;

  ByteStream* stream_;
  const Clock* clock_;
  Lms200Config config_;
  Lms200SessionOptions options_;
  Lms200Framer framer_;
  std::deque<TimedEvent> pending_;
  std::atomic<State> state_{State::kClosed};
  std::atomic<bool> cancel_{false};

  int last_good_baud_;
  Lms200ConfigBlock device_config_;
  Lms200Variant variant_;
  std::string device_type_;
  SteadyTime last_rx_;
  SteadyTime last_scan_;
  std::optional<uint8_t> last_telegram_index_;
  uint64_t sequence_ = 0;
  bool announced_missing_port_ = false;

  mutable std::mutex health_mutex_;  // guards the fields below
  DeviceState health_state_ = DeviceState::kOff;
  std::string health_message_ = "not started";
  std::vector<std::pair<std::string, uint64_t>> counters_;
  FramerStats framer_stats_;
  mutable RateMeter rate_;
};

}  // namespace mostar::laser
