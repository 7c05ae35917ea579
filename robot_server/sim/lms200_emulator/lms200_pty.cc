#include "robot_server/sim/lms200_emulator/lms200_pty.h"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "robot_server/serial/baud_rate.h"

namespace mostar::sim {

Lms200PtyRunner::Lms200PtyRunner(Lms200Emulator* emulator, std::string link_path)
    : emulator_(emulator), link_path_(std::move(link_path)) {}

Lms200PtyRunner::~Lms200PtyRunner() { Stop(); }

bool Lms200PtyRunner::OpenPtyLocked(std::string* error) {
  const int master = posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || grantpt(master) != 0 || unlockpt(master) != 0) {
    if (error) *error = std::string("cannot create a pty: ") + std::strerror(errno);
    if (master >= 0) ::close(master);
    return false;
  }
  const char* name = ptsname(master);
  if (name == nullptr) {
    if (error) *error = "ptsname failed";
    ::close(master);
    return false;
  }
  slave_path_ = name;
  const int keeper = ::open(slave_path_.c_str(), O_RDWR | O_NOCTTY);
  if (keeper >= 0) {
    termios tio{};
    if (tcgetattr(keeper, &tio) == 0) {
      cfmakeraw(&tio);
      cfsetispeed(&tio, B9600);
      cfsetospeed(&tio, B9600);
      tcsetattr(keeper, TCSANOW, &tio);
    }
  }
  ::fcntl(master, F_SETFL, ::fcntl(master, F_GETFL) | O_NONBLOCK);
  master_fd_ = master;
  slave_keeper_fd_ = keeper;
  if (!link_path_.empty()) {
    const std::string tmp = link_path_ + ".tmp";
    ::unlink(tmp.c_str());
    if (::symlink(slave_path_.c_str(), tmp.c_str()) != 0 ||
        ::rename(tmp.c_str(), link_path_.c_str()) != 0) {
      if (error) *error = "cannot link " + link_path_ + ": " + std::strerror(errno);
      ClosePtyLocked();
      return false;
    }
  }
  return true;
}

void Lms200PtyRunner::ClosePtyLocked() {
  if (!link_path_.empty()) ::unlink(link_path_.c_str());
  if (slave_keeper_fd_ >= 0) ::close(slave_keeper_fd_);
  if (master_fd_ >= 0) ::close(master_fd_);
  slave_keeper_fd_ = master_fd_ = -1;
}

bool Lms200PtyRunner::Start(std::string* error) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (thread_.joinable()) {
      if (error) *error = "already started";
      return false;
    }
    if (!OpenPtyLocked(error)) return false;
  }
  stop_ = false;
  thread_ = std::thread([this] { Run(); });
  return true;
}

void Lms200PtyRunner::Stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  std::lock_guard<std::mutex> lock(mutex_);
  ClosePtyLocked();
}

std::string Lms200PtyRunner::device_path() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return link_path_.empty() ? slave_path_ : link_path_;
}

std::string Lms200PtyRunner::slave_path() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return slave_path_;
}

void Lms200PtyRunner::Unplug() {
  std::lock_guard<std::mutex> lock(mutex_);
  ClosePtyLocked();
}

bool Lms200PtyRunner::Replug(std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  ClosePtyLocked();
  return OpenPtyLocked(error);
}

void Lms200PtyRunner::Run() {
  std::vector<uint8_t> out;
  // Device bytes the pty did not take yet. A pty buffers only about 12 KB (240 ms at 500 kBd);
  // a serial port's receive buffer in the kernel holds 64 KB, so the rest waits here.
  std::vector<uint8_t> backlog;
  int backlog_fd = -1;
  uint8_t buffer[4096];
  while (!stop_.load()) {
    int fd;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      fd = master_fd_;
    }
    if (fd < 0) {
      // Unplugged: the device keeps running, its bytes go nowhere.
      out.clear();
      emulator_->Transmit(std::chrono::steady_clock::now(), 0, &out);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      continue;
    }
    pollfd pfd{fd, POLLIN, 0};
    ::poll(&pfd, 1, 1);
    std::lock_guard<std::mutex> lock(mutex_);
    if (master_fd_ != fd) continue;         // replugged meanwhile
    if (backlog_fd != fd) backlog.clear();  // what was buffered went with the old device
    backlog_fd = fd;
    const int host_baud = std::max(0, serial::LineBaud(fd));
    if ((pfd.revents & POLLIN) != 0) {
      const ssize_t n = ::read(fd, buffer, sizeof(buffer));
      if (n > 0) {
        emulator_->Receive(buffer, static_cast<size_t>(n), host_baud,
                           std::chrono::steady_clock::now());
      }
    }
    out.clear();
    emulator_->Transmit(std::chrono::steady_clock::now(), host_baud, &out);
    // Beyond the kernel's buffer the host is not reading: new bytes are lost (an overrun).
    const size_t room = kHostBufferBytes - std::min(kHostBufferBytes, backlog.size());
    if (out.size() > room) bytes_overrun_ += out.size() - room;
    backlog.insert(backlog.end(), out.begin(),
                   out.begin() + static_cast<std::ptrdiff_t>(std::min(room, out.size())));
    size_t written = 0;
    while (written < backlog.size()) {
      const ssize_t n = ::write(fd, backlog.data() + written, backlog.size() - written);
      if (n <= 0) break;  // the pty is full: the rest waits
      written += static_cast<size_t>(n);
    }
    backlog.erase(backlog.begin(), backlog.begin() + static_cast<std::ptrdiff_t>(written));
  }
}

}  // namespace mostar::sim
