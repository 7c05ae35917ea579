#include "robot_server/laser/lms200_crc.h"

namespace mostar::laser {

uint16_t Lms200Crc(const uint8_t* data, size_t size) {
  constexpr uint16_t kGenerator = 0x8005;
  uint16_t crc = 0;
  uint8_t previous = 0;
  for (size_t i = 0; i < size; ++i) {
    const uint8_t current = data[i];
    if ((crc & 0x8000u) != 0) {
      crc = static_cast<uint16_t>(((crc & 0x7FFFu) << 1) ^ kGenerator);
    } else {
      crc = static_cast<uint16_t>(crc << 1);
    }
    crc ^= static_cast<uint16_t>((previous << 8) | current);
    previous = current;
  }
  return crc;
}

}  // namespace mostar::laser
