// ByteStream over a serial device (RS-232/RS-422 adapter or pseudo-terminal) with libserial.
// A rate is only accepted when the kernel reports it in force afterwards: an adapter whose
// driver cannot produce it (many on-board UARTs at 500000 Bd) is refused with both rates named
// instead of streaming garbage.
#pragma once

#include <libserial/SerialPort.h>

#include <memory>
#include <string>

#include "robot_server/laser/byte_stream.h"

namespace mostar::laser {

class SerialByteStream final : public ByteStream {
 public:
  // Does not open the device; call Reopen(). `baud` is the initial rate.
  SerialByteStream(std::string path, int baud);
  ~SerialByteStream() override;

  bool Write(const uint8_t* data, size_t size, std::string* error) override;
  void SetWriteByteGap(Duration gap) override { write_byte_gap_ = gap; }
  int Read(uint8_t* buffer, size_t max, Duration timeout, std::string* error) override;
  bool SetBaudRate(int baud, std::string* error) override;
  int baud_rate() const override { return baud_; }
  void Flush() override;
  bool IsOpen() const override;
  bool Reopen(std::string* error) override;
  void Close() override;
  std::string name() const override { return path_; }

 private:
  bool ApplyBaud(std::string* error);
  // Writes `size` bytes at once; false (and closed) on failure.
  bool WriteAll(const uint8_t* data, size_t size, std::string* error);
  std::string path_;
  int baud_;
  Duration write_byte_gap_{0};
  // Null while closed. Recreated on every open: after the device vanished libserial can no
  // longer close it cleanly (see Close()).
  std::unique_ptr<LibSerial::SerialPort> port_;
};

}  // namespace mostar::laser
