#include "robot_server/laser/serial_byte_stream.h"

#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>
#include <thread>

#include "robot_server/serial/baud_rate.h"

namespace mostar::laser {
namespace {

void SetError(std::string* error, const std::string& message) {
  if (error) *error = message;
}

}  // namespace

SerialByteStream::SerialByteStream(std::string path, int baud)
    : path_(std::move(path)), baud_(baud) {}

SerialByteStream::~SerialByteStream() { Close(); }

bool SerialByteStream::IsOpen() const { return port_ != nullptr && port_->IsOpen(); }

void SerialByteStream::Close() { serial::ClosePort(&port_); }

bool SerialByteStream::ApplyBaud(std::string* error) {
  const auto rate = serial::ToLibSerialBaudRate(baud_);
  if (!rate) {
    SetError(error, "unsupported baud rate " + std::to_string(baud_));
    return false;
  }
  try {
    port_->SetBaudRate(*rate);
    port_->SetCharacterSize(LibSerial::CharacterSize::CHAR_SIZE_8);
    port_->SetParity(LibSerial::Parity::PARITY_NONE);
    port_->SetStopBits(LibSerial::StopBits::STOP_BITS_1);
    port_->SetFlowControl(LibSerial::FlowControl::FLOW_CONTROL_NONE);
  } catch (const std::exception& e) {
    SetError(error, path_ + ": cannot set " + std::to_string(baud_) + " Bd: " + e.what());
    return false;
  }
  const int in_force = serial::LineBaud(port_->GetFileDescriptor());
  if (in_force != baud_) {
    SetError(error, path_ + ": asked for " + std::to_string(baud_) + " Bd, the driver runs at " +
                        (in_force > 0 ? std::to_string(in_force) + " Bd"
                                      : std::string("a non-standard or unknown rate")) +
                        " (adapter without this rate?)");
    return false;
  }
  return true;
}

bool SerialByteStream::Reopen(std::string* error) {
  Close();
  port_ = std::make_unique<LibSerial::SerialPort>();
  try {
    port_->Open(path_);
  } catch (const std::exception& e) {
    SetError(error, path_ + ": cannot open: " + e.what());
    return false;
  }
  if (!ApplyBaud(error)) {
    Close();
    return false;
  }
  Flush();
  return true;
}

bool SerialByteStream::SetBaudRate(int baud, std::string* error) {
  if (!serial::ToLibSerialBaudRate(baud)) {
    SetError(error, "unsupported baud rate " + std::to_string(baud));
    return false;
  }
  baud_ = baud;
  if (!IsOpen()) return true;  // applied on the next Reopen()
  return ApplyBaud(error);
}

void SerialByteStream::Flush() {
  if (!IsOpen()) return;
  try {
    port_->FlushIOBuffers();
  } catch (const std::exception&) {
    // A vanished device shows up on the next Read/Write.
  }
}

bool SerialByteStream::Write(const uint8_t* data, size_t size, std::string* error) {
  if (!IsOpen()) {
    SetError(error, path_ + " is not open");
    return false;
  }
  if (write_byte_gap_ <= Duration::zero()) return WriteAll(data, size, error);
  // One byte at a time: each is drained to the line (for a USB adapter: out of the chip, so
  // two bytes never share a USB packet) before the gap starts.
  for (size_t i = 0; i < size; ++i) {
    if (i > 0) std::this_thread::sleep_for(write_byte_gap_);
    if (!WriteAll(data + i, 1, error)) return false;
    ::tcdrain(port_->GetFileDescriptor());  // an unplugged device shows up on the next call
  }
  return true;
}

bool SerialByteStream::WriteAll(const uint8_t* data, size_t size, std::string* error) {
  const int fd = port_->GetFileDescriptor();
  size_t written = 0;
  while (written < size) {
    const ssize_t n = ::write(fd, data + written, size - written);
    if (n > 0) {
      written += static_cast<size_t>(n);
    } else if (n < 0 && (errno == EAGAIN || errno == EINTR)) {
      pollfd pfd{fd, POLLOUT, 0};
      ::poll(&pfd, 1, 50);
    } else {
      SetError(error, path_ + ": write failed: " + std::strerror(errno));
      Close();
      return false;
    }
  }
  return true;
}

int SerialByteStream::Read(uint8_t* buffer, size_t max, Duration timeout, std::string* error) {
  if (!IsOpen()) {
    SetError(error, path_ + " is not open");
    return -1;
  }
  const int fd = port_->GetFileDescriptor();
  pollfd pfd{fd, POLLIN, 0};
  const int timeout_ms = static_cast<int>(
      std::max<int64_t>(0, std::chrono::ceil<std::chrono::milliseconds>(timeout).count()));
  const int ready = ::poll(&pfd, 1, timeout_ms);
  if (ready < 0) {
    if (errno == EINTR) return 0;
    SetError(error, path_ + ": poll failed: " + std::strerror(errno));
    Close();
    return -1;
  }
  if (ready == 0) return 0;
  if ((pfd.revents & POLLIN) == 0 && (pfd.revents & (POLLHUP | POLLERR | POLLNVAL)) != 0) {
    SetError(error, path_ + ": device hung up");
    Close();
    return -1;
  }
  const ssize_t n = ::read(fd, buffer, max);
  if (n > 0) return static_cast<int>(n);
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return 0;
  SetError(error, path_ + (n == 0 ? ": end of file"
                                  : std::string(": read failed: ") + std::strerror(errno)));
  Close();
  return -1;
}

}  // namespace mostar::laser
