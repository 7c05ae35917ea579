// --check-config of DDS profiles, on a real PKI made by deploy/security/make_pki.sh: each
// mistake a user can make is reported with its fix, and a good bundle passes.
#include "common/dds/profile_check.h"

#include <fastrtps/xmlparser/XMLProfileManager.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "common/testing/dds_profiles.h"
#include "common/testing/subprocess.h"

namespace mostar::dds {
namespace {

std::string Sh(const std::string& command) { return "sh -c '" + command + "' >/dev/null 2>&1"; }

// A PKI (robot, pilot alice, relay hub) in a fresh folder; its path ("" on failure).
std::string MakePki() {
  const std::string dir = mostar::testing::MakeTempDir("profile_check");
  const std::string pki = dir + "/pki";
  const std::string cmd = std::string(MOSTAR_TEST_SOURCE_DIR) + "/deploy/security/make_pki.sh " +
                          pki + " --robot robot --pilot alice --relay hub >/dev/null 2>&1";
  return std::system(cmd.c_str()) == 0 ? pki : "";
}

// Fast DDS keeps loaded profiles for the whole process and ignores a later file's profiles of
// the same names: each test starts from none.
class ProfileCheckTest : public ::testing::Test {
 protected:
  void SetUp() override { eprosima::fastrtps::xmlparser::XMLProfileManager::DeleteInstance(); }
};

ParticipantOptions Robot(const std::string& profile) {
  ParticipantOptions options;
  options.profile = profile;
  options.name = "robot";
  return options;
}

TEST_F(ProfileCheckTest, LoopbackNeedsNothing) {
  ConfigReport report;
  const ProfileCheck check = CheckDdsProfile(Robot("loopback"), "mostar", &report);
  EXPECT_TRUE(report.all_well());
  EXPECT_FALSE(check.secure);
}

TEST_F(ProfileCheckTest, AMissingProfileFileIsNamed) {
  ConfigReport report;
  CheckDdsProfile(Robot("/nonexistent/robot.xml"), "mostar", &report);
  EXPECT_TRUE(report.HasProblem("/nonexistent/robot.xml cannot be read"));
  EXPECT_TRUE(report.HasProblem("make_pki.sh"));
}

TEST_F(ProfileCheckTest, AGoodBundlePassesAndNamesItsClientId) {
  const std::string pki = MakePki();
  ASSERT_FALSE(pki.empty());
  ConfigReport report;
  const ProfileCheck check = CheckDdsProfile(Robot(pki + "/hosts/robot/robot.xml"), "", &report);
  for (const auto& p : report.problems()) ADD_FAILURE() << p.what;
  EXPECT_TRUE(check.secure);
  ASSERT_TRUE(check.own_client_id.has_value());
  EXPECT_EQ(*check.own_client_id, "robot");
  EXPECT_EQ(check.certificate_path, pki + "/robot.cert.pem");  // make_pki's --install-dir
}

TEST_F(ProfileCheckTest, MissingSecurityFilesAndWrongParticipantNamesAreReported) {
  const std::string pki = MakePki();
  ASSERT_FALSE(pki.empty());
  ASSERT_EQ(std::system(Sh("rm " + pki + "/robot.permissions.p7s").c_str()), 0);
  ConfigReport report;
  CheckDdsProfile(Robot(pki + "/robot.xml"), "", &report);
  EXPECT_TRUE(report.HasProblem("robot.permissions.p7s cannot be read"))
      << report.problems().size();
  EXPECT_TRUE(report.HasProblem("hosts/NAME/"));

  ConfigReport wrong_name;
  ParticipantOptions options = Robot(pki + "/alice.xml");
  options.name = "nobody";
  CheckDdsProfile(options, "", &wrong_name);
  EXPECT_TRUE(wrong_name.HasProblem("no participant profile named 'nobody'"));
}

TEST_F(ProfileCheckTest, AnExpiredRevocationListIsCaught) {
  const std::string pki = MakePki();
  ASSERT_FALSE(pki.empty());
  // A CRL whose next update was in 2020 (OpenSSL 3's explicit update dates).
  ASSERT_EQ(std::system(Sh("cd " + pki +
                           " && openssl ca -batch -config ca.cnf -gencrl -crl_lastupdate "
                           "20200101000000Z -crl_nextupdate 20200102000000Z -out "
                           "identity_ca.crl.pem")
                            .c_str()),
            0);
  ConfigReport report;
  CheckDdsProfile(Robot(pki + "/robot.xml"), "", &report);
  EXPECT_TRUE(report.HasProblem("has expired")) << report.problems().size();
  EXPECT_TRUE(report.HasProblem("--refresh-crl"));
}

TEST_F(ProfileCheckTest, AProfileWithoutSecurityNeedsInsecure) {
  const std::string dir = mostar::testing::MakeTempDir("profile_check");
  const std::string profile = mostar::testing::WriteLoopbackUdpProfile(dir, "robot");
  ASSERT_FALSE(profile.empty());
  ConfigReport refused;
  CheckDdsProfile(Robot(profile), "", &refused);
  EXPECT_TRUE(refused.HasProblem("make_pki.sh"));
  ConfigReport allowed;
  ParticipantOptions options = Robot(profile);
  options.insecure = true;
  CheckDdsProfile(options, "", &allowed);
  EXPECT_TRUE(allowed.all_well());
}

// The overlay address of a robot started before its WireGuard interface.
TEST_F(ProfileCheckTest, AWhitelistedAddressMissingOnThisHostIsNamed) {
  const std::string dir = mostar::testing::MakeTempDir("profile_check");
  const std::string path = dir + "/robot.xml";
  std::ofstream(path) << R"(<?xml version="1.0" encoding="UTF-8" ?>
<profiles xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <transport_descriptors><transport_descriptor>
    <transport_id>overlay</transport_id><type>UDPv4</type>
    <interfaceWhiteList><address>10.254.77.2</address></interfaceWhiteList>
  </transport_descriptor></transport_descriptors>
  <participant profile_name="robot"><rtps>
    <useBuiltinTransports>false</useBuiltinTransports>
    <userTransports><transport_id>overlay</transport_id></userTransports>
  </rtps></participant>
</profiles>
)";
  ConfigReport report;
  ParticipantOptions options = Robot(path);
  options.insecure = true;
  CheckDdsProfile(options, "", &report);
  EXPECT_TRUE(report.HasProblem("address 10.254.77.2 of the profile's interfaceWhiteList"));
  EXPECT_TRUE(report.HasProblem("wg-quick"));
}

}  // namespace
}  // namespace mostar::dds
