#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "common/testing/subprocess.h"

namespace mostar::testing {
namespace {

TEST(WaitForTextTest, SeesALineWrittenLaterAndGivesUpAtTheTimeout) {
  const std::string dir = MakeTempDir("mostar_wait_for_text_test_");
  ASSERT_FALSE(dir.empty());
  const std::string path = dir + "/server.log";
  std::thread writer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    std::ofstream(path) << "starting\nLMS200: streaming at 38400 Bd\n";
  });
  EXPECT_TRUE(WaitForText(path, "streaming at", std::chrono::seconds(30)));
  writer.join();
  EXPECT_FALSE(WaitForText(path, "stopping", std::chrono::milliseconds(200)));
  EXPECT_FALSE(WaitForText(dir + "/missing.log", "streaming", std::chrono::milliseconds(100)));
}

}  // namespace
}  // namespace mostar::testing
