// BumperBelt on GPIO lines of one Linux GPIO chip (the GPIO character device, libgpiod 1.6):
// one input line per segment, read together each call. The MORDUC's bumper wiring is not
// documented; GPIO inputs (an I/O expander or the on-board computer's header, one line per
// switch, pulled up, the switch to ground: active low) are the common way to wire switches on a
// Linux robot, and the choice stays behind the BumperBelt interface.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "robot_server/bumper/bumper_belt.h"

struct gpiod_chip;

namespace mostar::bumper {

struct GpiodBumperOptions {
  std::string chip = "/dev/gpiochip0";  // path or name ("gpiochip0")
  std::vector<unsigned> lines;          // line offset of segment i, one per segment
  bool active_low = true;               // pressed = line at 0 (pull-up, switch to ground)
  bool IsValid(std::string* error) const;
};

class GpiodBumperBelt final : public BumperBelt {
 public:
  // Opens the chip and requests the lines as inputs (consumer "mostar-bumpers"); null with a
  // message naming the chip or line when it cannot.
  static std::unique_ptr<GpiodBumperBelt> Open(const GpiodBumperOptions& options,
                                               std::string* error);
  ~GpiodBumperBelt() override;

  bool Read(uint32_t* pressed, std::string* error) override;
  int segments() const override { return static_cast<int>(options_.lines.size()); }
  DeviceHealth Health() const override;

 private:
  GpiodBumperBelt(gpiod_chip* chip, void* bulk, GpiodBumperOptions options);
  gpiod_chip* const chip_;
  void* const bulk_;  // gpiod_line_bulk*, requested
  const GpiodBumperOptions options_;
  mutable std::mutex mutex_;
  uint64_t reads_ = 0;
  uint64_t read_errors_ = 0;
  uint32_t last_ = 0;
  std::string last_error_;
};

}  // namespace mostar::bumper
