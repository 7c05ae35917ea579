#include "robot_server/laser/lms200_crc.h"

#include <gtest/gtest.h>

#include <vector>

namespace mostar::laser {
namespace {

uint16_t CrcOf(const std::vector<uint8_t>& bytes) { return Lms200Crc(bytes.data(), bytes.size()); }

TEST(Lms200CrcTest, MatchesTelegramListingVectors) {
  EXPECT_EQ(CrcOf({0x02, 0x00, 0x01, 0x00, 0x31}), 0x1215);  // status request
  EXPECT_EQ(CrcOf({0x02, 0x00, 0x01, 0x00, 0x10}), 0x1234);  // reset
  EXPECT_EQ(CrcOf({0x02, 0x00, 0x02, 0x00, 0x20, 0x24}), 0x0834);
  EXPECT_EQ(CrcOf({0x02, 0x80, 0x03, 0x00, 0xA0, 0x00, 0x10}), 0x0A16);
}

TEST(Lms200CrcTest, EmptyInputIsZero) { EXPECT_EQ(Lms200Crc(nullptr, 0), 0); }

}  // namespace
}  // namespace mostar::laser
