#include "common/process/exit_deadline.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <utility>

namespace mostar {

ExitDeadline::ExitDeadline(Duration timeout, int exit_code, std::string program, std::string what)
    : ExitDeadline(timeout, [timeout, exit_code, program = std::move(program),
                             what = std::move(what)] {
        char line[512];
        const int n = std::snprintf(
            line, sizeof line, "%s: %s did not finish within %.2f s: ending now (exit status %d)\n",
            program.c_str(), what.c_str(), ToSeconds(timeout), exit_code);
        // write(2), not stdio: the blocked thread may hold a stdio lock.
        if (n > 0) {
          const ssize_t ignored = ::write(2, line, static_cast<size_t>(n));
          (void)ignored;
        }
        std::_Exit(exit_code);
      }) {}

ExitDeadline::ExitDeadline(Duration timeout, std::function<void()> on_expiry) {
  waiter_ = std::thread([this, timeout, on_expiry = std::move(on_expiry)] {
    std::unique_lock<std::mutex> lock(mutex_);
    if (disarmed_cv_.wait_for(lock, timeout, [this] { return disarmed_; })) return;
    lock.unlock();
    on_expiry();
  });
}

ExitDeadline::~ExitDeadline() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    disarmed_ = true;
  }
  disarmed_cv_.notify_all();
  waiter_.join();
}

}  // namespace mostar
