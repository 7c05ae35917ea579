#include "robot_server/sim/lms200_emulator/lms200_emulator.h"

#include <algorithm>
#include <cmath>

namespace mostar::sim {

using laser::Lms200ConfigBlock;
using laser::Lms200Frame;
using laser::Lms200Variant;

namespace {

constexpr double kPi = 3.14159265358979323846;
const Duration kMirrorPeriod = FromSeconds(laser::kLms200MirrorPeriodS);

void AppendU16(uint16_t v, std::vector<uint8_t>* out) {
  out->push_back(static_cast<uint8_t>(v & 0xFF));
  out->push_back(static_cast<uint8_t>(v >> 8));
}

int BaudOfModeCode(uint8_t code) {
  switch (code) {
    case laser::kModeBaud38400:
      return 38400;
    case laser::kModeBaud19200:
      return 19200;
    case laser::kModeBaud9600:
      return 9600;
    case laser::kModeBaud500000:
      return 500000;
    default:
      return 0;
  }
}

}  // namespace

Lms200Emulator::Lms200Emulator(const Lms200EmulatorOptions& options, RangeSource* ranges,
                               SteadyTime start)
    : options_(options),
      ranges_(ranges),
      rng_(options.seed),
      request_framer_(laser::Lms200Framer::Options{laser::Lms200Framer::Direction::kRequests, 0,
                                                   false, laser::kLms200MaxFrameBytes}),
      last_rx_(start),
      baud_(options.initial_baud),
      variant_(options.variant),
      tx_free_(start),
      mirror_start_(start) {
  config_.bytes[2] = 0x46;  // stop threshold, factory value
  config_.set_measuring_mode(options.measuring_mode);
  config_.set_unit(options.unit);
  config_.set_real_time_indices(options.real_time_indices);
  next_scan_end_ = start + ScanPeriod();
}

Duration Lms200Emulator::ByteTime(int baud) const {
  return FromSeconds(static_cast<double>(laser::kLms200BitsPerByte) / baud);
}

Duration Lms200Emulator::ScanPeriod() const { return kMirrorPeriod * variant_.revolutions(); }

void Lms200Emulator::RandomBytesLocked(size_t n, std::vector<uint8_t>* out) {
  std::uniform_int_distribution<int> byte(0, 255);
  for (size_t i = 0; i < n; ++i) out->push_back(static_cast<uint8_t>(byte(rng_)));
}

void Lms200Emulator::SendLocked(const std::vector<uint8_t>& bytes, SteadyTime at, uint64_t scan,
                                size_t telegram_bytes) {
  SteadyTime t = std::max(at, tx_free_);
  const Duration per_byte = ByteTime(baud_);
  for (size_t i = 0; i < bytes.size(); ++i) {
    t += per_byte;
    const bool in_telegram = scan != 0 && i + telegram_bytes >= bytes.size();
    tx_.push_back({bytes[i], t, baud_, in_telegram ? scan : 0, i + 1 == bytes.size()});
  }
  tx_free_ = t;
}

void Lms200Emulator::SendReplyLocked(const std::vector<uint8_t>& payload, SteadyTime at,
                                     bool with_ack, uint64_t scan) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<uint8_t> bytes;
  if (options_.garbage_rate > 0 && uniform(rng_) < options_.garbage_rate) {
    RandomBytesLocked(1 + rng_() % 20, &bytes);
  }
  if (with_ack) bytes.push_back(laser::kLms200Ack);
  std::vector<uint8_t> telegram = laser::BuildReplyTelegram(options_.reply_address, payload);
  if (corrupt_next_ > 0 ||
      (options_.crc_error_rate > 0 && uniform(rng_) < options_.crc_error_rate)) {
    if (corrupt_next_ > 0) --corrupt_next_;
    telegram.back() ^= 0x5A;
    scan = 0;
  }
  if (truncate_next_ > 0 ||
      (options_.truncate_rate > 0 && uniform(rng_) < options_.truncate_rate)) {
    if (truncate_next_ > 0) --truncate_next_;
    telegram.resize(telegram.size() / 2);
    scan = 0;
  }
  bytes.insert(bytes.end(), telegram.begin(), telegram.end());
  SendLocked(bytes, at, scan, telegram.size());
}

void Lms200Emulator::ApplyPendingLocked(SteadyTime now) {
  if (pending_baud_ && pending_baud_->first <= now) {
    baud_ = pending_baud_->second;
    pending_baud_.reset();
  }
  if (pending_power_on_ && *pending_power_on_ <= now) {
    pending_power_on_.reset();
    std::vector<uint8_t> payload{laser::kReplyPowerOn};
    payload.insert(payload.end(), options_.type.begin(), options_.type.end());
    payload.push_back(0x10);
    SendReplyLocked(payload, now, false);
  }
}

std::vector<uint8_t> Lms200Emulator::ScanPayloadLocked(SteadyTime scan_end) {
  const int count = variant_.values();
  std::vector<float> ranges;
  const float angle_min = static_cast<float>(-variant_.angle_deg * 0.5 * kPi / 180.0);
  const float increment = static_cast<float>(variant_.resolution_cdeg * 0.01 * kPi / 180.0);
  ranges_->Sample(scan_end, angle_min, increment, count, &ranges);
  const uint16_t mask = laser::DistanceMask(config_.measuring_mode());
  const auto unit = static_cast<laser::Lms200Unit>(config_.unit_code() & 1);
  const double unit_m = laser::UnitMetres(unit);
  std::vector<uint8_t> payload{laser::kReplyScan};
  AppendU16(static_cast<uint16_t>(count | (static_cast<int>(unit) << 14)), &payload);
  for (int i = 0; i < count; ++i) {
    uint16_t word;
    const auto forced = beam_codes_.find(i);
    const float r = i < static_cast<int>(ranges.size()) ? ranges[static_cast<size_t>(i)] : NAN;
    if (mask == 0) {
      word = 0;  // reflectivity mode: not modelled
    } else if (forced != beam_codes_.end()) {
      word = static_cast<uint16_t>(mask - (0x1FFF - forced->second));
    } else if (!(r > 0)) {
      word = static_cast<uint16_t>(mask - 1);  // NaN, not positive: a measurement error (dazzle)
    } else if (std::isinf(r)) {
      word = mask;  // no echo
    } else {
      const double counts = std::round(r / unit_m);
      word = counts >= mask - 8 ? static_cast<uint16_t>(mask - 8)  // beyond the maximum
                                : static_cast<uint16_t>(counts);
    }
    AppendU16(word, &payload);
  }
  if (config_.real_time_indices()) {
    payload.push_back(static_cast<uint8_t>(revolutions_ & 0xFF));
    payload.push_back(telegram_index_++);
  }
  payload.push_back(0x10);
  return payload;
}

std::vector<uint8_t> Lms200Emulator::StatusPayloadLocked() const {
  std::vector<uint8_t> p(1 + laser::kLms200StatusDataBytes + 1, 0);
  p[0] = laser::kReplyStatus;
  const std::string version = "V02.10 ";
  for (size_t i = 0; i < 7; ++i) p[1 + i] = static_cast<uint8_t>(version[i]);
  p[8] = mode_;
  p[9] = 0;
  p[18] = 0x01;
  p[102] = config_.measuring_mode();
  p[107] = static_cast<uint8_t>(variant_.angle_deg & 0xFF);
  p[108] = static_cast<uint8_t>(variant_.angle_deg >> 8);
  p[109] = static_cast<uint8_t>(variant_.resolution_cdeg & 0xFF);
  p[110] = static_cast<uint8_t>(variant_.resolution_cdeg >> 8);
  const uint16_t baud_word = laser::StatusBaudWord(baud_);
  p[116] = static_cast<uint8_t>(baud_word & 0xFF);
  p[117] = static_cast<uint8_t>(baud_word >> 8);
  p[120] = options_.address;
  p[122] = config_.unit_code();
  p.back() = 0x10;
  return p;
}

void Lms200Emulator::HandleRequestLocked(const Lms200Frame& frame, SteadyTime now) {
  if (frame.address != options_.address && frame.address != 0) return;  // not for us
  ++requests_;
  if (silent_) return;
  // A request aborts the telegram in flight.
  while (!tx_.empty() && tx_.back().done > now) tx_.pop_back();
  tx_free_ = now;
  if (nak_next_ > 0) {
    --nak_next_;
    SendLocked({laser::kLms200Nak}, now);
    return;
  }
  const std::vector<uint8_t>& p = frame.payload;
  const std::vector<uint8_t> rejected{laser::kReplyRejected, 0x10};
  const SteadyTime at = now + std::chrono::milliseconds(1);
  switch (p[0]) {
    case laser::kCmdReset:
      SendReplyLocked({laser::kReplyResetAck, 0x10}, at, true);
      mode_ = laser::kModeOnRequest;
      installation_ = false;
      pending_baud_ = {tx_free_, 9600};
      pending_power_on_ = tx_free_ + options_.reset_time;
      return;
    case laser::kCmdMode: {
      if (p.size() < 2) break;
      const uint8_t sub = p[1];
      uint8_t result = 0;
      int new_baud = 0;
      if (sub == laser::kModeInstallation) {
        const std::string given(p.begin() + 2, p.end());
        if (p.size() != 10 || given != options_.password) {
          result = 1;
        } else {
          installation_ = true;
          mode_ = sub;
        }
      } else if (sub == laser::kModeContinuous) {
        mode_ = sub;
        installation_ = false;
        ++stream_starts_;
      } else if (sub == laser::kModeOnRequest) {
        mode_ = sub;
        installation_ = false;
      } else if ((new_baud = BaudOfModeCode(sub)) != 0) {
        if (new_baud == 500000 && !options_.rs422) {
          result = 1;
          new_baud = 0;
        }
      } else {
        SendReplyLocked(rejected, at, true);
        return;
      }
      SendReplyLocked({laser::kReplyMode, result, 0x10}, at, true);
      if (new_baud != 0) pending_baud_ = {tx_free_, new_baud};
      return;
    }
    case laser::kCmdPollScan:
      if (p.size() == 2 && p[1] == 0x01) {
        SendReplyLocked(ScanPayloadLocked(now), at, true, scans_sent_ + 1);
        ++scans_sent_;
        return;
      }
      break;
    case laser::kCmdStatus:
      SendReplyLocked(StatusPayloadLocked(), at, true);
      return;
    case laser::kCmdErrors:
      SendReplyLocked({laser::kReplyErrors, 0x10}, at, true);
      return;
    case laser::kCmdType: {
      std::vector<uint8_t> payload{laser::kReplyType};
      payload.insert(payload.end(), options_.type.begin(), options_.type.end());
      payload.push_back(0x10);
      SendReplyLocked(payload, at, true);
      return;
    }
    case laser::kCmdVariant: {
      if (p.size() != 5) break;
      const Lms200Variant wanted{p[1] | (p[2] << 8), p[3] | (p[4] << 8)};
      const bool ok = wanted.IsValid() && mode_ != laser::kModeContinuous;
      if (ok) {
        variant_ = wanted;
        next_scan_end_ = now + ScanPeriod();
      }
      std::vector<uint8_t> payload{laser::kReplyVariant, static_cast<uint8_t>(ok ? 1 : 0)};
      AppendU16(static_cast<uint16_t>(variant_.angle_deg), &payload);
      AppendU16(static_cast<uint16_t>(variant_.resolution_cdeg), &payload);
      payload.push_back(0x10);
      SendReplyLocked(payload, at, true);
      return;
    }
    case laser::kCmdReadConfig: {
      std::vector<uint8_t> payload{laser::kReplyReadConfig};
      payload.insert(payload.end(), config_.bytes.begin(), config_.bytes.end());
      payload.push_back(0x10);
      SendReplyLocked(payload, at, true);
      return;
    }
    case laser::kCmdWriteConfig: {
      if (!installation_) break;
      const size_t block = p.size() - 1;
      const bool ok =
          block == Lms200ConfigBlock::kSize || block == Lms200ConfigBlock::kOldFirmwareSize;
      if (ok) {
        std::copy(p.begin() + 1, p.end(), config_.bytes.begin());
        ++eeprom_writes_;
      }
      std::vector<uint8_t> payload{laser::kReplyWriteConfig, static_cast<uint8_t>(ok ? 1 : 0)};
      payload.insert(payload.end(), config_.bytes.begin(), config_.bytes.end());
      payload.push_back(0x10);
      SendReplyLocked(payload, at, true);
      return;
    }
    default:
      break;
  }
  SendReplyLocked(rejected, at, true);
}

void Lms200Emulator::AdvanceMirrorLocked(SteadyTime now) {
  const Duration period = ScanPeriod();
  while (next_scan_end_ <= now) {
    revolutions_ += static_cast<uint64_t>(variant_.revolutions());
    ApplyPendingLocked(next_scan_end_);
    if (mode_ == laser::kModeContinuous && tx_free_ <= next_scan_end_ && !silent_) {
      SendReplyLocked(ScanPayloadLocked(next_scan_end_), next_scan_end_, false, scans_sent_ + 1);
      ++scans_sent_;
    }
    next_scan_end_ += period;
  }
}

void Lms200Emulator::Receive(const uint8_t* data, size_t size, int host_baud, SteadyTime now) {
  std::lock_guard<std::mutex> lock(mutex_);
  AdvanceMirrorLocked(now);
  ApplyPendingLocked(now);
  if (host_baud != baud_) return;  // framing errors: the bytes are lost
  std::vector<laser::FramerEvent> events;
  if (now - last_rx_ > std::chrono::milliseconds(50)) request_framer_.Reset();
  last_rx_ = now;
  const uint64_t crc_errors = request_framer_.stats().crc_errors;
  request_framer_.Push(data, size, &events);
  if (request_framer_.stats().crc_errors != crc_errors && events.empty() && !silent_) {
    SendLocked({laser::kLms200Nak}, now);
  }
  for (const laser::FramerEvent& event : events) {
    if (event.type == laser::FramerEventType::kFrame) HandleRequestLocked(event.frame, now);
  }
}

void Lms200Emulator::Transmit(SteadyTime now, int host_baud, std::vector<uint8_t>* out) {
  std::lock_guard<std::mutex> lock(mutex_);
  AdvanceMirrorLocked(now);
  ApplyPendingLocked(now);
  std::uniform_int_distribution<int> byte(0, 255);
  while (!tx_.empty() && tx_.front().done <= now) {
    const TxByte& b = tx_.front();
    const bool heard = b.baud == host_baud;
    out->push_back(heard ? b.byte : static_cast<uint8_t>(byte(rng_)));
    if (b.scan != 0 && !heard) spoiled_scan_ = b.scan;
    if (b.scan != 0 && b.scan != sending_scan_) {
      sending_scan_ = b.scan;
      sending_first_lateness_ = now - b.done;
    }
    if (b.scan != 0 && b.last && spoiled_scan_ != b.scan &&
        (now - b.done) - sending_first_lateness_ > kMaxLineStall) {
      spoiled_scan_ = b.scan;  // the line paused inside the telegram: not what a scanner sends
      stalled_.push_back(b.scan - 1);
      if (stalled_.size() > kIntactScanLog) stalled_.pop_front();
    }
    if (b.scan != 0 && b.last && spoiled_scan_ != b.scan) {
      intact_.push_back({b.scan - 1, b.done, stream_starts_});
      if (intact_.size() > kIntactScanLog) intact_.pop_front();
    }
    tx_.pop_front();
  }
}

void Lms200Emulator::InjectGarbage(size_t bytes) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<uint8_t> garbage;
  RandomBytesLocked(bytes, &garbage);
  SendLocked(garbage, tx_free_);
}
void Lms200Emulator::CorruptNextTelegrams(int count) {
  std::lock_guard<std::mutex> lock(mutex_);
  corrupt_next_ = count;
}
void Lms200Emulator::TruncateNextTelegrams(int count) {
  std::lock_guard<std::mutex> lock(mutex_);
  truncate_next_ = count;
}
void Lms200Emulator::NakNextRequests(int count) {
  std::lock_guard<std::mutex> lock(mutex_);
  nak_next_ = count;
}
void Lms200Emulator::SetSilent(bool silent) {
  std::lock_guard<std::mutex> lock(mutex_);
  silent_ = silent;
}
void Lms200Emulator::SetBeamCode(int beam, uint16_t code_13bit) {
  std::lock_guard<std::mutex> lock(mutex_);
  beam_codes_[beam] = code_13bit;
}
void Lms200Emulator::ClearBeamCodes() {
  std::lock_guard<std::mutex> lock(mutex_);
  beam_codes_.clear();
}
int Lms200Emulator::baud() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return baud_;
}
uint8_t Lms200Emulator::operating_mode() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return mode_;
}
Lms200ConfigBlock Lms200Emulator::config() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return config_;
}
Lms200Variant Lms200Emulator::variant() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return variant_;
}
int Lms200Emulator::eeprom_writes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return eeprom_writes_;
}
uint64_t Lms200Emulator::scans_sent() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return scans_sent_;
}
uint64_t Lms200Emulator::stream_starts() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stream_starts_;
}
std::vector<uint64_t> Lms200Emulator::StalledScans() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {stalled_.begin(), stalled_.end()};
}

std::vector<Lms200Emulator::IntactScan> Lms200Emulator::IntactScans() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {intact_.begin(), intact_.end()};
}
uint64_t Lms200Emulator::requests_received() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return requests_;
}

}  // namespace mostar::sim
