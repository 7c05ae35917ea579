// libserial helpers shared by the serial devices (LMS200 laser, motor board): baud rates in
// bits/s to libserial's enumeration (which rates a device accepts is the device's business),
// and closing a port whose device may have vanished.
#pragma once

#include <libserial/SerialPort.h>
#include <libserial/SerialPortConstants.h>

#include <memory>
#include <optional>

namespace mostar::serial {

// The libserial rate for `baud` bits/s, or nothing when libserial has no such rate.
std::optional<LibSerial::BaudRate> ToLibSerialBaudRate(int baud);

// Closes `*port` and leaves it null. When the device vanished (unplugged adapter, closed pty)
// libserial cannot restore the line settings, keeps the port marked open and would throw from
// its destructor: the descriptor is then closed here and the small object abandoned (once per
// unplug).
void ClosePort(std::unique_ptr<LibSerial::SerialPort>* port);

}  // namespace mostar::serial
