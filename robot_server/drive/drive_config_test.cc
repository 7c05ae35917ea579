#include "robot_server/drive/drive_config.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "common/config/config_loader.h"

namespace mostar::drive {
namespace {

std::string SourceDir() {
  // The environment wins; the build's source directory is the fallback.
  const char* dir = std::getenv("MOSTAR_SOURCE_DIR");
  return dir ? dir : MOSTAR_TEST_SOURCE_DIR;
}

TEST(DriveConfigTest, ShippedMorducConfigLoadsAndValidates) {
  DriveConfig config;
  std::string error;
  ASSERT_TRUE(LoadTextConfig(SourceDir() + "/deploy/config/drive_morduc.pbtxt", &config, &error))
      << error;
  DriveSettings settings;
  ASSERT_TRUE(DriveSettingsFromProto(config, &settings, &error)) << error;
  EXPECT_EQ(settings.odometry.ticks_per_turn, 500);
  EXPECT_EQ(settings.safety.deadman_period, std::chrono::milliseconds(250));
  EXPECT_GT(settings.roles.size(), 0u);
}

TEST(DriveConfigTest, DefaultsAreValid) {
  DriveSettings settings;
  std::string error;
  EXPECT_TRUE(DriveSettingsFromProto(DriveConfig{}, &settings, &error)) << error;
  EXPECT_EQ(settings.motors.port, "/dev/mostar-drive");
  EXPECT_EQ(settings.roles.Lookup("anyone").role, Role::kObserver);
}

TEST(DriveConfigTest, SonarRulesAreConfigurable) {
  DriveConfig config;
  std::string error;
  ASSERT_TRUE(ParseTextConfig("safety { sonar_max_age_ms: 400 sonar_arc_step_m: 0.1 }",
                              "test.pbtxt", &config, &error))
      << error;
  DriveSettings settings;
  ASSERT_TRUE(DriveSettingsFromProto(config, &settings, &error)) << error;
  EXPECT_EQ(settings.safety.sonar_max_age, std::chrono::milliseconds(400));
  EXPECT_EQ(settings.safety.sonar_arc_step_m, 0.1);
  EXPECT_FALSE(ParseTextConfig("safety { sonar_arc_step_m: 0 }", "test.pbtxt", &config, &error));
  EXPECT_NE(error.find("sonar_arc_step_m"), std::string::npos) << error;
}

TEST(DriveConfigTest, RefusesAnOutOfRangeValueWithTheKey) {
  DriveConfig config;
  std::string error;
  EXPECT_FALSE(ParseTextConfig("safety { deadman_period_ms: 5 }", "test.pbtxt", &config, &error));
  EXPECT_NE(error.find("deadman_period_ms"), std::string::npos) << error;
}

TEST(DriveConfigTest, RefusesInconsistentDistancesAndDuplicateRoles) {
  DriveConfig config;
  std::string error;
  ASSERT_TRUE(
      ParseTextConfig("safety { stop_distance_m: 2 slow_distance_m: 1 }", "t", &config, &error))
      << error;
  DriveSettings settings;
  EXPECT_FALSE(DriveSettingsFromProto(config, &settings, &error));
  EXPECT_NE(error.find("slow_distance_m"), std::string::npos) << error;

  ASSERT_TRUE(ParseTextConfig(
      "roles { client_id: 'a' role: PILOT } roles { client_id: 'a' role: OBSERVER }", "t", &config,
      &error))
      << error;
  EXPECT_FALSE(DriveSettingsFromProto(config, &settings, &error));
  EXPECT_NE(error.find("twice"), std::string::npos) << error;
}

// Role ids are client ids: with DDS Security the CN of each client's certificate.
TEST(DriveConfigTest, RefusesRoleIdsThatAreNoClientIds) {
  for (const char* id : {"", "alice smith", "a,b", "CN=alice"}) {
    DriveConfig config;
    std::string error;
    ASSERT_TRUE(ParseTextConfig("roles { client_id: '" + std::string(id) + "' role: PILOT }", "t",
                                &config, &error))
        << error;
    DriveSettings settings;
    EXPECT_FALSE(DriveSettingsFromProto(config, &settings, &error)) << id;
    EXPECT_NE(error.find("roles: client_id"), std::string::npos) << error;
  }
}

}  // namespace
}  // namespace mostar::drive
