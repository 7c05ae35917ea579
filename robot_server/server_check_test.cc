// robot_server --check-config: the shipped examples, the mistakes a new user makes (a copied
// simulator configuration, placeholder roles, devices missing, a role table that does not match
// the certificates) each reported with its fix.
#include "robot_server/server_check.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "common/config/config_loader.h"
#include "common/config/config_paths.h"
#include "common/testing/subprocess.h"

namespace mostar::server {
namespace {

const std::string kConfigDir = std::string(MOSTAR_TEST_SOURCE_DIR) + "/deploy/config";

ServerConfig Load(const std::string& name) {
  ServerConfig config;
  std::string error;
  EXPECT_TRUE(LoadTextConfig(kConfigDir + "/" + name, &config, &error)) << error;
  return config;
}

void AddRole(ServerConfig* config, const std::string& id, drive::PilotRole::Role role) {
  drive::PilotRole* r = config->mutable_drive()->add_roles();
  r->set_client_id(id);
  r->set_role(role);
  if (role == drive::PilotRole::PILOT) r->set_strength(10);
}

TEST(ServerCheckTest, TheSimulatorExampleNeedsNothingMore) {
  ConfigReport report;
  CheckServerFiles(Load("server_sim.pbtxt"), kConfigDir, &report);
  for (const auto& p : report.problems()) ADD_FAILURE() << p.what;
  EXPECT_GE(report.ok().size(), 3u);
}

TEST(ServerCheckTest, ARepairDeadlineWithinTheRepairPeriodIsAProblem) {
  ServerConfig config = Load("server_sim.pbtxt");
  config.mutable_dds()->set_video_repair_period_ms(250);
  config.mutable_dds()->set_video_repair_deadline_ms(200);
  ConfigReport report;
  CheckServerFiles(config, kConfigDir, &report);
  EXPECT_TRUE(report.HasProblem("video_repair_deadline_ms 200 is not longer than"));
  config.mutable_dds()->set_video_repair_deadline_ms(650);
  ConfigReport fine;
  CheckServerFiles(config, kConfigDir, &fine);
  EXPECT_FALSE(fine.HasProblem("video_repair_deadline_ms"));
}

TEST(ServerCheckTest, AMissingSceneIsNamedWithWhereItWasLookedFor) {
  ServerConfig config = Load("server_sim.pbtxt");
  config.set_scene_file("../scenes/no_such_scene.pbtxt");
  ConfigReport report;
  CheckServerFiles(config, kConfigDir, &report);
  EXPECT_TRUE(report.HasProblem("no_such_scene.pbtxt does not exist"));
  EXPECT_TRUE(report.HasProblem(InstalledConfigDir()));
}

// The packaged /etc/mostar/server.pbtxt on a computer without the robot's devices.
TEST(ServerCheckTest, TheHardwareExampleNamesEachMissingDeviceAndPlaceholder) {
  const ServerConfig config = Load("server_morduc.pbtxt");
  ASSERT_EQ(config.source(), ServerConfig::HARDWARE);
  ConfigReport report;
  CheckServerFiles(config, kConfigDir, &report);
  CheckRoleTable(config, std::nullopt, &report);
  EXPECT_TRUE(report.HasProblem("LMS200 port /dev/lms200 does not exist"));
  EXPECT_TRUE(report.HasProblem("60-mostar-lms200.rules"));
  EXPECT_TRUE(report.HasProblem("motor board port /dev/mostar-drive does not exist"));
  EXPECT_TRUE(report.HasProblem("'CHANGE-ME-pilot' is a placeholder"));
  EXPECT_FALSE(report.HasProblem("intrinsics"));  // the example intrinsics resolve
}

TEST(ServerCheckTest, ARoleTableWithoutPilotsIsAProblem) {
  ServerConfig config;
  AddRole(&config, "carol", drive::PilotRole::OBSERVER);
  ConfigReport report;
  CheckRoleTable(config, std::nullopt, &report);
  EXPECT_TRUE(report.HasProblem("no PILOT"));
}

// The README's old Internet snippet: server_sim.pbtxt's names with the recipe's certificates.
TEST(ServerCheckTest, TheRoleTableIsComparedWithTheCertificates) {
  const std::map<std::string, std::string> pki = {
      {"robot", "robot"}, {"alice", "pilot"}, {"carol", "observer"}, {"hub", "relay"}};
  ServerConfig config;
  AddRole(&config, "operator", drive::PilotRole::PILOT);
  AddRole(&config, "relay", drive::PilotRole::OBSERVER);
  ConfigReport report;
  CheckRoleTable(config, pki, &report);
  EXPECT_TRUE(report.HasProblem("'operator' has no certificate"));
  EXPECT_TRUE(report.HasProblem("'relay' has no certificate"));
  EXPECT_TRUE(report.HasProblem("'alice' holds a pilot certificate"));
  EXPECT_TRUE(report.HasProblem("roles { client_id: \"alice\" role: PILOT"));
  EXPECT_TRUE(report.HasProblem("the relay 'hub' is not in the role table"));
  EXPECT_FALSE(report.HasProblem("carol"));  // unlisted observers just watch

  ServerConfig good;
  AddRole(&good, "alice", drive::PilotRole::PILOT);
  AddRole(&good, "hub", drive::PilotRole::OBSERVER);
  ConfigReport fine;
  CheckRoleTable(good, pki, &fine);
  for (const auto& p : fine.problems()) ADD_FAILURE() << p.what;
}

TEST(ServerCheckTest, PkiRolesAreReadFromMakePkisFile) {
  const std::string dir = testing::MakeTempDir("server_check");
  std::ofstream(dir + "/roles") << "robot robot\nalice pilot\n\nhub relay\n";
  std::map<std::string, std::string> roles;
  std::string error;
  ASSERT_TRUE(ReadPkiRoles(dir + "/roles", &roles, &error)) << error;
  EXPECT_EQ(roles.size(), 3u);
  EXPECT_EQ(roles["alice"], "pilot");
  std::ofstream(dir + "/bad") << "alice\n";
  EXPECT_FALSE(ReadPkiRoles(dir + "/bad", &roles, &error));
  EXPECT_NE(error.find(":1:"), std::string::npos);
}

// Everything together, with a bundle made by make_pki.sh: the roles file travels with it.
TEST(ServerCheckTest, AFullCheckReadsTheRolesFileOfTheRobotsBundle) {
  const std::string dir = testing::MakeTempDir("server_check");
  const std::string pki = dir + "/pki";
  const std::string cmd = std::string(MOSTAR_TEST_SOURCE_DIR) + "/deploy/security/make_pki.sh " +
                          pki + " --install-dir " + pki +
                          "/hosts/robot --robot robot --pilot alice --relay hub >/dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  dds::ParticipantOptions dds;
  dds.profile = pki + "/hosts/robot/robot.xml";
  dds.name = "robot";
  ConfigReport report;
  CheckServerConfig(Load("server_sim.pbtxt"), kConfigDir, dds, &report);
  EXPECT_TRUE(report.HasProblem("'operator' has no certificate"));
  EXPECT_TRUE(report.HasProblem("'alice' holds a pilot certificate"));

  ServerConfig fixed = Load("server_sim.pbtxt");
  fixed.mutable_drive()->clear_roles();
  AddRole(&fixed, "alice", drive::PilotRole::PILOT);
  AddRole(&fixed, "hub", drive::PilotRole::OBSERVER);
  ConfigReport fine;
  CheckServerConfig(fixed, kConfigDir, dds, &fine);
  for (const auto& p : fine.problems()) ADD_FAILURE() << p.what;

  // alice's certificate revoked: the robot's bundle says so, and her line must go.
  const std::string revoke = std::string(MOSTAR_TEST_SOURCE_DIR) + "/deploy/security/revoke.sh " +
                             pki + " alice >/dev/null 2>&1";
  ASSERT_EQ(std::system(revoke.c_str()), 0);
  ConfigReport revoked;
  CheckServerConfig(fixed, kConfigDir, dds, &revoked);
  EXPECT_TRUE(revoked.HasProblem("'alice' was revoked"));
}

TEST(ServerCheckTest, ARevokedNameInTheRoleTableIsAProblem) {
  const std::map<std::string, std::string> pki = {
      {"robot", "robot"}, {"alice", "revoked"}, {"bob", "pilot"}, {"carol", "revoked"}};
  ServerConfig config;
  AddRole(&config, "alice", drive::PilotRole::PILOT);
  AddRole(&config, "bob", drive::PilotRole::PILOT);
  ConfigReport report;
  CheckRoleTable(config, pki, &report);
  EXPECT_TRUE(report.HasProblem("'alice' was revoked"));
  EXPECT_TRUE(report.HasProblem("make_pki.sh --pilot alice"));
  EXPECT_FALSE(report.HasProblem("has no certificate"));
  EXPECT_FALSE(report.HasProblem("carol"));  // revoked and not in the table: nothing to do
  EXPECT_FALSE(report.HasProblem("bob"));
}

}  // namespace
}  // namespace mostar::server
