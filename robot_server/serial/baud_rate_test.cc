#include "robot_server/serial/baud_rate.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>

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

TEST(BaudRateTest, ReadsBackTheRateInForceOnATerminal) {
  EXPECT_EQ(BaudOfTermiosSpeed(B500000), 500000);
  EXPECT_EQ(BaudOfTermiosSpeed(B9600), 9600);
  EXPECT_EQ(BaudOfTermiosSpeed(B0), 0);
  const int master = posix_openpt(O_RDWR | O_NOCTTY);
  ASSERT_GE(master, 0);
  ASSERT_EQ(grantpt(master), 0);
  ASSERT_EQ(unlockpt(master), 0);
  const int slave = ::open(ptsname(master), O_RDWR | O_NOCTTY);
  ASSERT_GE(slave, 0);
  for (speed_t speed : {B9600, B38400, B500000}) {
    termios tio{};
    ASSERT_EQ(tcgetattr(slave, &tio), 0);
    cfsetospeed(&tio, speed);
    cfsetispeed(&tio, speed);
    ASSERT_EQ(tcsetattr(slave, TCSANOW, &tio), 0);
    EXPECT_EQ(LineBaud(slave), BaudOfTermiosSpeed(speed));
  }
  ::close(slave);
  ::close(master);
  EXPECT_EQ(LineBaud(slave), -1);  // closed
}

}  // namespace
}  // namespace mostar::serial
