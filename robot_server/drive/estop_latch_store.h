// The e-stop latch on disk: a robot_server restarted by the service watchdog, after a crash or a
// power loss comes back latched when the previous run ended with the e-stop engaged or did not
// stop cleanly (docs/safety.md, E1-E4).
//
// One text file, `<directory>/estop_latch`, replaced atomically on every change (a temporary
// file in the same directory, fsync, rename over the old one, fsync of the directory):
//   mostar-estop-latch 1
//   clean_stop 0|1     1 only when the run that wrote it stopped cleanly (RecordCleanStop)
//   engaged 0|1
//   engaged_by ID      who engaged it (printable ASCII without spaces, at most 64 bytes)
// Start() decides the latch of this run: no file (first start in this directory) or a clean stop
// with the latch released: unlatched; otherwise latched with the reason (engaged before the
// restart, unclean stop, file unreadable or corrupt, or this run cannot write the directory).
// Nothing here aborts on a bad file or directory: every failure latches and is reported.
// Thread-safe.
#pragma once

#include <cstdint>
#include <mutex>
#include <string>

#include "common/types/health.h"

namespace mostar::drive {

// The file's content.
struct EstopLatchFile {
  bool clean_stop = false;
  bool engaged = false;
  std::string engaged_by;
};
// Text of the file; `engaged_by` is sanitised (see above).
std::string FormatEstopLatchFile(const EstopLatchFile& file);
// False with the reason when `text` is not a complete file of the current version.
bool ParseEstopLatchFile(const std::string& text, EstopLatchFile* out, std::string* error);

// Replaces `path` by `contents` so that a crash at any point leaves either the old or the new
// file: writes `path`.tmp, fsyncs it, renames it over `path` and fsyncs the directory. False with
// the failing step and errno's text.
bool WriteFileAtomically(const std::string& path, const std::string& contents, std::string* error);

struct EstopLatchDecision {
  bool latched = false;
  std::string engaged_by;  // when latched: who engaged it before the restart, else ""
  std::string reason;      // when latched: why, for health and the log
};

class EstopLatchStore {
 public:
  static constexpr const char* kFileName = "estop_latch";
  static constexpr size_t kMaxFileBytes = 4096;  // a larger file is corrupt

  // `directory` must exist (systemd's StateDirectory=, or a test's temporary directory).
  explicit EstopLatchStore(std::string directory);
  EstopLatchStore(const EstopLatchStore&) = delete;
  EstopLatchStore& operator=(const EstopLatchStore&) = delete;

  // Reads what the previous run left and records this run as running (not stopped cleanly) with
  // the decided latch. Call once, before the others.
  EstopLatchDecision Start();
  // Records an engagement (true) or a release (false). False when the file could not be
  // written (counted, reported in Health()): the caller must then not release.
  bool Record(bool engaged, const std::string& engaged_by, std::string* error);
  // Records a clean stop with the latch as it is now; the next Start() is unlatched only if
  // `engaged` is false.
  bool RecordCleanStop(bool engaged, const std::string& engaged_by, std::string* error);

  // "estop_latch": the start decision in the message; WARN while the latch this run started
  // with is held, ERROR while the last write failed, else OK. Counters: writes, write_failures.
  DeviceHealth Health() const;
  const std::string& path() const { return path_; }

 private:
  bool WriteLocked(const EstopLatchFile& file, std::string* error);

  const std::string directory_;
  const std::string path_;
  mutable std::mutex mutex_;
  EstopLatchDecision decision_;
  bool started_ = false;
  bool start_latch_held_ = false;  // started latched and not released since
  std::string last_write_error_;   // "" after a successful write
  uint64_t writes_ = 0;
  uint64_t write_failures_ = 0;
};

}  // namespace mostar::drive
