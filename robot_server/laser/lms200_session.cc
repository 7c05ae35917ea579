#include "robot_server/laser/lms200_session.h"

#include <algorithm>
#include <thread>

#include "common/log/log.h"

namespace mostar::laser {
namespace {

Duration WireTime(size_t bytes, int baud) {
  if (baud <= 0) return Duration(0);
  return FromSeconds(static_cast<double>(bytes) * kLms200BitsPerByte / baud);
}

}  // namespace

bool ValidateLms200Config(const Lms200Config& config, std::string* error) {
  auto fail = [error](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (!BaudModeCode(config.baud())) {
    return fail("baud: " + std::to_string(config.baud()) +
                " is not one of 9600, 19200, 38400, 500000");
  }
  if (config.baud() == 500000 && !config.rs422()) {
    return fail("baud: 500000 needs an RS-422 link (set rs422: true)");
  }
  const Lms200Variant variant{config.angle_deg(), config.resolution_cdeg()};
  if (!variant.IsValid()) {
    return fail("angle_deg/resolution_cdeg: " + std::to_string(config.angle_deg()) + " x " +
                std::to_string(config.resolution_cdeg()) +
                " is not a valid variant (180x100, 180x50, 100x100, 100x50, 100x25)");
  }
  if (DistanceMask(static_cast<uint8_t>(config.measuring_mode())) == 0) {
    return fail("measuring_mode: " + std::to_string(config.measuring_mode()) +
                " does not deliver distances (use 0..6 or 15)");
  }
  if (config.address() < 0 || config.address() > 127) return fail("address: must be 0..127");
  if (config.installation_password().size() != 8) {
    return fail("installation_password: must have 8 characters");
  }
  return true;
}

Lms200Session::Lms200Session(ByteStream* stream, const Clock* clock, const Lms200Config& config,
                             Lms200SessionOptions options)
    : stream_(stream),
      clock_(clock),
      config_(config),
      options_(std::move(options)),
      framer_(Lms200Framer::Options{Lms200Framer::Direction::kReplies,
                                    static_cast<uint8_t>(config.address()),
                                    config.accept_reply_address_0x81(), kLms200MaxFrameBytes}),
      last_good_baud_(config.baud()),
      variant_{config.angle_deg(), config.resolution_cdeg()} {
  if (!options_.sleep) {
    options_.sleep = [](Duration d) { std::this_thread::sleep_for(d); };
  }
  device_config_.set_measuring_mode(static_cast<uint8_t>(config.measuring_mode()));
  device_config_.set_unit(static_cast<Lms200Unit>(config.unit()));
  last_rx_ = last_scan_ = clock_->SteadyNow();
}

void Lms200Session::Count(const char* name, uint64_t n) {
  std::lock_guard<std::mutex> lock(health_mutex_);
  for (auto& counter : counters_) {
    if (counter.first == name) {
      counter.second += n;
      return;
    }
  }
  counters_.emplace_back(name, n);
}

void Lms200Session::SetMessage(DeviceState state, const std::string& message) {
  std::lock_guard<std::mutex> lock(health_mutex_);
  health_state_ = state;
  health_message_ = message;
}

DeviceHealth Lms200Session::Health() const {
  DeviceHealth health;
  health.name = "lms200";
  std::lock_guard<std::mutex> lock(health_mutex_);
  health.state = health_state_;
  health.message = health_message_;
  health.rate_hz = static_cast<float>(rate_.RateHz(clock_->SteadyNow()));
  health.counters = counters_;
  health.counters.emplace_back("crc_errors", framer_stats_.crc_errors);
  health.counters.emplace_back("resyncs", framer_stats_.resyncs);
  health.counters.emplace_back("bytes_discarded", framer_stats_.bytes_discarded);
  health.counters.emplace_back("truncated_frames", framer_stats_.partials_abandoned);
  health.counters.emplace_back("naks", framer_stats_.naks);
  return health;
}

void Lms200Session::Sleep(Duration d) { options_.sleep(d); }

void Lms200Session::LostPort(const std::string& why) {
  stream_->Close();
  state_ = State::kClosed;
  pending_.clear();
  framer_.Reset();
  Count("port_lost");
  SetMessage(DeviceState::kError, "port lost: " + why);
  MOSTAR_LOG(WARNING) << "LMS200 " << stream_->name() << ": " << why;
}

Duration Lms200Session::ExpectedScanPeriod() const {
  const Duration mirror = FromSeconds(kLms200MirrorPeriodS * variant_.revolutions());
  const size_t frame_bytes = 2 * static_cast<size_t>(variant_.values()) + 10 +
                             (device_config_.real_time_indices() ? 2 : 0);
  const Duration wire = WireTime(frame_bytes, stream_->baud_rate());
  // The LMS sends the newest complete scan once the line is free: a whole number of scans.
  const int64_t scans = (wire.count() + mirror.count() - 1) / mirror.count();
  return mirror * std::max<int64_t>(1, scans);
}

Duration Lms200Session::WatchdogTimeout() const {
  return std::max<Duration>(3 * ExpectedScanPeriod(), options_.min_watchdog);
}

bool Lms200Session::Pump(SteadyTime deadline, std::string* error, Duration idle_gap) {
  uint8_t buffer[1024];
  while (pending_.empty()) {
    if (cancel_.load()) {
      if (error) *error = "cancelled";
      return false;
    }
    const SteadyTime now = clock_->SteadyNow();
    if (now >= deadline) return true;
    const Duration wait = std::min<Duration>(deadline - now, idle_gap);
    const int n = stream_->Read(buffer, sizeof(buffer), wait, error);
    if (n < 0) return false;
    std::vector<FramerEvent> events;
    if (n > 0) {
      last_rx_ = clock_->SteadyNow();
      framer_.Push(buffer, static_cast<size_t>(n), &events);
    } else if (framer_.holds_partial() && clock_->SteadyNow() - last_rx_ >= idle_gap) {
      framer_.AbandonPartial(&events);
    }
    const Time arrival = clock_->Now();
    for (FramerEvent& event : events) pending_.push_back({std::move(event), arrival});
    std::lock_guard<std::mutex> lock(health_mutex_);
    framer_stats_ = framer_.stats();
  }
  return true;
}

Lms200Session::TxResult Lms200Session::Transact(const std::vector<uint8_t>& request,
                                                uint8_t reply_code, Duration timeout, int max_sends,
                                                Lms200Frame* reply, std::string* error,
                                                bool scan_confirms) {
  TxResult result = TxResult::kTimeout;
  for (int send = 0; send < max_sends; ++send) {
    if (send > 0) Count("resends");
    stream_->Flush();
    framer_.Reset();
    pending_.clear();
    if (!stream_->Write(request.data(), request.size(), error)) return TxResult::kIoError;
    bool acked = false;
    SteadyTime deadline = clock_->SteadyNow() + options_.ack_timeout + timeout;
    result = TxResult::kTimeout;
    while (result == TxResult::kTimeout) {
      if (!Pump(deadline, error, options_.idle_gap)) {
        return cancel_.load() ? TxResult::kCancelled : TxResult::kIoError;
      }
      if (pending_.empty()) break;  // deadline reached
      TimedEvent event = std::move(pending_.front());
      pending_.pop_front();
      switch (event.event.type) {
        case FramerEventType::kAck:
          if (!acked) deadline = clock_->SteadyNow() + timeout;
          acked = true;
          break;
        case FramerEventType::kNak:
          result = TxResult::kNak;
          break;
        case FramerEventType::kFrame:
          if (event.event.frame.command() == reply_code) {
            *reply = std::move(event.event.frame);
            return TxResult::kOk;
          }
          if (scan_confirms && event.event.frame.command() == kReplyScan) {
            *reply = event.event.frame;
            pending_.push_front(std::move(event));
            return TxResult::kOk;
          }
          if (IsRejection(event.event.frame)) {
            Count("rejections");
            if (error) *error = "command rejected by the scanner (0x92)";
            return TxResult::kRejected;
          }
          Count("unexpected_frames");
          break;
      }
    }
    if (result == TxResult::kNak) {
      Sleep(options_.nak_pause);
      if (error) *error = "NAK (the scanner saw a bad checksum)";
    } else {
      Count(acked ? "reply_timeouts" : "ack_timeouts");
      if (error) *error = acked ? "no reply after ACK" : "no ACK";
    }
  }
  return result;
}

bool Lms200Session::DetectBaud(std::string* error) {
  std::vector<int> candidates{last_good_baud_, 9600, 38400, 19200};
  if (config_.rs422()) candidates.push_back(500000);
  std::vector<int> tried;
  const uint8_t address = static_cast<uint8_t>(config_.address());
  for (int baud : candidates) {
    if (std::find(tried.begin(), tried.end(), baud) != tried.end()) continue;
    tried.push_back(baud);
    if (!SetLineBaud(baud, error)) continue;
    Lms200Frame reply;
    // "Stop streaming" first: a scanner left streaming floods the line with B0 frames.
    const TxResult result = Transact(StopContinuousRequest(address), kReplyMode,
                                     options_.detect_timeout, 2, &reply, error);
    if (result == TxResult::kIoError || result == TxResult::kCancelled) return false;
    if (result == TxResult::kOk || result == TxResult::kRejected) {
      MOSTAR_LOG(INFO) << "LMS200 " << stream_->name() << " answers at " << baud << " Bd";
      return true;
    }
  }
  Count("detect_failures");
  if (error) *error = "no answer at any baud rate";
  return false;
}

bool Lms200Session::SetLineBaud(int baud, std::string* error) {
  stream_->SetWriteByteGap(baud > 38400 ? options_.fast_byte_gap : Duration::zero());
  return stream_->SetBaudRate(baud, error);
}

bool Lms200Session::SwitchBaud(int baud, std::string* error) {
  const uint8_t address = static_cast<uint8_t>(config_.address());
  // An adapter that cannot run at the new rate is found out before the scanner moves to it.
  const int old_baud = stream_->baud_rate();
  const bool host_can = SetLineBaud(baud, error);
  if (!SetLineBaud(old_baud, host_can ? error : nullptr) || !host_can) return false;
  Lms200Frame reply;
  Lms200ModeReply mode;
  if (Transact(BaudRequest(baud, address), kReplyMode, options_.mode_timeout, options_.max_sends,
               &reply, error) != TxResult::kOk ||
      !DecodeModeReply(reply, &mode, error)) {
    return false;
  }
  if (!mode.ok()) {
    if (error) *error = "baud switch to " + std::to_string(baud) + " refused";
    return false;
  }
  // The reply came at the old rate; the scanner now listens at the new one.
  if (!SetLineBaud(baud, error)) return false;
  Sleep(options_.baud_settle);
  if (Transact(StopContinuousRequest(address), kReplyMode, options_.reply_timeout,
               options_.max_sends, &reply, error) != TxResult::kOk) {
    if (error) *error = "no answer after switching to " + std::to_string(baud) + " Bd: " + *error;
    return false;
  }
  Count("baud_switches");
  return true;
}

bool Lms200Session::ConfigureDevice(std::string* error) {
  const uint8_t address = static_cast<uint8_t>(config_.address());
  Lms200Frame reply;
  // Type and status: informative; a failure here is not fatal.
  std::string ignored;
  if (Transact(TypeRequest(address), kReplyType, options_.reply_timeout, options_.max_sends, &reply,
               &ignored) == TxResult::kOk) {
    DecodeTypeReply(reply, &device_type_, &ignored);
  }
  std::optional<Lms200DeviceStatus> status;
  if (Transact(StatusRequest(address), kReplyStatus, options_.reply_timeout, options_.max_sends,
               &reply, &ignored) == TxResult::kOk) {
    Lms200DeviceStatus decoded;
    if (DecodeStatusReply(reply, &decoded, &ignored)) status = decoded;
  }
  if (status && status->status.is_error()) Count("device_error_status");

  // Configuration block: needed to decode (measuring mode, indices), written only on change.
  if (Transact(ReadConfigRequest(address), kReplyReadConfig, options_.reply_timeout,
               options_.max_sends, &reply, error) != TxResult::kOk ||
      !DecodeConfigReply(reply, &device_config_, error)) {
    if (error) *error = "reading the configuration: " + *error;
    return false;
  }
  Lms200ConfigBlock wanted = device_config_;
  wanted.set_unit(static_cast<Lms200Unit>(config_.unit()));
  wanted.set_measuring_mode(static_cast<uint8_t>(config_.measuring_mode()));
  wanted.set_real_time_indices(config_.real_time_indices());
  if (!(wanted == device_config_) && !config_.never_write_eeprom()) {
    MOSTAR_LOG(INFO) << "LMS200: writing the configuration (EEPROM)";
    Lms200ModeReply mode;
    if (Transact(InstallationModeRequest(config_.installation_password(), address), kReplyMode,
                 options_.mode_timeout, options_.max_sends, &reply, error) != TxResult::kOk ||
        !DecodeModeReply(reply, &mode, error)) {
      return false;
    }
    if (!mode.ok()) {
      if (error) *error = "installation mode refused (wrong password?)";
      return false;
    }
    bool accepted = false;
    Lms200ConfigBlock written;
    const TxResult write = Transact(WriteConfigRequest(wanted, address), kReplyWriteConfig,
                                    options_.eeprom_timeout, 1, &reply, error);
    if (write != TxResult::kOk || !DecodeConfigWriteReply(reply, &accepted, &written, error)) {
      return false;
    }
    Count("eeprom_writes");
    device_config_ = written;
    if (!accepted) {
      if (error) *error = "configuration write refused by the scanner";
      return false;
    }
    if (Transact(StopContinuousRequest(address), kReplyMode, options_.mode_timeout,
                 options_.max_sends, &reply, error) != TxResult::kOk) {
      return false;
    }
  }

  const Lms200Variant wanted_variant{config_.angle_deg(), config_.resolution_cdeg()};
  if (!status || status->variant != wanted_variant) {
    Lms200VariantReply variant;
    if (Transact(VariantRequest(wanted_variant, address), kReplyVariant, options_.mode_timeout,
                 options_.max_sends, &reply, error) != TxResult::kOk ||
        !DecodeVariantReply(reply, &variant, error)) {
      return false;
    }
    if (!variant.accepted) {
      if (error) *error = "variant refused by the scanner";
      return false;
    }
    Count("variant_changes");
  }
  variant_ = wanted_variant;
  return true;
}

bool Lms200Session::StartUp(std::string* error) {
  SetMessage(DeviceState::kWarn, "detecting baud rate");
  if (!DetectBaud(error)) return false;
  last_good_baud_ = stream_->baud_rate();
  SetMessage(DeviceState::kWarn, "configuring");
  if (!ConfigureDevice(error)) return false;
  if (stream_->baud_rate() != config_.baud()) {
    if (!SwitchBaud(config_.baud(), error)) return false;
    last_good_baud_ = stream_->baud_rate();
  }
  Lms200Frame reply;
  Lms200ModeReply mode;
  // A scan before the reply (the reply lost on the line) confirms as well: waiting for the
  // reply's timeout and asking again would drop every scan meanwhile.
  if (Transact(StartContinuousRequest(static_cast<uint8_t>(config_.address())), kReplyMode,
               options_.mode_timeout, options_.max_sends, &reply, error,
               /*scan_confirms=*/true) != TxResult::kOk) {
    return false;
  }
  if (reply.command() == kReplyScan) {
    Count("start_confirmed_by_scan");
  } else if (!DecodeModeReply(reply, &mode, error)) {
    return false;
  } else if (!mode.ok()) {
    if (error) *error = "continuous mode refused";
    return false;
  }
  last_telegram_index_.reset();
  last_scan_ = clock_->SteadyNow();
  return true;
}

void Lms200Session::HandleScanFrame(const TimedEvent& event, const ScanCallback& on_scan) {
  const Lms200Frame& frame = event.event.frame;
  Lms200MeasuredValues values;
  std::string error;
  Lms200ScanDecodeOptions decode{device_config_.measuring_mode(),
                                 device_config_.real_time_indices()};
  LaserScan scan;
  Lms200BeamCounts beams;
  if (!DecodeScanReply(frame, decode, &values, &error) ||
      !ToLaserScan(values, decode.measuring_mode, &scan, &beams, &error)) {
    Count("decode_errors");
    MOSTAR_LOG_EVERY_SEC(WARNING, 5) << "LMS200: undecodable scan: " << error;
    return;
  }
  if (values.telegram_index) {
    if (last_telegram_index_) {
      const uint8_t gap = static_cast<uint8_t>(*values.telegram_index - *last_telegram_index_ - 1);
      if (gap > 0) Count("lost_scans", gap);
    }
    last_telegram_index_ = values.telegram_index;
  }
  const Lms200Variant variant =
      VariantFromValueCount(values.count).value_or(Lms200Variant{180, 100});
  const Duration sweep =
      FromSeconds(kLms200MirrorPeriodS * ((variant.revolutions() - 1) + variant.angle_deg / 360.0));
  scan.stamp = event.arrival - WireTime(frame.wire_bytes(), stream_->baud_rate()) - sweep;
  scan.sequence = sequence_++;
  scan.scan_time_s = static_cast<float>(ToSeconds(ExpectedScanPeriod()));
  last_scan_ = clock_->SteadyNow();
  Count("scans");
  if (beams.invalid() > 0) Count("invalid_beams", beams.invalid());
  for (int code = 1; code < kLms200BeamCodeCount; ++code) {  // every code but a range
    if (beams.by_code[code] == 0) continue;
    const std::string name =
        std::string("beams_") + BeamCodeName(static_cast<Lms200BeamCode>(code));
    Count(name.c_str(), beams.by_code[code]);
  }
  if (values.status.pollution()) Count("pollution_scans");
  if (values.status.is_error()) Count("error_status_scans");
  {
    std::lock_guard<std::mutex> lock(health_mutex_);
    rate_.Tick(last_scan_);
    if (values.status.pollution() || values.status.severity() >= 2) {
      health_state_ = values.status.is_error() ? DeviceState::kError : DeviceState::kWarn;
      health_message_ = values.status.pollution() ? "front screen polluted"
                                                  : "scanner reports status severity " +
                                                        std::to_string(values.status.severity());
    } else {
      health_state_ = DeviceState::kOk;
      health_message_ = "streaming at " + std::to_string(stream_->baud_rate()) + " Bd";
    }
  }
  if (on_scan) on_scan(scan);
}

void Lms200Session::StepStreaming(const ScanCallback& on_scan) {
  std::string error;
  if (!Pump(clock_->SteadyNow() + std::chrono::milliseconds(50), &error,
            options_.streaming_idle_gap)) {
    if (!cancel_.load()) LostPort(error);
    return;
  }
  while (!pending_.empty()) {
    TimedEvent event = std::move(pending_.front());
    pending_.pop_front();
    if (event.event.type == FramerEventType::kFrame && event.event.frame.command() == kReplyScan) {
      HandleScanFrame(event, on_scan);
    }
  }
  if (clock_->SteadyNow() - last_scan_ > WatchdogTimeout()) {
    Count("watchdog_restarts");
    MOSTAR_LOG(WARNING) << "LMS200: no scan for " << ToSeconds(WatchdogTimeout())
                        << " s, restarting the link";
    SetMessage(DeviceState::kWarn, "no scans; restarting the link");
    std::string ignored;
    const std::vector<uint8_t> stop =
        StopContinuousRequest(static_cast<uint8_t>(config_.address()));
    stream_->Write(stop.data(), stop.size(), &ignored);
    stream_->Flush();
    framer_.Reset();
    pending_.clear();
    state_ = stream_->IsOpen() ? State::kDetecting : State::kClosed;
  }
}

void Lms200Session::Step(const ScanCallback& on_scan) {
  switch (state_.load()) {
    case State::kClosed: {
      std::string error;
      if (!stream_->Reopen(&error)) {
        Count("open_failures");
        if (!announced_missing_port_) {
          MOSTAR_LOG(WARNING) << "LMS200: " << error << "; retrying";
          announced_missing_port_ = true;
        }
        SetMessage(DeviceState::kError, error);
        Sleep(options_.reopen_interval);
        return;
      }
      announced_missing_port_ = false;
      framer_.Reset();
      pending_.clear();
      state_ = State::kDetecting;
      return;
    }
    case State::kDetecting: {
      std::string error;
      if (StartUp(&error)) {
        state_ = State::kStreaming;
        SetMessage(DeviceState::kOk, "streaming at " + std::to_string(stream_->baud_rate()) +
                                         " Bd" + (device_type_.empty() ? "" : ", " + device_type_));
        MOSTAR_LOG(INFO) << "LMS200 " << stream_->name() << ": streaming at "
                         << stream_->baud_rate() << " Bd (" << device_type_ << ")";
        return;
      }
      if (cancel_.load()) return;
      if (!stream_->IsOpen()) {
        LostPort(error);
        return;
      }
      Count("startup_failures");
      MOSTAR_LOG_EVERY_SEC(WARNING, 5) << "LMS200 start-up failed: " << error;
      SetMessage(DeviceState::kWarn, "start-up failed: " + error);
      Sleep(options_.retry_pause);
      return;
    }
    case State::kStreaming:
      StepStreaming(on_scan);
      return;
  }
}

void Lms200Session::Shutdown() {
  if (stream_->IsOpen()) {
    std::string ignored;
    const std::vector<uint8_t> stop =
        StopContinuousRequest(static_cast<uint8_t>(config_.address()));
    stream_->Write(stop.data(), stop.size(), &ignored);
    stream_->Close();
  }
  state_ = State::kClosed;
  SetMessage(DeviceState::kOff, "stopped");
}

}  // namespace mostar::laser
