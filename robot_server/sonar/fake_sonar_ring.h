// SonarRing for unit tests: the test emits belt cycles by hand, as the ring's thread would.
#pragma once

#include <string>
#include <utility>

#include "robot_server/sonar/sonar_ring.h"

namespace mostar::sonar {

class FakeSonarRing final : public SonarRing {
 public:
  bool Start(RangesCallback on_ranges, std::string* /*error*/) override {
    on_ranges_ = std::move(on_ranges);
    ++starts;
    return true;
  }
  void Stop() override { ++stops; }
  DeviceHealth Health() const override {
    DeviceHealth health;
    health.name = "sonar";
    return health;
  }
  // Delivers one cycle to the started callback.
  void Emit(const SonarRanges& ranges) { on_ranges_(ranges); }

  int starts = 0;
  int stops = 0;

 private:
  RangesCallback on_ranges_;
};

}  // namespace mostar::sonar
