#include "common/service/service_notifier.h"

#include <systemd/sd-daemon.h>

#include <cstdint>
#include <cstdlib>

namespace mostar::service {

ServiceNotifier::ServiceNotifier() {
  enabled_ = std::getenv("NOTIFY_SOCKET") != nullptr;
  uint64_t usec = 0;
  if (enabled_ && sd_watchdog_enabled(0, &usec) > 0 && usec > 0) {
    watchdog_interval_ = std::chrono::microseconds(usec);
  }
}

void ServiceNotifier::Ready(const std::string& status) {
  if (!enabled_) return;
  sd_notifyf(0, "READY=1\nSTATUS=%s", status.c_str());
}

void ServiceNotifier::Alive(SteadyTime now) {
  if (!enabled_ || watchdog_interval_ <= Duration::zero()) return;
  if (alive_sent_ && now - last_alive_ < watchdog_interval_ / 2) return;
  sd_notify(0, "WATCHDOG=1");
  last_alive_ = now;
  alive_sent_ = true;
  ++watchdog_messages_;
}

void ServiceNotifier::Stopping(const std::string& status) {
  if (!enabled_) return;
  sd_notifyf(0, "STOPPING=1\nSTATUS=%s", status.c_str());
}

}  // namespace mostar::service
