#include "common/config/config_paths.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <climits>
#include <cstdlib>

namespace mostar {
namespace {

TEST(ConfigPathsTest, DirectoryOfAFile) {
  EXPECT_EQ(DirectoryOf("deploy/config/server_sim.pbtxt"), "deploy/config");
  EXPECT_EQ(DirectoryOf("/etc/mostar/server.pbtxt"), "/etc/mostar");
  EXPECT_EQ(DirectoryOf("server.pbtxt"), ".");
  EXPECT_EQ(DirectoryOf("/server.pbtxt"), "/");
}

TEST(ConfigPathsTest, RelativePathsAreResolvedAgainstTheBase) {
  EXPECT_EQ(ResolveRelativeTo("scenes/corridor.pbtxt", "deploy"), "deploy/scenes/corridor.pbtxt");
  EXPECT_EQ(ResolveRelativeTo("corridor.pbtxt", "/"), "/corridor.pbtxt");
  EXPECT_EQ(ResolveRelativeTo("../scenes/a.pbtxt", "deploy/config"),
            "deploy/config/../scenes/a.pbtxt");
}

TEST(ConfigPathsTest, AbsoluteEmptyOrBaselessPathsAreUnchanged) {
  EXPECT_EQ(ResolveRelativeTo("/var/lib/a.mostar", "deploy"), "/var/lib/a.mostar");
  EXPECT_EQ(ResolveRelativeTo("", "deploy"), "");
  EXPECT_EQ(ResolveRelativeTo("a.pbtxt", ""), "a.pbtxt");
}

TEST(ConfigPathsTest, CommandLinePathsAreMadeAbsoluteFromTheWorkingDirectory) {
  char cwd[PATH_MAX];
  ASSERT_NE(getcwd(cwd, sizeof(cwd)), nullptr);
  EXPECT_EQ(AbsoluteFromWorkingDirectory("run.mostar"), std::string(cwd) + "/run.mostar");
  EXPECT_EQ(AbsoluteFromWorkingDirectory("/tmp/run.mostar"), "/tmp/run.mostar");
  EXPECT_EQ(AbsoluteFromWorkingDirectory(""), "");
}

// An example copied out of the installed folder keeps finding its scene beside the original.
TEST(ConfigPathsTest, ConfigPathsFallBackToTheInstalledExamples) {
  const std::string root = testing::TempDir() + "config_paths_fallback";
  ASSERT_EQ(
      system(("rm -rf " + root + " && mkdir -p " + root + "/share/config " + root +
              "/share/scenes " + root + "/etc && touch " + root + "/share/scenes/corridor.pbtxt")
                 .c_str()),
      0);
  const std::string fallback = root + "/share/config";
  EXPECT_EQ(ResolveConfigPath("../scenes/corridor.pbtxt", root + "/etc", fallback),
            fallback + "/../scenes/corridor.pbtxt");
  // A file beside the configuration wins over the installed one.
  ASSERT_EQ(
      system(("mkdir -p " + root + "/scenes && touch " + root + "/scenes/corridor.pbtxt").c_str()),
      0);
  EXPECT_EQ(ResolveConfigPath("../scenes/corridor.pbtxt", root + "/etc", fallback),
            root + "/etc/../scenes/corridor.pbtxt");
  // Missing in both: the first candidate, for the caller's error.
  EXPECT_EQ(ResolveConfigPath("missing.pbtxt", root + "/etc", fallback),
            root + "/etc/missing.pbtxt");
  EXPECT_EQ(ResolveConfigPath("/abs/missing.pbtxt", root + "/etc", fallback), "/abs/missing.pbtxt");
  EXPECT_EQ(ResolveConfigPath("", root + "/etc", fallback), "");
  EXPECT_EQ(InstalledConfigDir().substr(InstalledConfigDir().size() - 13), "mostar/config");
}

}  // namespace
}  // namespace mostar
