// MakeTempDir's directories are removed when the test program passes and kept when it fails.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>

#include "common/testing/subprocess.h"

namespace mostar::testing {
namespace {

namespace fs = std::filesystem;

// Runs the child test program; its temp dir ("" when it printed none) and its output.
std::string RunChild(bool fail, std::string* output) {
  const std::string work = MakeTempDir("mostar_temp_dir_test_");
  EXPECT_FALSE(work.empty());
  if (fail) {
    ::setenv("MOSTAR_TEMP_DIR_CHILD_FAILS", "1", 1);
  } else {
    ::unsetenv("MOSTAR_TEMP_DIR_CHILD_FAILS");
  }
  Subprocess child;
  std::string error;
  EXPECT_TRUE(child.Start({MOSTAR_TEMP_DIR_CHILD}, work + "/child.log", &error)) << error;
  const std::optional<int> status = child.Wait(std::chrono::seconds(30));
  ::unsetenv("MOSTAR_TEMP_DIR_CHILD_FAILS");
  EXPECT_EQ(status, fail ? std::optional<int>(1) : std::optional<int>(0));
  *output = ReadFile(work + "/child.log");
  std::smatch match;
  const std::regex dir_line("dir=(\\S+)");
  return std::regex_search(*output, match, dir_line) ? match[1].str() : std::string();
}

TEST(MakeTempDirTest, RemovesItsDirectoriesWhenEveryTestPassed) {
  std::string output;
  const std::string dir = RunChild(/*fail=*/false, &output);
  ASSERT_FALSE(dir.empty()) << output;
  EXPECT_FALSE(fs::exists(dir)) << "left behind: " << dir;
  EXPECT_EQ(output.find("kept for inspection"), std::string::npos) << output;
}

TEST(MakeTempDirTest, KeepsThemAndNamesThemWhenATestFailed) {
  std::string output;
  const std::string dir = RunChild(/*fail=*/true, &output);
  ASSERT_FALSE(dir.empty()) << output;
  EXPECT_TRUE(fs::exists(dir + "/output.txt")) << "removed: " << dir;
  EXPECT_NE(output.find("kept for inspection: " + dir), std::string::npos) << output;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mostar::testing
