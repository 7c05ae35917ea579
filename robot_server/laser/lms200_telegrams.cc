#include "robot_server/laser/lms200_telegrams.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "robot_server/laser/lms200_crc.h"

namespace mostar::laser {
namespace {

constexpr double kPi = 3.14159265358979323846;

uint16_t ReadU16(const std::vector<uint8_t>& bytes, size_t offset) {
  return static_cast<uint16_t>(bytes[offset] | (static_cast<uint16_t>(bytes[offset + 1]) << 8));
}

void AppendU16(uint16_t value, std::vector<uint8_t>* out) {
  out->push_back(static_cast<uint8_t>(value & 0xFF));
  out->push_back(static_cast<uint8_t>(value >> 8));
}

std::string Hex(uint8_t value) {
  static const char kDigits[] = "0123456789ABCDEF";
  return std::string("0x") + kDigits[value >> 4] + kDigits[value & 0xF];
}

// Checks the reply code and that at least `min_payload` bytes (code .. status) are present.
bool CheckReply(const Lms200Frame& frame, uint8_t code, size_t min_payload, std::string* error) {
  if (frame.payload.empty() || frame.payload[0] != code) {
    if (error) {
      *error = "expected reply " + Hex(code) + ", got " +
               (frame.payload.empty() ? std::string("an empty telegram") : Hex(frame.command()));
    }
    return false;
  }
  if (frame.payload.size() < min_payload) {
    if (error) {
      std::ostringstream s;
      s << "reply " << Hex(code) << " has " << frame.payload.size() << " bytes, need at least "
        << min_payload;
      *error = s.str();
    }
    return false;
  }
  return true;
}

Lms200StatusByte StatusOf(const Lms200Frame& frame) {
  Lms200StatusByte status;
  status.raw = frame.payload.back();
  return status;
}

}  // namespace

double UnitMetres(Lms200Unit unit) { return unit == Lms200Unit::kMm ? 0.001 : 0.01; }

bool Lms200Variant::IsValid() const {
  if (angle_deg == 180) return resolution_cdeg == 100 || resolution_cdeg == 50;
  if (angle_deg == 100) {
    return resolution_cdeg == 100 || resolution_cdeg == 50 || resolution_cdeg == 25;
  }
  return false;
}

std::optional<Lms200Variant> VariantFromValueCount(int count) {
  switch (count) {
    case 181:
      return Lms200Variant{180, 100};
    case 361:
      return Lms200Variant{180, 50};
    case 101:
      return Lms200Variant{100, 100};
    case 201:
      return Lms200Variant{100, 50};
    case 401:
      return Lms200Variant{100, 25};
    default:
      return std::nullopt;
  }
}

std::optional<uint8_t> BaudModeCode(int baud) {
  switch (baud) {
    case 9600:
      return kModeBaud9600;
    case 19200:
      return kModeBaud19200;
    case 38400:
      return kModeBaud38400;
    case 500000:
      return kModeBaud500000;
    default:
      return std::nullopt;
  }
}

void Lms200ConfigBlock::set_real_time_indices(bool on) {
  bytes[4] = static_cast<uint8_t>(on ? (bytes[4] | 0x02) : (bytes[4] & ~0x02));
}

uint16_t DistanceMask(uint8_t measuring_mode) {
  switch (measuring_mode) {
    case 0x00:
    case 0x01:
    case 0x02:
      return 0x1FFF;
    case 0x03:
    case 0x04:
      return 0x3FFF;
    case 0x05:
    case 0x06:
      return 0x7FFF;
    case 0x0F:
      return 0xFFFF;
    default:
      return 0;
  }
}

int ReflectorLevelBits(uint8_t measuring_mode) {
  switch (measuring_mode) {
    case 0x01:
      return 3;
    case 0x03:
      return 2;
    case 0x05:
      return 1;
    default:
      return 0;
  }
}

std::vector<uint8_t> BuildTelegram(uint8_t address, const std::vector<uint8_t>& payload) {
  std::vector<uint8_t> out;
  out.reserve(payload.size() + kLms200FrameOverheadBytes);
  out.push_back(kLms200Stx);
  out.push_back(address);
  AppendU16(static_cast<uint16_t>(payload.size()), &out);
  out.insert(out.end(), payload.begin(), payload.end());
  AppendU16(Lms200Crc(out.data(), out.size()), &out);
  return out;
}

std::vector<uint8_t> BuildReplyTelegram(uint8_t reply_address,
                                        const std::vector<uint8_t>& payload) {
  return BuildTelegram(reply_address, payload);
}

std::vector<uint8_t> ResetRequest(uint8_t address) { return BuildTelegram(address, {kCmdReset}); }
std::vector<uint8_t> StatusRequest(uint8_t address) { return BuildTelegram(address, {kCmdStatus}); }
std::vector<uint8_t> ErrorRequest(uint8_t address) { return BuildTelegram(address, {kCmdErrors}); }
std::vector<uint8_t> TypeRequest(uint8_t address) { return BuildTelegram(address, {kCmdType}); }
std::vector<uint8_t> ReadConfigRequest(uint8_t address) {
  return BuildTelegram(address, {kCmdReadConfig});
}
std::vector<uint8_t> WriteConfigRequest(const Lms200ConfigBlock& block, uint8_t address) {
  std::vector<uint8_t> payload{kCmdWriteConfig};
  payload.insert(payload.end(), block.bytes.begin(), block.bytes.end());
  return BuildTelegram(address, payload);
}
std::vector<uint8_t> VariantRequest(const Lms200Variant& variant, uint8_t address) {
  std::vector<uint8_t> payload{kCmdVariant};
  AppendU16(static_cast<uint16_t>(variant.angle_deg), &payload);
  AppendU16(static_cast<uint16_t>(variant.resolution_cdeg), &payload);
  return BuildTelegram(address, payload);
}
std::vector<uint8_t> ModeRequest(uint8_t mode, uint8_t address) {
  return BuildTelegram(address, {kCmdMode, mode});
}
std::vector<uint8_t> InstallationModeRequest(const std::string& password, uint8_t address) {
  std::vector<uint8_t> payload{kCmdMode, kModeInstallation};
  for (size_t i = 0; i < 8; ++i) {
    payload.push_back(static_cast<uint8_t>(i < password.size() ? password[i] : ' '));
  }
  return BuildTelegram(address, payload);
}
std::vector<uint8_t> StartContinuousRequest(uint8_t address) {
  return ModeRequest(kModeContinuous, address);
}
std::vector<uint8_t> StopContinuousRequest(uint8_t address) {
  return ModeRequest(kModeOnRequest, address);
}
std::vector<uint8_t> PollScanRequest(uint8_t address) {
  return BuildTelegram(address, {kCmdPollScan, 0x01});
}
std::vector<uint8_t> BaudRequest(int baud, uint8_t address) {
  const std::optional<uint8_t> code = BaudModeCode(baud);
  if (!code) return {};
  return ModeRequest(*code, address);
}

bool IsRejection(const Lms200Frame& frame) { return frame.command() == kReplyRejected; }

bool DecodeModeReply(const Lms200Frame& frame, Lms200ModeReply* out, std::string* error) {
  if (!CheckReply(frame, kReplyMode, 3, error)) return false;
  out->result = frame.payload[1];
  out->status = StatusOf(frame);
  return true;
}

bool DecodeVariantReply(const Lms200Frame& frame, Lms200VariantReply* out, std::string* error) {
  if (!CheckReply(frame, kReplyVariant, 7, error)) return false;
  out->accepted = frame.payload[1] == 0x01;
  out->variant.angle_deg = ReadU16(frame.payload, 2);
  out->variant.resolution_cdeg = ReadU16(frame.payload, 4);
  out->status = StatusOf(frame);
  return true;
}

bool DecodeTypeReply(const Lms200Frame& frame, std::string* type, std::string* error) {
  if (!CheckReply(frame, kReplyType, 2, error)) return false;
  type->assign(frame.payload.begin() + 1, frame.payload.end() - 1);
  return true;
}

namespace {
bool ExtractConfigBlock(const Lms200Frame& frame, size_t offset, Lms200ConfigBlock* block,
                        std::string* error) {
  // offset = first block byte; the status byte follows the block.
  const size_t block_bytes = frame.payload.size() - offset - 1;
  if (block_bytes != Lms200ConfigBlock::kSize &&
      block_bytes != Lms200ConfigBlock::kOldFirmwareSize) {
    if (error) {
      std::ostringstream s;
      s << "configuration block has " << block_bytes << " bytes, expected 34 or 32";
      *error = s.str();
    }
    return false;
  }
  block->bytes.assign(frame.payload.begin() + static_cast<std::ptrdiff_t>(offset),
                      frame.payload.begin() + static_cast<std::ptrdiff_t>(offset + block_bytes));
  return true;
}
}  // namespace

bool DecodeConfigReply(const Lms200Frame& frame, Lms200ConfigBlock* out, std::string* error) {
  if (!CheckReply(frame, kReplyReadConfig, 2 + Lms200ConfigBlock::kOldFirmwareSize, error)) {
    return false;
  }
  return ExtractConfigBlock(frame, 1, out, error);
}

bool DecodeConfigWriteReply(const Lms200Frame& frame, bool* accepted, Lms200ConfigBlock* block,
                            std::string* error) {
  if (!CheckReply(frame, kReplyWriteConfig, 3 + Lms200ConfigBlock::kOldFirmwareSize, error)) {
    return false;
  }
  *accepted = frame.payload[1] == 0x01;
  return ExtractConfigBlock(frame, 2, block, error);
}

uint16_t StatusBaudWord(int baud) {
  switch (baud) {
    case 9600:
      return 0x8067;
    case 19200:
      return 0x8033;
    case 38400:
      return 0x8019;
    case 500000:
      return 0x8001;
    default:
      return 0;
  }
}

bool DecodeStatusReply(const Lms200Frame& frame, Lms200DeviceStatus* out, std::string* error) {
  // The fields used here end at offset 122; the wire layout has 152 data bytes.
  if (!CheckReply(frame, kReplyStatus, 124, error)) return false;
  const std::vector<uint8_t>& p = frame.payload;
  out->software_version.clear();
  for (size_t i = 1; i <= 7; ++i) {
    if (p[i] != 0) out->software_version.push_back(static_cast<char>(p[i]));
  }
  out->operating_mode = p[8];
  out->device_status = p[9];
  out->measuring_mode = p[102];
  out->variant.angle_deg = ReadU16(p, 107);
  out->variant.resolution_cdeg = ReadU16(p, 109);
  switch (ReadU16(p, 116)) {
    case 0x8067:
      out->baud = 9600;
      break;
    case 0x8033:
      out->baud = 19200;
      break;
    case 0x8019:
      out->baud = 38400;
      break;
    case 0x8001:
      out->baud = 500000;
      break;
    default:
      out->baud = 0;
  }
  out->permanent_baud = p[119] != 0;
  out->address = p[120];
  out->unit_code = p[122];
  out->status = StatusOf(frame);
  return true;
}

bool DecodeScanReply(const Lms200Frame& frame, const Lms200ScanDecodeOptions& options,
                     Lms200MeasuredValues* out, std::string* error) {
  if (!CheckReply(frame, kReplyScan, 4, error)) return false;
  const std::vector<uint8_t>& p = frame.payload;
  const uint16_t count_word = ReadU16(p, 1);
  out->count = count_word & 0x03FF;
  out->partial_raster = (count_word >> 11) & 0x3;
  out->partial = ((count_word >> 13) & 0x1) != 0;
  const int unit_bits = count_word >> 14;
  if (unit_bits > 1) {
    if (error) *error = "B0 count word has the reserved unit code " + std::to_string(unit_bits);
    return false;
  }
  out->unit = unit_bits == 1 ? Lms200Unit::kMm : Lms200Unit::kCm;
  const size_t index_bytes = options.real_time_indices ? 2 : 0;
  // B0, count word, values, [indices], status.
  const size_t expected = 3 + 2 * static_cast<size_t>(out->count) + index_bytes + 1;
  if (p.size() != expected) {
    if (error) {
      std::ostringstream s;
      s << "B0 with " << out->count << " values" << (index_bytes ? " and indices" : "") << " needs "
        << expected << " bytes, telegram has " << p.size();
      *error = s.str();
    }
    return false;
  }
  out->words.resize(static_cast<size_t>(out->count));
  for (size_t i = 0; i < out->words.size(); ++i) out->words[i] = ReadU16(p, 3 + 2 * i);
  if (index_bytes) {
    out->scan_index = p[p.size() - 3];
    out->telegram_index = p[p.size() - 2];
  } else {
    out->scan_index.reset();
    out->telegram_index.reset();
  }
  out->status = StatusOf(frame);
  return true;
}

const char* BeamCodeName(Lms200BeamCode code) {
  switch (code) {
    case Lms200BeamCode::kRange:
      return "range";
    case Lms200BeamCode::kBeyondRange:
      return "beyond_range";
    case Lms200BeamCode::kNoEcho:
      return "no_echo";
    case Lms200BeamCode::kDazzle:
      return "dazzle";
    case Lms200BeamCode::kOverflow:
      return "overflow";
    case Lms200BeamCode::kLowSignal:
      return "low_signal";
    case Lms200BeamCode::kChannelError:
      return "channel_error";
    case Lms200BeamCode::kOtherError:
      return "other_error";
  }
  return "?";
}

Lms200BeamCode ClassifyValue(uint16_t distance, uint16_t mask) {
  if (distance < mask - 8) return Lms200BeamCode::kRange;
  switch (mask - distance) {
    case 8:
      return Lms200BeamCode::kBeyondRange;
    case 0:
      return Lms200BeamCode::kNoEcho;
    case 1:
      return Lms200BeamCode::kDazzle;
    case 2:
      return Lms200BeamCode::kOverflow;
    case 4:
      return Lms200BeamCode::kLowSignal;
    case 5:
      return Lms200BeamCode::kChannelError;
    default:
      return Lms200BeamCode::kOtherError;
  }
}

bool IsFreeSpaceCode(Lms200BeamCode code) {
  return code == Lms200BeamCode::kNoEcho || code == Lms200BeamCode::kBeyondRange;
}

uint64_t Lms200BeamCounts::invalid() const {
  uint64_t total = 0;
  for (int i = 0; i < kLms200BeamCodeCount; ++i) {
    const auto code = static_cast<Lms200BeamCode>(i);
    if (code != Lms200BeamCode::kRange && !IsFreeSpaceCode(code)) total += by_code[i];
  }
  return total;
}

bool ToLaserScan(const Lms200MeasuredValues& values, uint8_t measuring_mode, LaserScan* scan,
                 Lms200BeamCounts* counts, std::string* error) {
  const uint16_t mask = DistanceMask(measuring_mode);
  if (mask == 0) {
    if (error) *error = "measuring mode " + Hex(measuring_mode) + " does not deliver distances";
    return false;
  }
  if (values.partial) {
    if (error) *error = "partial (interlaced) scans are not supported";
    return false;
  }
  const std::optional<Lms200Variant> variant = VariantFromValueCount(values.count);
  if (!variant) {
    if (error) *error = "no scan variant has " + std::to_string(values.count) + " values";
    return false;
  }
  const double unit_m = UnitMetres(values.unit);
  const double resolution_rad = variant->resolution_cdeg * 0.01 * kPi / 180.0;
  scan->angle_min_rad = static_cast<float>(-variant->angle_deg * 0.5 * kPi / 180.0);
  scan->angle_increment_rad = static_cast<float>(resolution_rad);
  // One mirror revolution sweeps 360 deg in 13.32 ms.
  scan->time_increment_s =
      static_cast<float>(kLms200MirrorPeriodS * variant->resolution_cdeg * 0.01 / 360.0);
  scan->range_min_m = static_cast<float>(unit_m);
  scan->range_max_m = static_cast<float>((mask - 9) * unit_m);
  const int level_bits = ReflectorLevelBits(measuring_mode);
  int distance_bits = 0;
  while (distance_bits < 16 && ((mask >> distance_bits) & 1u) != 0) ++distance_bits;
  scan->ranges_m.resize(values.words.size());
  scan->intensities.clear();
  if (level_bits > 0) scan->intensities.resize(values.words.size());
  for (size_t i = 0; i < values.words.size(); ++i) {
    const uint16_t distance = values.words[i] & mask;
    const Lms200BeamCode code = ClassifyValue(distance, mask);
    if (counts) ++counts->by_code[static_cast<int>(code)];
    float range = std::numeric_limits<float>::quiet_NaN();
    if (code == Lms200BeamCode::kRange) {
      range = static_cast<float>(distance * unit_m);
    } else if (IsFreeSpaceCode(code)) {
      range = std::numeric_limits<float>::infinity();
    }
    scan->ranges_m[i] = range;
    if (level_bits > 0) {
      scan->intensities[i] = static_cast<float>(values.words[i] >> distance_bits);
    }
  }
  return true;
}

}  // namespace mostar::laser
