// A belt of range sonars (the MORDUC's 8 SRF08) running on its own thread.
#pragma once

#include <functional>
#include <string>

#include "common/types/health.h"
#include "common/types/sonar.h"

namespace mostar::sonar {

class SonarRing {
 public:
  // Called on the ring's thread once per belt cycle (every sensor ranged once). Must not block.
  using RangesCallback = std::function<void(const SonarRanges&)>;

  SonarRing() = default;
  SonarRing(const SonarRing&) = delete;
  SonarRing& operator=(const SonarRing&) = delete;
  virtual ~SonarRing() = default;

  // Starts the thread; it keeps retrying sensors that fail (see Health()), so Start fails only
  // on misuse (already started, invalid configuration).
  virtual bool Start(RangesCallback on_ranges, std::string* error) = 0;
  // Stops and joins the thread; no callback runs after it returns. Idempotent.
  virtual void Stop() = 0;
  // State, message, cycle rate and counters. Thread-safe.
  virtual DeviceHealth Health() const = 0;
};

}  // namespace mostar::sonar
