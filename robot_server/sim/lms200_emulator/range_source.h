// Where the LMS200 emulator gets its distances from.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "common/time/time.h"

namespace mostar::sim {

class RangeSource {
 public:
  virtual ~RangeSource() = default;
  // Ranges (metres) of `count` beams at angles angle_min_rad + i * angle_increment_rad in the
  // laser frame (REP-103: CCW, 0 = ahead), measured at `time`, as a LaserScan carries them:
  // +Inf = no echo (sent as 0x1FFF), a finite range above the maximum = beyond range (0x1FF7),
  // NaN = no measurement (sent as the dazzle error code). Called on the emulator's thread;
  // implementations shared with other threads must synchronise.
  virtual void Sample(SteadyTime time, float angle_min_rad, float angle_increment_rad, int count,
                      std::vector<float>* ranges_m) = 0;
};

// An empty rectangular room, the laser at (x_m, y_m) looking along +x. Walls at
// x = 0 and x = length_m, y = 0 and y = width_m.
class RoomRangeSource final : public RangeSource {
 public:
  RoomRangeSource(double length_m, double width_m, double x_m, double y_m)
      : length_m_(length_m), width_m_(width_m), x_m_(x_m), y_m_(y_m) {}
  void Sample(SteadyTime time, float angle_min_rad, float angle_increment_rad, int count,
              std::vector<float>* ranges_m) override;

 private:
  double length_m_, width_m_, x_m_, y_m_;
};

// Ranges from a function of (time, beam angle); for tests.
class FunctionRangeSource final : public RangeSource {
 public:
  using Function = std::function<float(SteadyTime time, float angle_rad)>;
  explicit FunctionRangeSource(Function f) : f_(std::move(f)) {}
  void Sample(SteadyTime time, float angle_min_rad, float angle_increment_rad, int count,
              std::vector<float>* ranges_m) override {
    ranges_m->resize(static_cast<size_t>(count));
    for (int i = 0; i < count; ++i) {
      (*ranges_m)[static_cast<size_t>(i)] = f_(time, angle_min_rad + i * angle_increment_rad);
    }
  }

 private:
  Function f_;
};

// Numbers the scans it is asked for, so that loss tests and benches can tell which scan a
// delivered one is: beam 0 of the n-th scan reads 0.5 m + (n mod kModulus) mm, the other beams
// 3 m. The emulator calls it once per scan telegram: its n-th call is the emulator's scan id n.
// Called on the emulator's thread only.
class NumberedRangeSource final : public RangeSource {
 public:
  static constexpr uint64_t kModulus = 4096;
  void Sample(SteadyTime, float, float, int count, std::vector<float>* ranges_m) override {
    ranges_m->assign(static_cast<size_t>(count), 3.0f);
    if (count > 0) (*ranges_m)[0] = 0.5f + static_cast<float>(next_++ % kModulus) * 0.001f;
  }
  // The number (mod kModulus) of a scan decoded in mm.
  static uint64_t Number(const std::vector<float>& ranges_m) {
    return static_cast<uint64_t>(std::llround((ranges_m.at(0) - 0.5) * 1000.0));
  }

 private:
  uint64_t next_ = 0;
};

}  // namespace mostar::sim
