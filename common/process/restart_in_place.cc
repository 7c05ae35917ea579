#include "common/process/restart_in_place.h"

#include <fcntl.h>
#include <linux/close_range.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

#include "common/process/stop_signals.h"

namespace mostar {
namespace {

std::vector<std::string>& RememberedArguments() {
  static std::vector<std::string> arguments;
  return arguments;
}
std::atomic<bool> g_restart_requested{false};

}  // namespace

void RememberCommandLine(int argc, char** argv) { RememberedArguments().assign(argv, argv + argc); }

void RequestRestart() {
  g_restart_requested.store(true);
  RequestStop();
}

bool RestartRequested() { return g_restart_requested.load(); }

bool RestartInPlace(std::string* error, const std::string& executable) {
  const std::vector<std::string>& arguments = RememberedArguments();
  if (arguments.empty()) {
    *error = "no command line remembered (RememberCommandLine was not called)";
    return false;
  }
  std::vector<char*> argv;
  for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::fflush(nullptr);
  // Everything above stderr closes on exec (Linux 5.11: close_range with CLOSE_RANGE_CLOEXEC).
  if (syscall(SYS_close_range, 3u, ~0u, CLOSE_RANGE_CLOEXEC) != 0) {
    const long limit = sysconf(_SC_OPEN_MAX);  // older kernels: one fcntl per possible descriptor
    for (int fd = 3; fd < (limit > 0 ? limit : 1024); ++fd) (void)fcntl(fd, F_SETFD, FD_CLOEXEC);
  }
  execv(executable.c_str(), argv.data());
  *error = "cannot restart " + executable + ": " + std::strerror(errno);
  return false;
}

int RestartIfRequested(int status, const char* program) {
  if (!RestartRequested() || status != 0) return status;
  std::string error;
  RestartInPlace(&error);
  std::fprintf(stderr, "%s: %s\n", program, error.c_str());
  return 1;
}

}  // namespace mostar
