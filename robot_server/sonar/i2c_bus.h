// A Linux I2C bus as the SRF08 driver uses it: register writes and register reads of 7-bit
// addresses. Real (/dev/i2c-N, linux_i2c_bus.h) or emulated (srf08_emulator.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace mostar::sonar {

class I2cBus {
 public:
  virtual ~I2cBus() = default;
  // Writes `value` to register `reg` of the device at 7-bit `address`.
  virtual bool WriteRegister(uint8_t address, uint8_t reg, uint8_t value, std::string* error) = 0;
  // Reads `count` consecutive registers from `reg` (a write of the register number, then a
  // read with a repeated start).
  virtual bool ReadRegisters(uint8_t address, uint8_t reg, uint8_t* out, size_t count,
                             std::string* error) = 0;
};

}  // namespace mostar::sonar
