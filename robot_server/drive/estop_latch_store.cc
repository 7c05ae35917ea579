#include "robot_server/drive/estop_latch_store.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <sstream>
#include <utility>

namespace mostar::drive {
namespace {

constexpr const char* kMagic = "mostar-estop-latch";
constexpr int kVersion = 1;
constexpr size_t kMaxIdBytes = 64;

std::string Errno(const std::string& what) { return what + ": " + std::strerror(errno); }

// Printable ASCII without spaces, at most kMaxIdBytes; "-" when empty.
std::string SanitiseId(const std::string& id) {
  std::string out;
  for (const char c : id) {
    if (out.size() == kMaxIdBytes) break;
    out.push_back(c > ' ' && c < 0x7F ? c : '_');
  }
  return out.empty() ? "-" : out;
}

bool ParseFlag(const std::string& value, bool* out) {
  if (value != "0" && value != "1") return false;
  *out = value == "1";
  return true;
}

// Reads at most `limit` + 1 bytes. Returns false with errno set when the file cannot be read;
// `*missing` tells a missing file apart.
bool ReadSmallFile(const std::string& path, size_t limit, std::string* out, bool* missing) {
  *missing = false;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    *missing = errno == ENOENT;
    return false;
  }
  out->clear();
  char buffer[512];
  while (out->size() <= limit) {
    const ssize_t n = ::read(fd, buffer, sizeof(buffer));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int saved = errno;
      ::close(fd);
      errno = saved;
      return false;
    }
    if (n == 0) break;
    out->append(buffer, static_cast<size_t>(n));
  }
  ::close(fd);
  return true;
}

bool WriteAll(int fd, const std::string& data) {
  size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = ::write(fd, data.data() + done, data.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<size_t>(n);
  }
  return true;
}

}  // namespace

std::string FormatEstopLatchFile(const EstopLatchFile& file) {
  std::ostringstream out;
  out << kMagic << " " << kVersion << "\n"
      << "clean_stop " << (file.clean_stop ? 1 : 0) << "\n"
      << "engaged " << (file.engaged ? 1 : 0) << "\n"
      << "engaged_by " << SanitiseId(file.engaged_by) << "\n";
  return out.str();
}

bool ParseEstopLatchFile(const std::string& text, EstopLatchFile* out, std::string* error) {
  std::istringstream in(text);
  std::string line;
  EstopLatchFile file;
  bool header = false, clean_stop = false, engaged = false, engaged_by = false;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    std::istringstream fields(line);
    std::string key, value, extra;
    fields >> key >> value;
    if (key.empty() || value.empty() || (fields >> extra)) {
      *error = "line " + std::to_string(number) + " is not 'key value'";
      return false;
    }
    if (number == 1) {
      if (key != kMagic || value != std::to_string(kVersion)) {
        *error = "not a version " + std::to_string(kVersion) + " e-stop latch file";
        return false;
      }
      header = true;
    } else if (key == "clean_stop" && !clean_stop) {
      clean_stop = ParseFlag(value, &file.clean_stop);
      if (!clean_stop) {
        *error = "clean_stop must be 0 or 1";
        return false;
      }
    } else if (key == "engaged" && !engaged) {
      engaged = ParseFlag(value, &file.engaged);
      if (!engaged) {
        *error = "engaged must be 0 or 1";
        return false;
      }
    } else if (key == "engaged_by" && !engaged_by) {
      engaged_by = true;
      file.engaged_by = value == "-" ? "" : value;
    } else {
      *error = "unexpected or repeated key '" + key.substr(0, 32) + "'";
      return false;
    }
  }
  if (!header || !clean_stop || !engaged || !engaged_by) {
    *error = "incomplete (truncated?)";
    return false;
  }
  *out = file;
  return true;
}

bool WriteFileAtomically(const std::string& path, const std::string& contents, std::string* error) {
  const std::string temporary = path + ".tmp";
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0640);
  if (fd < 0) {
    *error = Errno("cannot create " + temporary);
    return false;
  }
  if (!WriteAll(fd, contents) || ::fsync(fd) != 0) {
    *error = Errno("cannot write " + temporary);
    ::close(fd);
    ::unlink(temporary.c_str());
    return false;
  }
  if (::close(fd) != 0) {
    *error = Errno("cannot close " + temporary);
    ::unlink(temporary.c_str());
    return false;
  }
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    *error = Errno("cannot rename " + temporary + " to " + path);
    ::unlink(temporary.c_str());
    return false;
  }
  // The rename itself is durable once the directory is synced.
  const size_t slash = path.rfind('/');
  const std::string directory = slash == std::string::npos ? "." : path.substr(0, slash + 1);
  const int dir_fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir_fd < 0) {
    *error = Errno("cannot open " + directory);
    return false;
  }
  const bool synced = ::fsync(dir_fd) == 0;
  if (!synced) *error = Errno("cannot sync " + directory);
  ::close(dir_fd);
  return synced;
}

EstopLatchStore::EstopLatchStore(std::string directory)
    : directory_(std::move(directory)), path_(directory_ + "/" + kFileName) {}

EstopLatchDecision EstopLatchStore::Start() {
  std::lock_guard<std::mutex> lock(mutex_);
  EstopLatchDecision decision;
  std::string text;
  bool missing = false;
  if (!ReadSmallFile(path_, kMaxFileBytes, &text, &missing)) {
    if (!missing) {
      decision.latched = true;
      decision.reason = Errno("state file " + path_ + " unreadable");
    }
  } else if (text.size() > kMaxFileBytes) {
    decision.latched = true;
    decision.reason =
        "state file " + path_ + " corrupt: larger than " + std::to_string(kMaxFileBytes) + " bytes";
  } else {
    EstopLatchFile previous;
    std::string why;
    if (!ParseEstopLatchFile(text, &previous, &why)) {
      decision.latched = true;
      decision.reason = "state file " + path_ + " corrupt: " + why;
    } else if (previous.engaged) {
      decision.latched = true;
      decision.engaged_by = previous.engaged_by;
      decision.reason =
          "engaged before the restart" +
          (previous.engaged_by.empty() ? std::string() : " by " + previous.engaged_by);
    } else if (!previous.clean_stop) {
      decision.latched = true;
      decision.reason = "the previous run did not stop cleanly";
    }
  }
  EstopLatchFile running;
  running.engaged = decision.latched;
  running.engaged_by = decision.engaged_by;
  std::string error;
  if (!WriteLocked(running, &error)) {
    if (!decision.latched) decision.reason = "cannot record the latch: " + error;
    decision.latched = true;
  }
  decision_ = decision;
  start_latch_held_ = decision.latched;
  started_ = true;
  return decision;
}

bool EstopLatchStore::Record(bool engaged, const std::string& engaged_by, std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  EstopLatchFile file;
  file.engaged = engaged;
  file.engaged_by = engaged ? engaged_by : "";
  if (!WriteLocked(file, error)) return false;
  if (!engaged) start_latch_held_ = false;
  return true;
}

bool EstopLatchStore::RecordCleanStop(bool engaged, const std::string& engaged_by,
                                      std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  EstopLatchFile file;
  file.clean_stop = true;
  file.engaged = engaged;
  file.engaged_by = engaged ? engaged_by : "";
  return WriteLocked(file, error);
}

bool EstopLatchStore::WriteLocked(const EstopLatchFile& file, std::string* error) {
  std::string why;
  if (!WriteFileAtomically(path_, FormatEstopLatchFile(file), &why)) {
    ++write_failures_;
    last_write_error_ = why;
    if (error) *error = why;
    return false;
  }
  ++writes_;
  last_write_error_.clear();
  return true;
}

DeviceHealth EstopLatchStore::Health() const {
  std::lock_guard<std::mutex> lock(mutex_);
  DeviceHealth health;
  health.name = "estop_latch";
  std::ostringstream message;
  if (!last_write_error_.empty()) {
    health.state = DeviceState::kError;
    message << "cannot persist the e-stop latch (" << last_write_error_ << "); ";
  } else {
    health.state = start_latch_held_ ? DeviceState::kWarn : DeviceState::kOk;
  }
  if (!started_) {
    message << "not started";
  } else if (decision_.latched) {
    message << "started latched: " << decision_.reason;
    if (!start_latch_held_) message << "; released since";
  } else {
    message << "started unlatched";
  }
  message << " (" << path_ << ")";
  health.message = message.str();
  health.counters = {{"writes", writes_}, {"write_failures", write_failures_}};
  return health;
}

}  // namespace mostar::drive
