// Tells the service manager (systemd, Type=notify) how a daemon is doing: ready, alive (the
// watchdog), stopping. Without a service manager (NOTIFY_SOCKET unset: a terminal, a test)
// every call does nothing.
//
// The watchdog is fed from the loop that must not stall (robot_server: the control loop), at
// most every half of the interval systemd asks for (WatchdogSec=, read from WATCHDOG_USEC):
// if that loop stops, systemd kills the process and restarts it.
#pragma once

#include <string>

#include "common/time/time.h"

namespace mostar::service {

class ServiceNotifier {
 public:
  ServiceNotifier();

  // True when a service manager listens (NOTIFY_SOCKET is set).
  bool enabled() const { return enabled_; }
  // The watchdog interval systemd expects, or zero when it has none.
  Duration watchdog_interval() const { return watchdog_interval_; }

  // READY=1 with a one-line status.
  void Ready(const std::string& status);
  // WATCHDOG=1 when half the interval has passed since the last one (call it every cycle).
  void Alive(SteadyTime now);
  // STOPPING=1 with a one-line status.
  void Stopping(const std::string& status);

  // Watchdog messages sent so far.
  int watchdog_messages() const { return watchdog_messages_; }

 private:
  bool enabled_ = false;
  Duration watchdog_interval_{};
  SteadyTime last_alive_{};
  bool alive_sent_ = false;
  int watchdog_messages_ = 0;
};

}  // namespace mostar::service
