// Devantech SRF08 ultrasonic range finder on I2C: register map, conversions, and the belt
// driver that ranges the sensors group by group.
//
// SRF08 registers: 0 write = command (0x51: range in centimetres), read = software revision
// (the sensor does not answer on the bus while it ranges); 1 write = maximum analogue gain
// (0..31); 2 write = range register (window = (value + 1) x 43 mm, 255 = 11 m; ranging ends
// after the window's echo time, at most 65 ms); 2-3 read = first echo (high, low byte; 0 = no
// echo), 4-35 the later echoes. 7-bit addresses 0x70-0x7F (0xE0-0xFE on the datasheet).
//
// Ping groups: sensors in one group fire together and must not hear each other's bursts
// (e.g. opposite sides of the belt); groups fire one after the other, so one belt cycle takes
// about groups x ranging time (4 x 65 ms = 3.8 Hz for 8 sensors in opposite pairs).
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/time/time.h"
#include "robot_server/sonar/i2c_bus.h"
#include "robot_server/sonar/sonar_ring.h"

namespace mostar::sonar {

inline constexpr uint8_t kSrf08CommandRegister = 0;
inline constexpr uint8_t kSrf08GainRegister = 1;
inline constexpr uint8_t kSrf08RangeRegister = 2;
inline constexpr uint8_t kSrf08FirstEchoRegister = 2;
inline constexpr uint8_t kSrf08RangeCentimetres = 0x51;
inline constexpr uint8_t kSrf08MinAddress = 0x70;
inline constexpr uint8_t kSrf08MaxAddress = 0x7F;

// The range register value whose window covers `max_range_m` (43 mm steps, 0..255).
uint8_t Srf08RangeRegisterFor(double max_range_m);
// The window of a range register value, metres.
double Srf08WindowMetres(uint8_t range_register);
// The first echo's bytes (centimetres) as metres; +Inf when 0 (no echo in the window).
float Srf08EchoMetres(uint8_t high, uint8_t low);

struct Srf08Sensor {
  uint8_t address = kSrf08MinAddress;  // 7-bit
  SonarMount mount;
};

struct Srf08RingOptions {
  std::vector<Srf08Sensor> sensors;
  // Indices into `sensors`; every sensor in exactly one group. Empty: one group per sensor.
  std::vector<std::vector<int>> ping_groups;
  double max_range_m = 6.0;  // ranging window (range register), 0.043..11
  int gain = 31;             // maximum analogue gain register, 0..31
  Duration ranging_time = std::chrono::milliseconds(65);  // before the first poll
  Duration poll_timeout = std::chrono::milliseconds(40);  // further polling, then failed
  double min_range_m = 0.03;        // closer is lost in the transducer's ringing
  double field_of_view_rad = 0.96;  // the SRF08's cone, about 55 degrees
  bool IsValid(std::string* error) const;
};

// The belt on one I2C bus. Each cycle: per group, the ranging command to every sensor of the
// group, a wait of ranging_time, then polls of register 0 (a sensor that does not answer is
// still ranging) until poll_timeout, and a read of the first echo. A sensor that fails (no
// answer, bus error) reads NaN this cycle and is configured again (range and gain registers)
// before its next ranging; the others go on.
class Srf08Ring final : public SonarRing {
 public:
  Srf08Ring(std::unique_ptr<I2cBus> bus, const Srf08RingOptions& options, const Clock& clock);
  ~Srf08Ring() override;

  bool Start(RangesCallback on_ranges, std::string* error) override;
  void Stop() override;
  DeviceHealth Health() const override;

 private:
  void Run();
  bool Configure(size_t sensor, std::string* error);
  // Waits `duration` or until Stop; false when stopping.
  bool Sleep(Duration duration);

  const std::unique_ptr<I2cBus> bus_;
  Srf08RingOptions options_;
  const Clock& clock_;
  RangesCallback on_ranges_;
  std::thread thread_;
  std::mutex stop_mutex_;
  std::condition_variable stop_cv_;
  bool stopping_ = false;
  bool started_ = false;

  std::vector<bool> configured_;  // ring thread only
  mutable std::mutex health_mutex_;
  uint64_t cycles_ = 0;
  uint64_t bus_errors_ = 0;
  uint64_t timeouts_ = 0;
  uint64_t no_echo_ = 0;
  std::vector<std::string> failed_last_cycle_;
  SteadyTime first_cycle_end_{};
  SteadyTime last_cycle_end_{};
};

}  // namespace mostar::sonar
