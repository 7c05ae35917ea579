// A test program for temp_dir_test: makes a temp dir with a file in it, prints "dir=PATH" and
// fails when MOSTAR_TEMP_DIR_CHILD_FAILS is set.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "common/testing/subprocess.h"

TEST(TempDirChild, MakesADirectoryWithAFile) {
  const std::string dir = mostar::testing::MakeTempDir("mostar_temp_dir_child_");
  ASSERT_FALSE(dir.empty());
  std::ofstream(dir + "/output.txt") << "a test's output\n";
  std::printf("dir=%s\n", dir.c_str());
  if (std::getenv("MOSTAR_TEMP_DIR_CHILD_FAILS") != nullptr) ADD_FAILURE() << "failing on request";
}
