#include "common/config/config_paths.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <climits>

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

}  // namespace
}  // namespace mostar
