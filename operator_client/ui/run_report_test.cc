#include "operator_client/ui/run_report.h"

#include <gtest/gtest.h>

#include <map>
#include <sstream>

namespace mostar::ui {
namespace {

// The report's key=value pairs, as the benches read them.
std::map<std::string, std::string> Parse(const std::string& line) {
  std::map<std::string, std::string> out;
  std::istringstream words(line);
  std::string word;
  words >> word;
  EXPECT_EQ(word, "report:");
  while (words >> word) {
    const size_t eq = word.find('=');
    EXPECT_NE(eq, std::string::npos) << word;
    EXPECT_EQ(out.count(word.substr(0, eq)), 0u) << "key twice: " << word;
    out[word.substr(0, eq)] = word.substr(eq + 1);
  }
  return out;
}

// A run that averaged 8.6 pairs/s but ended on a 30 Hz window says both, each under its name.
TEST(RunReportTest, TheRunsAverageAndTheLastWindowAreBothThere) {
  ConsoleRunTotals console;
  console.run_s = 40;
  client::ReceiverStats video;
  video.pairs_decoded = 344;
  video.pair_rate_hz = 30;
  const std::string line = FormatRunReport(console, video);
  ASSERT_FALSE(line.empty());
  EXPECT_EQ(line.back(), '\n');
  auto keys = Parse(line);
  EXPECT_EQ(keys["pairs_decoded"], "344");
  EXPECT_DOUBLE_EQ(std::stod(keys["pairs_per_s_run"]), 8.6);
  EXPECT_EQ(keys["pair_rate_hz_last_2s"], "30");
  EXPECT_EQ(keys.count("pair_rate_hz"), 0u);
}

TEST(RunReportTest, EveryCountHasItsKey) {
  ConsoleRunTotals console;
  console.rendered_frames = 11;
  console.scripted_rearms = 2;
  console.scans = 33;
  console.commands_sent = 44;
  console.run_s = 1;
  console.display_age_ms_p95 = 120.5;
  console.sonar_unseen = 3;
  console.overlays_faded = 4;
  console.vision_without_result = 6;
  console.vision_added_late = 5;
  console.latency = {{"decoded", 4.5, 8.25, 10}, {"total", 90, 140, 10}};
  console.frame_parts = {{"eyes", 3.5, 6.0, 10}};
  client::ReceiverStats video;
  video.broken_images = 5;
  video.video_gaps = 6;
  video.keyframe_requests = 7;
  video.pairs_dropped = 8;
  auto keys = Parse(FormatRunReport(console, video));
  EXPECT_EQ(keys["rendered_frames"], "11");
  EXPECT_EQ(keys["scripted_rearms"], "2");
  EXPECT_EQ(keys["scans"], "33");
  EXPECT_EQ(keys["commands_sent"], "44");
  EXPECT_EQ(keys["display_age_ms_p95"], "120.5");
  EXPECT_EQ(keys["sonar_unseen"], "3");
  EXPECT_EQ(keys["overlays_faded"], "4");
  EXPECT_EQ(keys["vision_without_result"], "6");
  EXPECT_EQ(keys["vision_added_late"], "5");
  EXPECT_EQ(keys["latency_decoded_ms_p50"], "4.5");
  EXPECT_EQ(keys["latency_decoded_ms_p95"], "8.25");
  EXPECT_EQ(keys["latency_total_ms_p95"], "140");
  EXPECT_EQ(keys["part_eyes_ms_p50"], "3.5");
  EXPECT_EQ(keys["part_eyes_ms_p95"], "6");
  EXPECT_EQ(keys["broken_images"], "5");
  EXPECT_EQ(keys["video_gaps"], "6");
  EXPECT_EQ(keys["pairs_dropped"], "8");
  EXPECT_EQ(keys["keyframe_requests"], "7");
  EXPECT_EQ(keys.count("captured_stamp_ns"), 0u);  // only when a pair was captured
}

TEST(RunReportTest, ACapturedPairsStampIsReported) {
  ConsoleRunTotals console;
  console.captured_stamp_ns = 1700000000123456789;
  auto keys = Parse(FormatRunReport(console, {}));
  EXPECT_EQ(keys["captured_stamp_ns"], "1700000000123456789");
  // No run time (ended at once): no division by zero.
  EXPECT_EQ(keys["pairs_per_s_run"], "0");
}

}  // namespace
}  // namespace mostar::ui
