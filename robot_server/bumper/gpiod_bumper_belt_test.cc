// The GPIO backend without GPIO hardware: options and the errors a user meets. (Reading real
// lines needs a GPIO chip; the simulator's belt covers the behaviour behind the interface.)
#include "robot_server/bumper/gpiod_bumper_belt.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mostar::bumper {
namespace {

TEST(GpiodBumperBeltTest, OptionsNeedLinesEachOnce) {
  std::string error;
  GpiodBumperOptions o;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("lines"), std::string::npos);
  o.lines = {3, 4, 3};
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("twice"), std::string::npos);
  o.lines = {3, 4, 5};
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o.lines.assign(33, 0);
  EXPECT_FALSE(o.IsValid(&error));
}

TEST(GpiodBumperBeltTest, AMissingChipIsNamed) {
  GpiodBumperOptions o;
  o.chip = "/dev/gpiochip-mostar-missing";
  o.lines = {0, 1};
  std::string error;
  EXPECT_EQ(GpiodBumperBelt::Open(o, &error), nullptr);
  EXPECT_NE(error.find("/dev/gpiochip-mostar-missing"), std::string::npos) << error;
}

TEST(BumperBeltTest, SegmentsGoCounterClockwiseFromAhead) {
  EXPECT_DOUBLE_EQ(SegmentAngleRad(0, 16), 0.0);
  EXPECT_DOUBLE_EQ(SegmentAngleRad(4, 16), M_PI / 2);  // left
  EXPECT_DOUBLE_EQ(SegmentAngleRad(8, 16), M_PI);      // behind
}

}  // namespace
}  // namespace mostar::bumper
