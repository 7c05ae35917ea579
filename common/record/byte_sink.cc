#include "common/record/byte_sink.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace mostar::record {
namespace {

std::string ErrnoText(int error_number) {
  if (error_number == ENOSPC) return "no space left on device (disk full)";
  return std::strerror(error_number);
}

class FileSink final : public ByteSink {
 public:
  FileSink(std::string path, int fd) : path_(std::move(path)), fd_(fd) {}
  ~FileSink() override {
    if (fd_ >= 0) ::close(fd_);
  }

  bool Append(const char* data, size_t size, std::string* error) override {
    while (size > 0) {
      const ssize_t n = ::write(fd_, data, size);
      if (n < 0) {
        if (errno == EINTR) continue;
        *error = "cannot write " + path_ + ": " + ErrnoText(errno);
        return false;
      }
      if (n == 0) {
        *error = "cannot write " + path_ + ": write returned 0";
        return false;
      }
      data += n;
      size -= static_cast<size_t>(n);
    }
    return true;
  }

  bool Sync(std::string* error) override {
    if (::fdatasync(fd_) != 0 && errno != EINVAL && errno != EROFS) {
      // EINVAL/EROFS: the file does not support syncing (a pipe, /dev/null): nothing to make
      // durable.
      *error = "cannot sync " + path_ + ": " + ErrnoText(errno);
      return false;
    }
    return true;
  }

  bool Truncate(uint64_t size_bytes, std::string* error) override {
    if (::ftruncate(fd_, static_cast<off_t>(size_bytes)) != 0) {
      *error = "cannot truncate " + path_ + ": " + ErrnoText(errno);
      return false;
    }
    if (::lseek(fd_, static_cast<off_t>(size_bytes), SEEK_SET) < 0) {
      *error = "cannot seek in " + path_ + ": " + ErrnoText(errno);
      return false;
    }
    return true;
  }

  bool Close(std::string* error) override {
    if (fd_ < 0) return true;
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) {
      *error = "cannot close " + path_ + ": " + ErrnoText(errno);
      return false;
    }
    return true;
  }

 private:
  const std::string path_;
  int fd_;
};

}  // namespace

std::unique_ptr<ByteSink> OpenFileSink(const std::string& path, std::string* error) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    *error = "cannot create recording " + path + ": " + ErrnoText(errno);
    return nullptr;
  }
  return std::make_unique<FileSink>(path, fd);
}

}  // namespace mostar::record
