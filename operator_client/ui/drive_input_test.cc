#include "operator_client/ui/drive_input.h"

#include <gtest/gtest.h>

#include <limits>

namespace mostar::ui {
namespace {

TEST(DriveMapperTest, NothingHeldMeansDisabledZero) {
  DriveMapper mapper(DriveLimits{});
  const DriveOutput out = mapper.Map({});
  EXPECT_FALSE(out.enable);
  EXPECT_EQ(out.linear_mps, 0);
  EXPECT_EQ(out.angular_radps, 0);
}

TEST(DriveMapperTest, KeyboardForwardLeftAtHalfScale) {
  DriveLimits limits;
  limits.max_linear_mps = 0.8;
  limits.max_angular_radps = 1.2;
  DriveMapper mapper(limits);
  DriveInputState in;
  in.forward = true;
  in.left = true;
  const DriveOutput out = mapper.Map(in);
  EXPECT_TRUE(out.enable);
  EXPECT_DOUBLE_EQ(out.linear_mps, 0.4);
  EXPECT_DOUBLE_EQ(out.angular_radps, 0.6);
}

TEST(DriveMapperTest, KeyboardBackwardRight) {
  DriveMapper mapper(DriveLimits{});
  DriveInputState in;
  in.backward = true;
  in.right = true;
  const DriveOutput out = mapper.Map(in);
  EXPECT_LT(out.linear_mps, 0);
  EXPECT_LT(out.angular_radps, 0);
}

TEST(DriveMapperTest, GamepadNeedsDeadman) {
  DriveMapper mapper(DriveLimits{});
  DriveInputState in;
  in.gamepad_present = true;
  in.stick_linear = 1.0f;
  EXPECT_FALSE(mapper.Map(in).enable);
  in.gamepad_deadman = true;
  const DriveOutput out = mapper.Map(in);
  EXPECT_TRUE(out.enable);
  EXPECT_DOUBLE_EQ(out.linear_mps, 0.6 * 0.5);
}

TEST(DriveMapperTest, GamepadDeadzoneAndNaN) {
  DriveMapper mapper(DriveLimits{});
  DriveInputState in;
  in.gamepad_present = true;
  in.gamepad_deadman = true;
  in.stick_linear = 0.1f;
  in.stick_angular = std::numeric_limits<float>::quiet_NaN();
  const DriveOutput out = mapper.Map(in);
  EXPECT_TRUE(out.enable);
  EXPECT_EQ(out.linear_mps, 0);
  EXPECT_EQ(out.angular_radps, 0);
}

TEST(DriveMapperTest, ScaleStepsAndClamps) {
  DriveMapper mapper(DriveLimits{});
  for (int i = 0; i < 20; ++i) mapper.ScaleUp();
  EXPECT_DOUBLE_EQ(mapper.scale(), 1.0);
  for (int i = 0; i < 20; ++i) mapper.ScaleDown();
  EXPECT_DOUBLE_EQ(mapper.scale(), 0.1);
}

TEST(DriveLimitsTest, RejectsNonsense) {
  DriveLimits limits;
  std::string error;
  EXPECT_TRUE(limits.IsValid(&error));
  limits.max_linear_mps = -1;
  EXPECT_FALSE(limits.IsValid(&error));
  EXPECT_NE(error.find("max_linear_mps"), std::string::npos);
}

}  // namespace
}  // namespace mostar::ui
