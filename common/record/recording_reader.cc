#include "common/record/recording_reader.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <utility>

#include "common/record/record_conversions.h"
#include "common/record/recording.pb.h"

namespace mostar::record {
namespace {

// Granularity of an index rebuilt by scanning.
constexpr Duration kRebuiltIndexPeriod = std::chrono::seconds(1);
// Bytes read per frame by the light scan: length prefix + log time + payload tag.
constexpr size_t kLightScanBytes = 32;
constexpr int kIndexFieldNumber = 30;

uint32_t LoadLe32(const char* p) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<uint8_t>(p[i]);
  return v;
}

uint64_t LoadLe64(const char* p) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | static_cast<uint8_t>(p[i]);
  return v;
}

std::string Hex32(uint32_t v) {
  char text[16];
  std::snprintf(text, sizeof(text), "0x%08x", v);
  return text;
}

}  // namespace

std::unique_ptr<RecordingReader> RecordingReader::Open(const std::string& path,
                                                       std::string* error) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    *error = "cannot open recording " + path + ": " + std::strerror(errno);
    return nullptr;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    *error = "cannot open recording " + path + ": not a regular file";
    ::close(fd);
    return nullptr;
  }
  std::unique_ptr<RecordingReader> reader(
      new RecordingReader(path, fd, static_cast<uint64_t>(st.st_size)));
  if (!reader->OpenHeader(error)) return nullptr;
  reader->FindFooter();
  reader->position_ = reader->data_begin_;
  return reader;
}

RecordingReader::RecordingReader(std::string path, int fd, uint64_t file_size)
    : path_(std::move(path)), fd_(fd), file_size_(file_size), data_end_(file_size) {}

RecordingReader::~RecordingReader() { ::close(fd_); }

size_t RecordingReader::ReadAt(uint64_t offset, size_t size, char* out) const {
  size_t done = 0;
  while (done < size) {
    const ssize_t n = ::pread(fd_, out + done, size - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<size_t>(n);
  }
  return done;
}

bool RecordingReader::OpenHeader(std::string* error) {
  const std::string where = "recording " + path_ + ": ";
  if (file_size_ == 0) {
    *error = where + "the file is empty (not a mostar recording)";
    return false;
  }
  char prelude[kPreludeSize];
  const size_t n = ReadAt(0, kPreludeSize, prelude);
  const size_t magic_bytes = std::min(n, kMagicSize);
  if (std::memcmp(prelude, kMagic, magic_bytes) != 0) {
    *error = where + "not a mostar recording (wrong magic bytes)";
    return false;
  }
  if (n < kPreludeSize) {
    *error = where + "truncated in the prelude (" + std::to_string(n) + " bytes)";
    return false;
  }
  info_.format_version = LoadLe32(prelude + kMagicSize);
  if (info_.format_version == 0) {
    *error = where + "invalid format version 0";
    return false;
  }
  if (info_.format_version > kFormatVersion) {
    *error = where + "format version " + std::to_string(info_.format_version) +
             " is newer than this reader supports (version " + std::to_string(kFormatVersion) +
             "); update mostar to read it";
    return false;
  }
  std::string bytes;
  uint64_t frame_size = 0;
  RecordDamage damage;
  switch (ReadFrame(kPreludeSize, &bytes, &frame_size, &damage)) {
    case FrameStatus::kOk:
      break;
    case FrameStatus::kEnd:
      *error = where + "truncated: the header is missing";
      return false;
    case FrameStatus::kDamage:
      *error =
          where + "damaged header at byte " + std::to_string(damage.offset) + ": " + damage.reason;
      return false;
  }
  proto::Header header;
  if (!header.ParseFromString(bytes)) {
    *error = where + "the header does not parse";
    return false;
  }
  FromProto(header, &info_);
  data_begin_ = kPreludeSize + frame_size;
  return true;
}

void RecordingReader::FindFooter() {
  data_end_ = file_size_;
  if (file_size_ < data_begin_ + kTrailerSize) return;
  char trailer[kTrailerSize];
  if (ReadAt(file_size_ - kTrailerSize, kTrailerSize, trailer) != kTrailerSize) return;
  if (std::memcmp(trailer + 8, kTrailerMagic, 8) != 0) return;
  const uint64_t footer_offset = LoadLe64(trailer);
  const uint64_t trailer_offset = file_size_ - kTrailerSize;
  if (footer_offset < data_begin_ || footer_offset >= trailer_offset) return;
  data_end_ = trailer_offset;
  std::string bytes;
  uint64_t frame_size = 0;
  RecordDamage damage;
  proto::Record record;
  if (ReadFrame(footer_offset, &bytes, &frame_size, &damage) != FrameStatus::kOk ||
      footer_offset + frame_size != trailer_offset || !record.ParseFromString(bytes) ||
      !record.has_index() || !record.index().footer()) {
    data_end_ = file_size_;  // not a valid footer: read the whole file, rebuild the index
    return;
  }
  index_.clear();
  Time last = Time::min();
  for (const proto::IndexEntry& e : record.index().entries()) {
    const Time t = FromUnixNanos(e.log_time_unix_ns());
    if (e.offset() < data_begin_ || e.offset() >= footer_offset || t < last) {
      data_end_ = file_size_;  // inconsistent footer: do not trust it
      index_.clear();
      return;
    }
    last = t;
    index_.push_back(IndexEntry{t, e.offset()});
  }
  data_end_ = footer_offset;
  has_footer_ = true;
  index_ready_ = true;
}

RecordingReader::FrameStatus RecordingReader::ReadFrame(uint64_t offset, std::string* record_bytes,
                                                        uint64_t* frame_size,
                                                        RecordDamage* damage) const {
  if (offset >= data_end_) return FrameStatus::kEnd;
  damage->offset = offset;
  const uint64_t left = data_end_ - offset;
  char prefix[10];
  const size_t n = ReadAt(offset, static_cast<size_t>(std::min<uint64_t>(left, 10)), prefix);
  uint64_t length = 0;
  const int used = ParseVarint(reinterpret_cast<const uint8_t*>(prefix), n, &length);
  if (used == 0) {
    damage->reason = "truncated length prefix (" + std::to_string(left) + " bytes left)";
    return FrameStatus::kDamage;
  }
  if (used < 0) {
    damage->reason = "bad length prefix (longer than 10 bytes)";
    return FrameStatus::kDamage;
  }
  if (length == 0) {
    damage->reason = "bad length 0 (zeroed or overwritten region)";
    return FrameStatus::kDamage;
  }
  if (length > kMaxRecordBytes) {
    damage->reason =
        "bad length " + std::to_string(length) + " (limit " + std::to_string(kMaxRecordBytes) + ")";
    return FrameStatus::kDamage;
  }
  const uint64_t total = static_cast<uint64_t>(used) + length + 4;
  if (total > left) {
    damage->reason = "truncated record: " + std::to_string(total) + " bytes announced, " +
                     std::to_string(left) + " left in the file";
    return FrameStatus::kDamage;
  }
  std::string bytes(static_cast<size_t>(length) + 4, '\0');
  if (ReadAt(offset + static_cast<uint64_t>(used), bytes.size(), bytes.data()) != bytes.size()) {
    damage->reason = "read error";
    return FrameStatus::kDamage;
  }
  const uint32_t stored = LoadLe32(bytes.data() + length);
  const uint32_t computed = Crc32(bytes.data(), static_cast<size_t>(length));
  if (stored != computed) {
    damage->reason =
        "CRC mismatch (stored " + Hex32(stored) + ", computed " + Hex32(computed) + ")";
    return FrameStatus::kDamage;
  }
  bytes.resize(static_cast<size_t>(length));
  *record_bytes = std::move(bytes);
  *frame_size = total;
  return FrameStatus::kOk;
}

bool RecordingReader::Next(RecordedMessage* message) {
  if (pending_.has_value()) {
    *message = std::move(*pending_);
    pending_.reset();
    return true;
  }
  if (damage_.has_value()) return false;
  for (;;) {
    std::string bytes;
    uint64_t frame_size = 0;
    RecordDamage damage;
    switch (ReadFrame(position_, &bytes, &frame_size, &damage)) {
      case FrameStatus::kOk:
        break;
      case FrameStatus::kEnd:
        return false;
      case FrameStatus::kDamage:
        damage_ = std::move(damage);
        return false;
    }
    proto::Record record;
    if (!record.ParseFromString(bytes)) {
      damage_ = RecordDamage{position_, "record does not parse (its CRC is correct)"};
      return false;
    }
    const uint64_t offset = position_;
    position_ += frame_size;
    RecordedMessage decoded;
    switch (FromProto(record, &decoded)) {
      case FromProtoResult::kIndex:
        ++index_records_seen_;
        continue;
      case FromProtoResult::kUnknown:
        ++unknown_records_skipped_;
        continue;
      case FromProtoResult::kOk:
        break;
    }
    decoded.offset = offset;
    decoded.size_bytes = frame_size;
    *message = std::move(decoded);
    return true;
  }
}

void RecordingReader::Rewind() {
  pending_.reset();
  damage_.reset();
  position_ = data_begin_;
}

bool RecordingReader::SeekToTime(Time t) {
  const std::vector<IndexEntry>& entries = index();
  Rewind();
  auto after = std::upper_bound(entries.begin(), entries.end(), t,
                                [](Time value, const IndexEntry& e) { return value < e.log_time; });
  if (after != entries.begin()) position_ = std::prev(after)->offset;
  RecordedMessage message;
  while (Next(&message)) {
    if (message.log_time >= t) {
      pending_ = std::move(message);
      return true;
    }
  }
  return false;
}

const std::vector<IndexEntry>& RecordingReader::index() {
  if (!index_ready_) {
    RebuildIndex();
    index_ready_ = true;
  }
  return index_;
}

void RecordingReader::RebuildIndex() {
  index_.clear();
  bool have_entry = false;
  Time next_entry_time;
  uint64_t offset = data_begin_;
  while (offset < data_end_) {
    char head[kLightScanBytes];
    const size_t n = ReadAt(
        offset, static_cast<size_t>(std::min<uint64_t>(data_end_ - offset, kLightScanBytes)), head);
    const auto* p = reinterpret_cast<const uint8_t*>(head);
    uint64_t length = 0;
    const int used = ParseVarint(p, n, &length);
    if (used <= 0 || length == 0 || length > kMaxRecordBytes) break;
    const uint64_t total = static_cast<uint64_t>(used) + length + 4;
    if (total > data_end_ - offset) break;
    // Record prefix: tag of field 1 (varint), the log time, then the payload's tag.
    const size_t avail = std::min<size_t>(n - static_cast<size_t>(used), length);
    const uint8_t* q = p + used;
    uint64_t tag = 0;
    uint64_t log_time_ns = 0;
    uint64_t payload_tag = 0;
    int a = ParseVarint(q, avail, &tag);
    int b = a > 0 ? ParseVarint(q + a, avail - static_cast<size_t>(a), &log_time_ns) : 0;
    int c = b > 0 ? ParseVarint(q + a + b, avail - static_cast<size_t>(a + b), &payload_tag) : 0;
    if (a <= 0 || b <= 0 || tag != 0x08) {
      // Unusual layout: fall back to a full read of this frame.
      std::string bytes;
      uint64_t frame_size = 0;
      RecordDamage damage;
      proto::Record record;
      if (ReadFrame(offset, &bytes, &frame_size, &damage) != FrameStatus::kOk ||
          !record.ParseFromString(bytes)) {
        break;
      }
      log_time_ns = static_cast<uint64_t>(record.log_time_unix_ns());
      payload_tag = record.has_index() ? (kIndexFieldNumber << 3) : 0;
      c = 1;
    }
    const bool is_index = c > 0 && (payload_tag >> 3) == kIndexFieldNumber;
    if (!is_index) {
      const Time log_time = FromUnixNanos(static_cast<int64_t>(log_time_ns));
      if (!have_entry || log_time >= next_entry_time) {
        index_.push_back(IndexEntry{log_time, offset});
        next_entry_time = log_time + kRebuiltIndexPeriod;
        have_entry = true;
      }
    }
    offset += total;
  }
}

}  // namespace mostar::record
