// A bidirectional byte link to a device (serial port, pseudo-terminal, test fake).
//
// Contract for every implementation:
// - Not thread-safe: one thread owns the stream (the device thread).
// - Failures are returned, never thrown: a negative Read result or `false`, with a message
//   in `*error` (may be null). After a failure that means the device is gone (unplugged USB
//   adapter, closed pty), `IsOpen()` is false until `Reopen()` succeeds.
// - Baud rates are in bits per second on an 8N1 line (10 bits per byte).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "common/time/time.h"

namespace mostar::laser {

class ByteStream {
 public:
  ByteStream() = default;
  ByteStream(const ByteStream&) = delete;
  ByteStream& operator=(const ByteStream&) = delete;
  virtual ~ByteStream() = default;

  // Queues all `size` bytes for transmission (paced, see SetWriteByteGap). False on failure.
  virtual bool Write(const uint8_t* data, size_t size, std::string* error) = 0;

  // Idle line time to leave between two bytes this stream sends; zero (the default) writes
  // back to back. A device that needs it (the LMS200 above 38400 Bd: at least 55 us) then
  // gets one byte at a time, so a Write of n bytes blocks for at least (n - 1) * gap.
  virtual void SetWriteByteGap(Duration gap) = 0;

  // Waits up to `timeout` for input; copies at most `max` available bytes into `buffer`.
  // Returns the number of bytes copied (0 = timeout), or -1 on failure (device gone).
  virtual int Read(uint8_t* buffer, size_t max, Duration timeout, std::string* error) = 0;

  // Sets the line speed; takes effect for bytes written afterwards. False when the rate is
  // not supported (by the code, or by the device: a UART that would run at another rate) or
  // the device is gone. The rate is kept across `Reopen()`.
  virtual bool SetBaudRate(int baud, std::string* error) = 0;
  virtual int baud_rate() const = 0;

  // Discards received-but-unread input and unsent output.
  virtual void Flush() = 0;

  virtual bool IsOpen() const = 0;
  // Closes (if open) and opens the same device again with the current baud rate.
  virtual bool Reopen(std::string* error) = 0;
  virtual void Close() = 0;

  // Human-readable name of the device (path), for logs and health messages.
  virtual std::string name() const = 0;
};

}  // namespace mostar::laser
