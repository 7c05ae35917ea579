#include "robot_server/serial/baud_rate.h"

#include <unistd.h>

#include <exception>
#include <mutex>
#include <vector>

namespace mostar::serial {

std::optional<LibSerial::BaudRate> ToLibSerialBaudRate(int baud) {
  using LibSerial::BaudRate;
  switch (baud) {
    case 1200:
      return BaudRate::BAUD_1200;
    case 2400:
      return BaudRate::BAUD_2400;
    case 4800:
      return BaudRate::BAUD_4800;
    case 9600:
      return BaudRate::BAUD_9600;
    case 19200:
      return BaudRate::BAUD_19200;
    case 38400:
      return BaudRate::BAUD_38400;
    case 57600:
      return BaudRate::BAUD_57600;
    case 115200:
      return BaudRate::BAUD_115200;
    case 230400:
      return BaudRate::BAUD_230400;
    case 460800:
      return BaudRate::BAUD_460800;
    case 500000:
      return BaudRate::BAUD_500000;
    case 921600:
      return BaudRate::BAUD_921600;
    default:
      return std::nullopt;
  }
}

int BaudOfTermiosSpeed(speed_t speed) {
  switch (speed) {
    case B1200:
      return 1200;
    case B2400:
      return 2400;
    case B4800:
      return 4800;
    case B9600:
      return 9600;
    case B19200:
      return 19200;
    case B38400:
      return 38400;
    case B57600:
      return 57600;
    case B115200:
      return 115200;
    case B230400:
      return 230400;
    case B460800:
      return 460800;
    case B500000:
      return 500000;
    case B921600:
      return 921600;
    default:
      return 0;
  }
}

int LineBaud(int fd) {
  termios tio{};
  if (tcgetattr(fd, &tio) != 0) return -1;
  return BaudOfTermiosSpeed(cfgetospeed(&tio));
}

void ClosePort(std::unique_ptr<LibSerial::SerialPort>* port) {
  if (*port == nullptr) return;
  if ((*port)->IsOpen()) {
    try {
      (*port)->Close();
    } catch (const std::exception&) {
      ::close((*port)->GetFileDescriptor());
      // Abandoned, never destroyed (its destructor would throw); kept reachable here so that
      // leak checkers see it is held on purpose.
      static std::mutex mutex;
      static auto* abandoned = new std::vector<std::unique_ptr<LibSerial::SerialPort>>();
      std::lock_guard<std::mutex> lock(mutex);
      abandoned->push_back(std::move(*port));
      return;
    }
  }
  port->reset();
}

}  // namespace mostar::serial
