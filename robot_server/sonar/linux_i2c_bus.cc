#include "robot_server/sonar/linux_i2c_bus.h"

#include <fcntl.h>
#include <linux/i2c-dev.h>
#include <linux/i2c.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace mostar::sonar {
namespace {

std::string Describe(const std::string& device, uint8_t address, const char* what) {
  char hex[8];
  std::snprintf(hex, sizeof(hex), "0x%02x", address);
  return device + " address " + hex + ": " + what + ": " + std::strerror(errno);
}

}  // namespace

std::unique_ptr<LinuxI2cBus> LinuxI2cBus::Open(const std::string& device, std::string* error) {
  const int fd = open(device.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) {
    *error = "cannot open " + device + ": " + std::strerror(errno);
    return nullptr;
  }
  unsigned long functions = 0;
  if (ioctl(fd, I2C_FUNCS, &functions) != 0 || (functions & I2C_FUNC_I2C) == 0) {
    *error = device + " is not a plain I2C adapter (no I2C_FUNC_I2C)";
    close(fd);
    return nullptr;
  }
  return std::unique_ptr<LinuxI2cBus>(new LinuxI2cBus(fd, device));
}

LinuxI2cBus::~LinuxI2cBus() { close(fd_); }

bool LinuxI2cBus::WriteRegister(uint8_t address, uint8_t reg, uint8_t value, std::string* error) {
  uint8_t bytes[2] = {reg, value};
  i2c_msg message{address, 0, sizeof(bytes), bytes};
  i2c_rdwr_ioctl_data transfer{&message, 1};
  if (ioctl(fd_, I2C_RDWR, &transfer) < 0) {
    *error = Describe(device_, address, "register write");
    return false;
  }
  return true;
}

bool LinuxI2cBus::ReadRegisters(uint8_t address, uint8_t reg, uint8_t* out, size_t count,
                                std::string* error) {
  i2c_msg messages[2] = {{address, 0, 1, &reg},
                         {address, I2C_M_RD, static_cast<uint16_t>(count), out}};
  i2c_rdwr_ioctl_data transfer{messages, 2};
  if (count == 0 || count > 64 || ioctl(fd_, I2C_RDWR, &transfer) < 0) {
    *error = Describe(device_, address, "register read");
    return false;
  }
  return true;
}

}  // namespace mostar::sonar
