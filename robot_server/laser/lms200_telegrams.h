// LMS2xx request builders and reply decoders (SICK Telegram Listing LMS2xx, firmware V02.30).
//
// Pure functions: bytes in, typed values out. Every multi-byte field is read explicitly as
// little endian; decoders check the reply code and the length before touching a field and
// return false with a message naming the problem (they never read out of bounds).
//
// Geometry of a scan: the LMS numbers beams by ascending angle with 0 deg = right, 90 deg =
// ahead, 180 deg = left. mostar's laser frame is REP-103 (x ahead, y left, angles CCW with
// 0 = ahead), so beam i of a scan with field of view F and resolution r is at
// -F/2 + i * r (a 180 deg scan spans -90 deg .. +90 deg).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/types/laser_scan.h"
#include "robot_server/laser/lms200_framer.h"

namespace mostar::laser {

// Request codes and their replies (reply = request + 0x80, except reset).
enum Lms200Command : uint8_t {
  kCmdReset = 0x10,
  kCmdMode = 0x20,
  kCmdPollScan = 0x30,
  kCmdStatus = 0x31,
  kCmdErrors = 0x32,
  kCmdType = 0x3A,
  kCmdVariant = 0x3B,
  kCmdReadConfig = 0x74,
  kCmdWriteConfig = 0x77,
  kReplyResetAck = 0x91,
  kReplyPowerOn = 0x90,
  kReplyRejected = 0x92,  // "not acknowledge, incorrect command" (a telegram, not a NAK byte)
  kReplyMode = 0xA0,
  kReplyScan = 0xB0,
  kReplyStatus = 0xB1,
  kReplyErrors = 0xB2,
  kReplyType = 0xBA,
  kReplyVariant = 0xBB,
  kReplyReadConfig = 0xF4,
  kReplyWriteConfig = 0xF7,
};

// Sub-codes of request 0x20 (operating mode).
enum Lms200Mode : uint8_t {
  kModeInstallation = 0x00,  // followed by an 8-byte password
  kModeContinuous = 0x24,    // continuous output of all values (B0 stream)
  kModeOnRequest = 0x25,     // values only on request; stops a continuous stream
  kModeBaud38400 = 0x40,
  kModeBaud19200 = 0x41,
  kModeBaud9600 = 0x42,
  kModeBaud500000 = 0x48,  // RS-422 only
};

enum class Lms200Unit : uint8_t { kCm = 0, kMm = 1 };
double UnitMetres(Lms200Unit unit);

// Angular field of view and resolution. Valid: 180x100, 180x50, 100x100, 100x50, 100x25.
struct Lms200Variant {
  int angle_deg = 180;
  int resolution_cdeg = 100;  // unit: 1/100 degree
  bool IsValid() const;
  int values() const { return angle_deg * 100 / resolution_cdeg + 1; }
  // Mirror revolutions (13.32 ms each) needed for one complete scan: 1, 2 or 4.
  int revolutions() const { return 100 / resolution_cdeg; }
  bool operator==(const Lms200Variant& o) const {
    return angle_deg == o.angle_deg && resolution_cdeg == o.resolution_cdeg;
  }
  bool operator!=(const Lms200Variant& o) const { return !(*this == o); }
};
// The variant implied by a number of values (181, 361, 101, 201, 401), if any.
std::optional<Lms200Variant> VariantFromValueCount(int count);

// Mirror revolution period: 13.32 ms (75 Hz).
constexpr double kLms200MirrorPeriodS = 0.01332;

// Baud code of request 20 xx; nullopt for rates the LMS does not support.
std::optional<uint8_t> BaudModeCode(int baud);
// Bits per byte on the wire (8N1).
constexpr int kLms200BitsPerByte = 10;

// Status byte of every reply (TL 8.1).
struct Lms200StatusByte {
  uint8_t raw = 0x10;
  int severity() const { return raw & 0x07; }  // 0 ok, 1 info, 2 warning, 3 error, 4 fatal
  bool is_error() const { return severity() >= 3; }
  bool implausible() const { return (raw & 0x40) != 0; }
  bool pollution() const { return (raw & 0x80) != 0; }  // dirty front screen
  bool restart_input() const { return (raw & 0x20) != 0; }
};

// The 34-byte configuration block of 0x74/0x77 (32 bytes on old firmware). Unknown bytes are
// preserved byte for byte when written back.
struct Lms200ConfigBlock {
  static constexpr size_t kSize = 34;
  static constexpr size_t kOldFirmwareSize = 32;
  std::vector<uint8_t> bytes = std::vector<uint8_t>(kSize, 0);

  bool real_time_indices() const { return (bytes[4] & 0x02) != 0; }  // block C bit 1
  uint8_t measuring_mode() const { return bytes[5]; }                // block D
  uint8_t unit_code() const { return bytes[6]; }                     // block E: 0 cm, 1 mm
  void set_real_time_indices(bool on);
  void set_measuring_mode(uint8_t mode) { bytes[5] = mode; }
  void set_unit(Lms200Unit unit) { bytes[6] = static_cast<uint8_t>(unit); }
  bool operator==(const Lms200ConfigBlock& o) const { return bytes == o.bytes; }
};

// Distance bits of a value word for a measuring mode (block D); 0 when the mode does not
// deliver distances (0x3F reflectivity) or is unknown.
uint16_t DistanceMask(uint8_t measuring_mode);
// Width of the flag field above the distance bits that carries a reflector level (modes 01,
// 03, 05); 0 when the flags are field/dazzle bits.
int ReflectorLevelBits(uint8_t measuring_mode);

// ---- Requests (complete telegrams, CRC included) ----
std::vector<uint8_t> BuildTelegram(uint8_t address, const std::vector<uint8_t>& payload);
// A reply telegram; `payload` holds reply code, data and status byte. Used by the emulator.
std::vector<uint8_t> BuildReplyTelegram(uint8_t reply_address, const std::vector<uint8_t>& payload);

std::vector<uint8_t> ResetRequest(uint8_t address = 0);
std::vector<uint8_t> StatusRequest(uint8_t address = 0);
std::vector<uint8_t> ErrorRequest(uint8_t address = 0);
std::vector<uint8_t> TypeRequest(uint8_t address = 0);
std::vector<uint8_t> ReadConfigRequest(uint8_t address = 0);
std::vector<uint8_t> WriteConfigRequest(const Lms200ConfigBlock& block, uint8_t address = 0);
std::vector<uint8_t> VariantRequest(const Lms200Variant& variant, uint8_t address = 0);
std::vector<uint8_t> ModeRequest(uint8_t mode, uint8_t address = 0);
// Installation mode; the password is 8 ASCII characters ("SICK_LMS" by default), padded with
// spaces or cut to 8.
std::vector<uint8_t> InstallationModeRequest(const std::string& password, uint8_t address = 0);
std::vector<uint8_t> StartContinuousRequest(uint8_t address = 0);
std::vector<uint8_t> StopContinuousRequest(uint8_t address = 0);
std::vector<uint8_t> PollScanRequest(uint8_t address = 0);
// Empty when `baud` is not one of 9600, 19200, 38400, 500000.
std::vector<uint8_t> BaudRequest(int baud, uint8_t address = 0);

// ---- Replies ----
// True for a 0x92 "incorrect command" telegram.
bool IsRejection(const Lms200Frame& frame);

struct Lms200ModeReply {  // A0
  uint8_t result = 0;     // 0 = switched, otherwise refused (bad password, device fault)
  Lms200StatusByte status;
  bool ok() const { return result == 0; }
};
bool DecodeModeReply(const Lms200Frame& frame, Lms200ModeReply* out, std::string* error);

struct Lms200VariantReply {  // BB
  bool accepted = false;     // false: previous variant still active
  Lms200Variant variant;
  Lms200StatusByte status;
};
bool DecodeVariantReply(const Lms200Frame& frame, Lms200VariantReply* out, std::string* error);

// BA: ASCII type string, e.g. "LMS200;301063;V02.10 ".
bool DecodeTypeReply(const Lms200Frame& frame, std::string* type, std::string* error);

// F4: the configuration block (34 or 32 bytes).
bool DecodeConfigReply(const Lms200Frame& frame, Lms200ConfigBlock* out, std::string* error);
// F7: `accepted` = data byte 1 is 01; `block` = the configuration the LMS now holds.
bool DecodeConfigWriteReply(const Lms200Frame& frame, bool* accepted, Lms200ConfigBlock* block,
                            std::string* error);

// B1 status (offsets as the wire layout: index 0 = the B1 byte).
struct Lms200DeviceStatus {
  std::string software_version;  // ASCII, offsets 1..7
  uint8_t operating_mode = 0;    // offset 8
  uint8_t device_status = 0;     // offset 9: 0 ok
  uint8_t measuring_mode = 0;    // offset 102
  Lms200Variant variant;         // offsets 107..110
  int baud = 0;                  // offsets 116..117, 0 if unknown code
  bool permanent_baud = false;   // offset 119
  uint8_t address = 0;           // offset 120
  uint8_t unit_code = 0;         // offset 122: 0 cm, 1 mm
  Lms200StatusByte status;
};
constexpr size_t kLms200StatusDataBytes = 152;  // data bytes after B1 on the wire
bool DecodeStatusReply(const Lms200Frame& frame, Lms200DeviceStatus* out, std::string* error);
// The B1 baud word for a rate (0x8067 = 9600 ...), 0 when unknown. Used by the emulator.
uint16_t StatusBaudWord(int baud);

// B0 measured values, undecoded words.
struct Lms200ScanDecodeOptions {
  uint8_t measuring_mode = 0;      // from the configuration block (0x74), not from B0
  bool real_time_indices = false;  // configuration block C bit 1
};
struct Lms200MeasuredValues {
  int count = 0;                          // count word bits 0..9
  bool partial = false;                   // bit 13: interlaced partial scan
  int partial_raster = 0;                 // bits 11..12: 0 = x.00, 1 = x.25, 2 = x.50, 3 = x.75 deg
  Lms200Unit unit = Lms200Unit::kCm;      // bits 14..15
  std::vector<uint16_t> words;            // raw value words, `count` of them
  std::optional<uint8_t> scan_index;      // per mirror revolution, mod 256
  std::optional<uint8_t> telegram_index;  // per telegram, mod 256
  Lms200StatusByte status;
};
bool DecodeScanReply(const Lms200Frame& frame, const Lms200ScanDecodeOptions& options,
                     Lms200MeasuredValues* out, std::string* error);

// Meaning of one value word after masking (TL 10.8.1; same pattern for 14/15/16-bit modes),
// and how a scan carries it (REP 117): only "no echo" and "beyond range" say that nothing was
// hit up to the maximum range (free space, +Inf); every error code says that the beam measured
// nothing (unknown space, NaN), so an obstacle may hide behind it (docs/safety.md, G15).
enum class Lms200BeamCode : uint8_t {
  kRange = 0,
  kBeyondRange,   // mask - 8 (0x1FF7): value > maximum measurable distance -> +Inf
  kNoEcho,        // mask     (0x1FFF): no stop signal, nothing reflected in range -> +Inf
  kDazzle,        // mask - 1 (0x1FFE): dazzled (blinded by light) -> NaN
  kOverflow,      // mask - 2 (0x1FFD): operation overflow -> NaN
  kLowSignal,     // mask - 4 (0x1FFB): signal/noise ratio too small -> NaN
  kChannelError,  // mask - 5 (0x1FFA): channel 1 read error -> NaN
  kOtherError,    // other codes in mask-8 .. mask (undocumented) -> NaN
};
constexpr int kLms200BeamCodeCount = 8;
const char* BeamCodeName(Lms200BeamCode code);
Lms200BeamCode ClassifyValue(uint16_t distance, uint16_t mask);
// True for the codes that mean free space (kNoEcho, kBeyondRange): +Inf in a scan.
bool IsFreeSpaceCode(Lms200BeamCode code);

struct Lms200BeamCounts {
  uint64_t by_code[kLms200BeamCodeCount] = {};
  uint64_t invalid() const;  // error codes: every code but kRange, kBeyondRange and kNoEcho
};

// Fills ranges (metres; +Inf for "no echo" and "beyond range", NaN for the error codes), the
// angles (see the
// top of this file) and, for reflector-level modes, intensities (the level). Does not touch
// `stamp`, `sequence`, `scan_time_s`. Partial (interlaced) scans are refused.
bool ToLaserScan(const Lms200MeasuredValues& values, uint8_t measuring_mode, LaserScan* scan,
                 Lms200BeamCounts* counts, std::string* error);

}  // namespace mostar::laser
