// libserial helpers shared by the serial devices (LMS200 laser, motor board): baud rates in
// bits/s to libserial's enumeration (which rates a device accepts is the device's business),
// and closing a port whose device may have vanished.
#pragma once

#include <libserial/SerialPort.h>
#include <libserial/SerialPortConstants.h>
#include <termios.h>

#include <memory>
#include <optional>

namespace mostar::serial {

// The libserial rate for `baud` bits/s, or nothing when libserial has no such rate.
std::optional<LibSerial::BaudRate> ToLibSerialBaudRate(int baud);

// Bits/s of a termios speed constant (B500000 -> 500000); 0 for B0, BOTHER or an unknown one.
int BaudOfTermiosSpeed(speed_t speed);

// The output rate in force on the open terminal `fd`, read back from the kernel (a driver
// that cannot run at the rate asked for keeps or substitutes another); 0 when it is not a
// standard rate, -1 when the line settings cannot be read.
int LineBaud(int fd);

// Closes `*port` and leaves it null. When the device vanished (unplugged adapter, closed pty)
// libserial cannot restore the line settings, keeps the port marked open and would throw from
// its destructor: the descriptor is then closed here and the small object abandoned (once per
// unplug).
void ClosePort(std::unique_ptr<LibSerial::SerialPort>* port);

}  // namespace mostar::serial
