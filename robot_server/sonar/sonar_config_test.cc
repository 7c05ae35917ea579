#include "robot_server/sonar/sonar_config.h"

#include <google/protobuf/text_format.h>
#include <gtest/gtest.h>

#include <cmath>

namespace mostar::sonar {
namespace {

SonarConfig Parse(const std::string& text) {
  SonarConfig c;
  EXPECT_TRUE(google::protobuf::TextFormat::ParseFromString(text, &c)) << text;
  return c;
}

TEST(SonarConfigTest, SensorsGroupsAndTimingBecomeDriverOptions) {
  const SonarConfig config = Parse(
      "sensors { address: 112 frame_id: 'front' x_m: 0.3 yaw_deg: 0 }\n"
      "sensors { address: 113 x_m: -0.3 yaw_deg: 180 }\n"
      "ping_groups { sensor: 0 sensor: 1 }\n"
      "max_range_m: 3 ranging_time_ms: 20");
  Srf08RingOptions options;
  std::string error;
  ASSERT_TRUE(Srf08RingOptionsFromConfig(config, &options, &error)) << error;
  ASSERT_EQ(options.sensors.size(), 2u);
  EXPECT_EQ(options.sensors[0].address, 0x70);
  EXPECT_EQ(options.sensors[0].mount.frame_id, "front");
  EXPECT_EQ(options.sensors[1].mount.frame_id, "sonar_1");  // default name
  EXPECT_NEAR(options.sensors[1].mount.yaw_rad, M_PI, 1e-12);
  ASSERT_EQ(options.ping_groups.size(), 1u);
  EXPECT_EQ(options.ping_groups[0], (std::vector<int>{0, 1}));
  EXPECT_EQ(options.ranging_time, std::chrono::milliseconds(20));
  EXPECT_NEAR(options.field_of_view_rad, 55 * M_PI / 180, 1e-12);
}

TEST(SonarConfigTest, AnInconsistentBeltIsRefusedWithTheReason) {
  Srf08RingOptions options;
  std::string error;
  EXPECT_FALSE(Srf08RingOptionsFromConfig(
      Parse("sensors { address: 112 } sensors { address: 112 }"), &options, &error));
  EXPECT_NE(error.find("sonar:"), std::string::npos) << error;
  EXPECT_NE(error.find("address used twice"), std::string::npos) << error;
  EXPECT_FALSE(Srf08RingOptionsFromConfig(
      Parse("sensors { address: 112 } ping_groups { sensor: 3 }"), &options, &error));
  EXPECT_NE(error.find("out of range"), std::string::npos) << error;
}

}  // namespace
}  // namespace mostar::sonar
