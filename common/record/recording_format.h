// The mostar recording format: byte layout, plain-data view of records, and the pieces shared
// by the writer, the reader and the tools. See docs/recording.md for the full description.
//
// Byte layout (all integers little-endian):
//   prelude   "MOSTARREC" (9 bytes) + uint32 format version              13 bytes
//   header    frame(proto::Header)
//   records   frame(proto::Record) ...   data records and periodic index records
//   footer    frame(proto::Record{index{footer: true}})           written by Close() only
//   trailer   uint64 offset of the footer frame + "MOSTRIDX"      16 bytes, Close() only
// where frame(m) = varint length of m's bytes + m's bytes + uint32 CRC-32 (IEEE) of m's bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "common/time/time.h"
#include "common/types/bumper.h"
#include "common/types/commands.h"
#include "common/types/health.h"
#include "common/types/laser_scan.h"
#include "common/types/odometry.h"
#include "common/types/sonar.h"
#include "common/types/stereo_frame.h"

namespace mostar::record {

// Version written by this library. Readers accept versions 1..kFormatVersion and refuse newer.
inline constexpr uint32_t kFormatVersion = 1;
inline constexpr char kMagic[] = "MOSTARREC";  // 9 bytes on disk, no terminating NUL
inline constexpr size_t kMagicSize = 9;
inline constexpr size_t kPreludeSize = kMagicSize + 4;
inline constexpr char kTrailerMagic[] = "MOSTRIDX";  // 8 bytes on disk
inline constexpr size_t kTrailerSize = 16;
// Larger length prefixes are treated as corruption (a JPEG eye is far smaller).
inline constexpr uint64_t kMaxRecordBytes = 64ull << 20;
// Length prefix (at most 10 bytes) + CRC.
inline constexpr size_t kMaxFrameOverheadBytes = 10 + 4;

// CRC-32 (IEEE 802.3, reflected, as zlib's crc32). `crc` continues a previous computation.
uint32_t Crc32(const void* data, size_t size, uint32_t crc = 0);

// Appends frame(bytes) = varint length + bytes + CRC-32 to `out`.
void AppendFrame(const std::string& bytes, std::string* out);

// Reads a varint from data[0..size). Returns the number of bytes used, 0 if `size` ends
// before the varint does, -1 if it is longer than 10 bytes (corrupt).
int ParseVarint(const uint8_t* data, size_t size, uint64_t* value);

// The sensors the recording saw; zero = unknown.
struct SensorDescription {
  float laser_angle_min_rad = 0.f;
  float laser_angle_increment_rad = 0.f;
  uint32_t laser_beam_count = 0;
  float laser_range_max_m = 0.f;
  float laser_scan_rate_hz = 0.f;
  uint32_t camera_width_px = 0;
  uint32_t camera_height_px = 0;
  float camera_frame_rate_hz = 0.f;
  std::string camera_format;  // "jpeg"
};

// Content of the file header.
struct RecordingInfo {
  uint32_t format_version = kFormatVersion;  // set by the reader; the writer always writes its own
  Time creation_time;                        // zero: the writer fills in its clock's Now()
  std::string robot_id;
  SensorDescription sensors;
  std::string calibration_text;  // calibration in force, protobuf text; opaque here
  std::vector<std::pair<std::string, std::string>> metadata;
};

// One eye as recorded.
struct RecordedImage {
  Eye eye = Eye::kLeft;
  uint64_t pair_sequence = 0;  // CompressedStereoPair::sequence when recorded as a pair, else 0
  CompressedImage image;
};

// The kinds of data record, in the order of RecordPayload's alternatives.
enum class RecordKind : uint8_t {
  kImage = 0,
  kScan = 1,
  kOdometry = 2,
  kVelocityCommand = 3,
  kEmergencyStop = 4,
  kControlRequest = 5,
  kControlLease = 6,
  kHealth = 7,
  kSonar = 8,
  kBumpers = 9,
};
inline constexpr size_t kRecordKindCount = 10;

using RecordPayload =
    std::variant<RecordedImage, LaserScan, Odometry, VelocityCommand, EmergencyStop, ControlRequest,
                 ControlLease, RobotHealth, SonarRanges, BumperState>;

// One data record. `offset` and `size_bytes` are set by the reader (ignored by the writer).
struct RecordedMessage {
  Time log_time;  // when the recorder received it (recorder's wall clock); replay is paced by it
  RecordPayload payload;
  uint64_t offset = 0;      // byte offset of the record's frame in the file
  uint64_t size_bytes = 0;  // frame size: length prefix + record + CRC

  RecordKind kind() const { return static_cast<RecordKind>(payload.index()); }
};

// Topic of a record, as the ROS topic name without the "mostar/" prefix: "camera/left",
// "camera/right", "scan", "odom", "cmd_vel", "estop", "control/request", "control/lease",
// "health", "sonar", "bumpers".
std::string TopicName(const RecordedMessage& message);

// Where and why a file stops being readable.
struct RecordDamage {
  uint64_t offset = 0;  // byte offset of the first frame that could not be read
  std::string reason;
};

// A time -> byte offset entry of the index.
struct IndexEntry {
  Time log_time;
  uint64_t offset = 0;
};

// A source of records in file order: the reader, or anything standing in for it in tests.
class RecordStream {
 public:
  virtual ~RecordStream() = default;
  // The next data record; false at the end (or at damage, for a file).
  virtual bool Next(RecordedMessage* message) = 0;
  // Positions the stream so that Next() returns the first record, in file order, whose
  // log_time >= t (Time::min() = the beginning). False if no such record exists.
  virtual bool SeekToTime(Time t) = 0;
};

}  // namespace mostar::record
