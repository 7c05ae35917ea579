#include "common/config/config_report.h"

#include <gtest/gtest.h>

#include <sstream>

namespace mostar {
namespace {

TEST(ConfigReportTest, AllWellExitsZeroAndCountsTheChecks) {
  ConfigReport report;
  report.Ok("configuration loads");
  report.Ok("scene found");
  std::ostringstream out;
  EXPECT_EQ(report.Print("robot_server", out), 0);
  EXPECT_NE(out.str().find("ok: scene found"), std::string::npos);
  EXPECT_NE(out.str().find("complete (2 checks)"), std::string::npos);
}

TEST(ConfigReportTest, EachProblemIsPrintedWithItsFix) {
  ConfigReport report;
  report.Ok("configuration loads");
  report.Fail("/dev/lms200 does not exist", "plug the laser in");
  report.Fail("role CHANGE-ME-pilot", "name your pilot");
  std::ostringstream out;
  EXPECT_EQ(report.Print("robot_server", out), 1);
  EXPECT_NE(out.str().find("PROBLEM: /dev/lms200 does not exist\n  fix: plug the laser in"),
            std::string::npos);
  EXPECT_NE(out.str().find("2 problems to fix (1 checks passed)"), std::string::npos);
  EXPECT_TRUE(report.HasProblem("CHANGE-ME"));
  EXPECT_FALSE(report.HasProblem("camera"));
}

}  // namespace
}  // namespace mostar
