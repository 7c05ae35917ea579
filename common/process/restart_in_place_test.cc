#include "common/process/restart_in_place.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "common/process/stop_signals.h"

namespace mostar {
namespace {

// Each test runs in its own process (gtest_discover_tests): the flags start clear.
TEST(RestartInPlaceTest, ARestartRequestAlsoRequestsAStop) {
  EXPECT_FALSE(RestartRequested());
  RequestRestart();
  EXPECT_TRUE(RestartRequested());
  EXPECT_TRUE(StopRequested());
}

TEST(RestartInPlaceTest, NothingRememberedIsAnError) {
  std::string error;
  EXPECT_FALSE(RestartInPlace(&error, "/bin/sh"));
  EXPECT_NE(error.find("RememberCommandLine"), std::string::npos) << error;
}

// A child remembers a shell command line and restarts into it: the same process id runs the
// remembered arguments, and a descriptor the old image left open is closed in the new one.
TEST(RestartInPlaceTest, TheNewImageRunsTheRememberedArgumentsInTheSameProcessWithoutOldFds) {
  char dir_template[] = "/tmp/mostar_restart_XXXXXX";
  ASSERT_NE(mkdtemp(dir_template), nullptr);
  const std::string out = std::string(dir_template) + "/out";
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const int leaked = open("/dev/null", O_RDONLY);  // no O_CLOEXEC: would survive a plain exec
    // What the new image's descriptor of that number points to (the shell's own pipe, or
    // nothing), never /dev/null.
    const std::string script = "echo \"$$ " + std::to_string(getpid()) + " " +
                               std::to_string(leaked) + " $(readlink /proc/$$/fd/" +
                               std::to_string(leaked) + " || echo none)\" > " + out + "; exit 7";
    std::string sh = "sh", c = "-c";
    char* argv[] = {sh.data(), c.data(), const_cast<char*>(script.c_str()), nullptr};
    RememberCommandLine(3, argv);
    std::string error;
    RestartInPlace(&error, "/bin/sh");
    _exit(99);  // exec failed
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 7);
  std::ifstream in(out);
  std::string new_pid, old_pid, fd, state;
  in >> new_pid >> old_pid >> fd >> state;
  EXPECT_EQ(new_pid, old_pid);
  EXPECT_EQ(new_pid, std::to_string(child));
  EXPECT_NE(state, "/dev/null") << "descriptor " << fd << " survived the restart";
  EXPECT_FALSE(state.empty());
  std::remove(out.c_str());
  rmdir(dir_template);
}

TEST(RestartInPlaceTest, AFailedExecSaysWhy) {
  std::string prog = "mostar_missing";
  char* argv[] = {prog.data(), nullptr};
  RememberCommandLine(1, argv);
  std::string error;
  EXPECT_FALSE(RestartInPlace(&error, "/nonexistent/mostar_missing"));
  EXPECT_NE(error.find("/nonexistent/mostar_missing"), std::string::npos) << error;
}

}  // namespace
}  // namespace mostar
