// A planar laser scanner running on its own thread.
#pragma once

#include <functional>
#include <string>

#include "common/types/health.h"
#include "common/types/laser_scan.h"

namespace mostar::laser {

class LaserScanner {
 public:
  // Called on the scanner's thread for every scan (laser frame, metres, radians). Must not
  // block: hand the scan over (latest-value slot) and return.
  using ScanCallback = std::function<void(const LaserScan&)>;

  LaserScanner() = default;
  LaserScanner(const LaserScanner&) = delete;
  LaserScanner& operator=(const LaserScanner&) = delete;
  virtual ~LaserScanner() = default;

  // Starts the device thread. The thread itself keeps retrying a missing or silent device
  // (see Health()), so Start fails only on misuse (already started, invalid configuration).
  virtual bool Start(ScanCallback on_scan, std::string* error) = 0;
  // Stops and joins the thread; no callback runs after it returns. Idempotent.
  virtual void Stop() = 0;
  // Snapshot of state, message, scan rate and counters. Thread-safe.
  virtual DeviceHealth Health() const = 0;
};

}  // namespace mostar::laser
