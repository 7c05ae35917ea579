#include "robot_server/serial/baud_rate.h"

#include <gtest/gtest.h>

namespace mostar::serial {
namespace {

TEST(BaudRateTest, MapsTheDevicesRatesAndRefusesOthers) {
  EXPECT_EQ(ToLibSerialBaudRate(9600), LibSerial::BaudRate::BAUD_9600);
  EXPECT_EQ(ToLibSerialBaudRate(38400), LibSerial::BaudRate::BAUD_38400);    // LMS200
  EXPECT_EQ(ToLibSerialBaudRate(500000), LibSerial::BaudRate::BAUD_500000);  // LMS200 on RS-422
  EXPECT_EQ(ToLibSerialBaudRate(115200), LibSerial::BaudRate::BAUD_115200);  // motor board
  EXPECT_FALSE(ToLibSerialBaudRate(0).has_value());
  EXPECT_FALSE(ToLibSerialBaudRate(12345).has_value());
  EXPECT_FALSE(ToLibSerialBaudRate(-9600).has_value());
}

}  // namespace
}  // namespace mostar::serial
