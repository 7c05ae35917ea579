// Baud rates in bits/s to libserial's enumeration, shared by the serial devices (LMS200 laser,
// motor board). Which rates a device accepts is the device's business; this only maps.
#pragma once

#include <libserial/SerialPortConstants.h>

#include <optional>

namespace mostar::serial {

// The libserial rate for `baud` bits/s, or nothing when libserial has no such rate.
std::optional<LibSerial::BaudRate> ToLibSerialBaudRate(int baud);

}  // namespace mostar::serial
