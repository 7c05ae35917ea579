// Reads a recording file (format: recording_format.h, docs/recording.md).
//
// Robustness contract: a truncated or corrupted file (bad length prefix, CRC mismatch, record
// that does not parse) never crashes or hangs the reader: Next() delivers every record before
// the damage, then returns false and damage() gives the byte offset of the first unreadable
// frame and the reason. Records of a payload type this reader does not know (written by a newer
// writer of the same format version) are skipped and counted.
//
// Seeking uses the footer index when the file was closed cleanly; otherwise the index is rebuilt
// once by a light scan that reads each frame's length prefix and the record's log time only
// (payloads are skipped, CRCs are checked later by Next()).
//
// Not thread-safe: one reader per thread (open the file several times for several consumers).
// The file must not grow while it is read.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/record/recording_format.h"

namespace mostar::record {

class RecordingReader final : public RecordStream {
 public:
  // Opens `path` and checks the prelude and header. Null with a message naming the file on
  // failure: missing file, not a recording (wrong magic), a newer format version (the message
  // names both versions), truncated or corrupted header.
  static std::unique_ptr<RecordingReader> Open(const std::string& path, std::string* error);

  RecordingReader(const RecordingReader&) = delete;
  RecordingReader& operator=(const RecordingReader&) = delete;
  ~RecordingReader() override;

  const std::string& path() const { return path_; }
  const RecordingInfo& info() const { return info_; }
  uint64_t file_size_bytes() const { return file_size_; }
  // Offset of the first record (after prelude and header).
  uint64_t data_begin() const { return data_begin_; }
  // True when the file was closed cleanly (footer index and trailer present and valid).
  bool has_footer() const { return has_footer_; }

  // RecordStream. Next(): the next data record in file order (index records are skipped).
  bool Next(RecordedMessage* message) override;
  // Uses the index (footer, else rebuilt by a light scan) then reads forward. Clears damage()
  // (it is found again if reading reaches it).
  bool SeekToTime(Time t) override;
  // Back to the first record; clears damage().
  void Rewind();

  // Set once Next() or SeekToTime() met damage; cleared by Rewind()/SeekToTime().
  const std::optional<RecordDamage>& damage() const { return damage_; }
  // Index entries (non-decreasing log times), from the footer or rebuilt on first use.
  const std::vector<IndexEntry>& index();
  // Counts since Open.
  uint64_t index_records_seen() const { return index_records_seen_; }
  uint64_t unknown_records_skipped() const { return unknown_records_skipped_; }

 private:
  enum class FrameStatus { kOk, kEnd, kDamage };

  RecordingReader(std::string path, int fd, uint64_t file_size);
  bool OpenHeader(std::string* error);
  void FindFooter();
  // Reads the frame at `offset` (bounded by data_end_): its record bytes and total size.
  FrameStatus ReadFrame(uint64_t offset, std::string* record_bytes, uint64_t* frame_size,
                        RecordDamage* damage) const;
  // Reads up to `size` bytes at `offset`; returns the number read (short at end of file).
  size_t ReadAt(uint64_t offset, size_t size, char* out) const;
  void RebuildIndex();

  const std::string path_;
  int fd_;
  const uint64_t file_size_;
  RecordingInfo info_;
  uint64_t data_begin_ = 0;
  uint64_t data_end_ = 0;  // footer offset with a footer, else the file size
  bool has_footer_ = false;
  bool index_ready_ = false;
  std::vector<IndexEntry> index_;

  uint64_t position_ = 0;
  std::optional<RecordedMessage> pending_;  // found by SeekToTime, returned by the next Next()
  std::optional<RecordDamage> damage_;
  uint64_t index_records_seen_ = 0;
  uint64_t unknown_records_skipped_ = 0;
};

}  // namespace mostar::record
