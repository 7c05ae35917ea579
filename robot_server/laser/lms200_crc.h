// The SICK LMS2xx telegram checksum (Telegram Listing LMS2xx, chapter 9).
//
// Not a standard CRC-16: the register is shifted once per byte and the XOR term is the pair
// (previous byte, current byte). Generator 0x8005, initial value 0, no reflection, no final
// XOR. It covers every byte from STX up to the last data byte (requests) or the status byte
// (replies) and is transmitted low byte first.
#pragma once

#include <cstddef>
#include <cstdint>

namespace mostar::laser {

uint16_t Lms200Crc(const uint8_t* data, size_t size);

}  // namespace mostar::laser
