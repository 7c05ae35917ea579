#include "common/dds/tcp_user_timeout.h"

#include <dirent.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <sys/stat.h>

#include <cstdlib>
#include <vector>

namespace mostar::dds {

namespace {

int GetIntOption(int fd, int level, int name, bool* ok) {
  int value = 0;
  socklen_t length = sizeof(value);
  *ok = ::getsockopt(fd, level, name, &value, &length) == 0;
  return value;
}

bool IsTcpSocket(int fd) {
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISSOCK(st.st_mode)) return false;
  bool ok = false;
  const int domain = GetIntOption(fd, SOL_SOCKET, SO_DOMAIN, &ok);
  if (!ok || (domain != AF_INET && domain != AF_INET6)) return false;
  const int type = GetIntOption(fd, SOL_SOCKET, SO_TYPE, &ok);
  if (!ok || type != SOCK_STREAM) return false;
  const int protocol = GetIntOption(fd, SOL_SOCKET, SO_PROTOCOL, &ok);
  return ok && protocol == IPPROTO_TCP;
}

std::vector<int> OpenDescriptors() {
  std::vector<int> fds;
  DIR* dir = ::opendir("/proc/self/fd");
  if (dir == nullptr) return fds;
  const int own = ::dirfd(dir);
  while (const dirent* entry = ::readdir(dir)) {
    char* end = nullptr;
    const long fd = std::strtol(entry->d_name, &end, 10);
    if (end == entry->d_name || *end != '\0' || fd == own) continue;
    fds.push_back(static_cast<int>(fd));
  }
  ::closedir(dir);
  return fds;
}

}  // namespace

int ApplyTcpUserTimeout(int timeout_ms) {
  if (timeout_ms <= 0) return 0;
  int changed = 0;
  for (int fd : OpenDescriptors()) {
    if (!IsTcpSocket(fd)) continue;
    bool ok = false;
    const int current = GetIntOption(fd, IPPROTO_TCP, TCP_USER_TIMEOUT, &ok);
    if (!ok || current == timeout_ms) continue;
    const unsigned int value = static_cast<unsigned int>(timeout_ms);
    if (::setsockopt(fd, IPPROTO_TCP, TCP_USER_TIMEOUT, &value, sizeof(value)) == 0) ++changed;
  }
  return changed;
}

TcpUserTimeoutGuard::TcpUserTimeoutGuard(int timeout_ms, std::chrono::milliseconds scan_period)
    : timeout_ms_(timeout_ms) {
  thread_ = std::thread([this, scan_period] {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_) {
      lock.unlock();
      sockets_set_ += ApplyTcpUserTimeout(timeout_ms_);
      lock.lock();
      cv_.wait_for(lock, scan_period, [this] { return stop_; });
    }
  });
}

TcpUserTimeoutGuard::~TcpUserTimeoutGuard() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

}  // namespace mostar::dds
