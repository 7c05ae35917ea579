// A device-level SICK LMS200 model: host bytes in, device bytes out, driven by time.
//
// Pure protocol state machine (no I/O, no threads of its own): the caller feeds the bytes the
// host sent (`Receive`) and collects the bytes whose transmission has finished (`Transmit`).
// The model paces its own output like a UART (10 bit times per byte at the device's baud),
// so the pty runner only forwards bytes. It implements:
// - ACK (06) before every reply, NAK (15) on a bad checksum, silence for other addresses,
//   0x92 for unknown commands or commands not allowed in the current mode;
// - reset (10 -> 91, then 90 at 9600 Bd), status (31), error log (32), type (3A), variant
//   (3B, only when not streaming), configuration read/write (74/77) on an EEPROM image
//   (77 only in installation mode, entered with the password), poll (30 01);
// - baud switching (20 40/41/42/48): the A0 reply leaves at the old rate, later bytes at the
//   new rate; bytes the host sends at another rate are lost, bytes the device sends at a rate
//   the host is not set to arrive as garbage;
// - continuous output (20 24): the mirror turns at 75 Hz; a complete scan (1, 2 or 4 turns)
//   is sent when it completes only if the line is free, so scans are skipped while the line
//   is busy (as fast as the baud allows);
// - a request from the host aborts the telegram in flight (the host sees a truncated frame);
// - mm/cm units, measuring-mode distance masks, 0x1FF7 beyond the maximum (8.183 m in 13-bit
//   mm mode), 0x1FFF where there is no echo (+Inf), the dazzle code 0x1FFE where the range
//   source has no measurement (NaN), optional real-time indices;
// - fault injection: garbage bytes, CRC errors, truncated telegrams, NAKs, silence, forced
//   beam error codes;
// - ground truth for loss tests: every scan telegram that left complete, with a valid CRC and
//   at the host's rate (`IntactScans`), numbered in the order the scans were taken. A telegram
//   whose bytes left with a pause of more than kMaxLineStall inside it (the emulator's thread
//   was not scheduled; a real scanner's UART never pauses mid-telegram) is not intact: it is
//   listed in `StalledScans()` instead.
// Thread-safe: every public method locks an internal mutex.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "common/time/time.h"
#include "robot_server/laser/lms200_framer.h"
#include "robot_server/laser/lms200_telegrams.h"
#include "robot_server/sim/lms200_emulator/range_source.h"

namespace mostar::sim {

struct Lms200EmulatorOptions {
  int initial_baud = 9600;  // the rate after power-on
  uint8_t address = 0;
  uint8_t reply_address = 0x80;
  laser::Lms200Variant variant{180, 50};  // factory setting
  laser::Lms200Unit unit = laser::Lms200Unit::kMm;
  uint8_t measuring_mode = 0;
  bool real_time_indices = false;
  bool rs422 = true;  // accept 500 kBd
  std::string type = "LMS200;301063;V02.10 ";
  std::string password = "SICK_LMS";
  Duration reset_time = std::chrono::milliseconds(200);  // 91 until 90
  // Random faults, probability per telegram sent.
  double garbage_rate = 0;
  double crc_error_rate = 0;
  double truncate_rate = 0;
  uint32_t seed = 1;
};

class Lms200Emulator {
 public:
  // A scan telegram whose every byte left with a valid CRC at the host's rate.
  struct IntactScan {
    uint64_t id;             // 0, 1, ...: the order of the range source's Sample calls
    SteadyTime done;         // its last byte left the emulator
    uint64_t stream_starts;  // "start continuous" requests (20 24) received before it left
  };

  // `ranges` must outlive the emulator. `start` = power-on time.
  Lms200Emulator(const Lms200EmulatorOptions& options, RangeSource* ranges, SteadyTime start);

  // Bytes the host sent, arriving at `now` with the host's UART at `host_baud`.
  void Receive(const uint8_t* data, size_t size, int host_baud, SteadyTime now);
  // Appends the device bytes whose transmission finished by `now`; bytes sent at a rate other
  // than `host_baud` arrive as garbage. Also runs the mirror (continuous output).
  void Transmit(SteadyTime now, int host_baud, std::vector<uint8_t>* out);

  // ---- Fault injection ----
  void InjectGarbage(size_t bytes);
  void CorruptNextTelegrams(int count);  // wrong CRC
  void TruncateNextTelegrams(int count);
  void NakNextRequests(int count);
  void SetSilent(bool silent);                      // ignores every request (no ACK, no reply)
  void SetBeamCode(int beam, uint16_t code_13bit);  // e.g. 0x1FFE dazzle; same low bits used
  void ClearBeamCodes();                            // in 14/15/16-bit modes

  // ---- Inspection ----
  int baud() const;
  uint8_t operating_mode() const;
  laser::Lms200ConfigBlock config() const;
  laser::Lms200Variant variant() const;
  int eeprom_writes() const;
  uint64_t scans_sent() const;
  uint64_t requests_received() const;
  uint64_t stream_starts() const;
  // The last kIntactScanLog intact scans, oldest first.
  std::vector<IntactScan> IntactScans() const;
  static constexpr size_t kIntactScanLog = 4096;
  // The ids of the last kIntactScanLog scan telegrams left out of IntactScans because the line
  // paused inside them for more than kMaxLineStall beyond their wire timing (the emulator's
  // host was overloaded), oldest first. A driver may deliver or drop them.
  std::vector<uint64_t> StalledScans() const;
  static constexpr Duration kMaxLineStall = std::chrono::milliseconds(50);

 private:
  struct TxByte {
    uint8_t byte;
    SteadyTime done;
    int baud;
    uint64_t scan;  // scan id + 1 for the bytes of an intact scan telegram, else 0
    bool last;      // the telegram's last byte
  };
  void ApplyPendingLocked(SteadyTime now);
  void AdvanceMirrorLocked(SteadyTime now);
  void HandleRequestLocked(const laser::Lms200Frame& frame, SteadyTime now);
  // `scan`: id + 1 when `bytes` end with an intact scan telegram of `telegram_bytes` bytes.
  void SendLocked(const std::vector<uint8_t>& bytes, SteadyTime at, uint64_t scan = 0,
                  size_t telegram_bytes = 0);
  // `scan`: id + 1 when the payload is a scan.
  void SendReplyLocked(const std::vector<uint8_t>& payload, SteadyTime at, bool with_ack,
                       uint64_t scan = 0);
  std::vector<uint8_t> ScanPayloadLocked(SteadyTime scan_end);
  std::vector<uint8_t> StatusPayloadLocked() const;
  void RandomBytesLocked(size_t n, std::vector<uint8_t>* out);
  Duration ByteTime(int baud) const;
  Duration ScanPeriod() const;

  mutable std::mutex mutex_;
  Lms200EmulatorOptions options_;
  RangeSource* ranges_;
  std::mt19937 rng_;
  laser::Lms200Framer request_framer_;
  SteadyTime last_rx_;
  int baud_;
  std::optional<std::pair<SteadyTime, int>> pending_baud_;
  std::optional<SteadyTime> pending_power_on_;
  uint8_t mode_ = laser::kModeOnRequest;
  bool installation_ = false;
  laser::Lms200Variant variant_;
  laser::Lms200ConfigBlock config_;
  std::deque<TxByte> tx_;
  SteadyTime tx_free_;
  SteadyTime mirror_start_;
  SteadyTime next_scan_end_;
  uint64_t revolutions_ = 0;
  uint8_t telegram_index_ = 0;
  int corrupt_next_ = 0, truncate_next_ = 0, nak_next_ = 0;
  bool silent_ = false;
  std::map<int, uint16_t> beam_codes_;
  int eeprom_writes_ = 0;
  uint64_t scans_sent_ = 0;
  uint64_t requests_ = 0;
  uint64_t stream_starts_ = 0;
  uint64_t spoiled_scan_ = 0;  // scan id + 1 of a telegram with a byte lost or garbled
  // The telegram being transmitted (scan id + 1) and how late its first byte left.
  uint64_t sending_scan_ = 0;
  Duration sending_first_lateness_{0};
  std::deque<uint64_t> stalled_;
  std::deque<IntactScan> intact_;
};

}  // namespace mostar::sim
