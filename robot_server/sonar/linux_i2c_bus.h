// I2cBus on a Linux I2C adapter (/dev/i2c-N, i2c-dev): every transfer is one I2C_RDWR ioctl,
// so register reads use a repeated start and no other master can slip in between.
#pragma once

#include <memory>
#include <string>

#include "robot_server/sonar/i2c_bus.h"

namespace mostar::sonar {

class LinuxI2cBus final : public I2cBus {
 public:
  // Opens `device` (e.g. "/dev/i2c-1"); nullptr with `error` when it cannot.
  static std::unique_ptr<LinuxI2cBus> Open(const std::string& device, std::string* error);
  ~LinuxI2cBus() override;

  bool WriteRegister(uint8_t address, uint8_t reg, uint8_t value, std::string* error) override;
  bool ReadRegisters(uint8_t address, uint8_t reg, uint8_t* out, size_t count,
                     std::string* error) override;

 private:
  LinuxI2cBus(int fd, std::string device) : fd_(fd), device_(std::move(device)) {}
  const int fd_;
  const std::string device_;
};

}  // namespace mostar::sonar
