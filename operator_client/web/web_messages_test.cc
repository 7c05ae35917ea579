#include "operator_client/web/web_messages.h"

#include <gtest/gtest.h>

#include "operator_client/web/frame_reader_for_test.h"

namespace mostar::web {
namespace {

PixelVertex V(float u, float v, uint8_t r) {
  PixelVertex p;
  p.u_px = u;
  p.v_px = v;
  p.rgba[0] = r;
  p.rgba[3] = 200;
  return p;
}

TEST(EncodeFrameTest, RoundTripsEveryField) {
  ImageOverlay overlay;
  overlay.triangles = {V(1, 2, 10), V(3, 4, 11), V(5.5f, -6.25f, 12)};
  overlay.lines = {V(7, 8, 20), V(9, 10, 21)};
  overlay.points = {V(11, 12, 30)};
  overlay.point_size_px = 4.5f;
  PixelLabel label;
  label.u_px = 100;
  label.v_px = 50;
  label.rgba[1] = 255;
  label.text = "1.35 m";
  overlay.labels = {label};
  std::vector<MapPoint> map(2);
  map[1].x_m = 1.25f;
  map[1].y_m = -0.5f;
  map[1].rgba[2] = 7;
  const std::vector<uint8_t> left = {0xff, 0xd8, 1, 2, 3};
  const std::vector<uint8_t> right = {0xff, 0xd8, 9};
  FrameContent content;
  content.sequence = 42;
  content.width_px = 640;
  content.height_px = 480;
  content.stamp = FromUnixNanos(1700000000123456789);
  content.scan_stamp = FromUnixNanos(1700000000100000000);
  content.overlay = &overlay;
  content.map = &map;
  content.left_jpeg = &left;
  content.right_jpeg = &right;
  ImageOverlay sonar;
  sonar.triangles = {V(20, 21, 40), V(22, 23, 41), V(24, 25, 42)};
  sonar.lines = {V(26, 27, 50), V(28, 29, 51)};
  std::vector<MapPoint> fans(3);
  fans[2].x_m = 0.75f;
  fans[2].rgba[0] = 60;
  std::vector<MapPoint> outlines(4);
  outlines[3].y_m = -1.5f;
  content.sonar = &sonar;
  content.sonar_map_triangles = &fans;
  content.sonar_map_lines = &outlines;
  content.sonar_echoes = 6;
  content.sonar_unseen = 2;
  content.possible_obstacles = 9;
  content.flags = kFrameEdges | kFrameSonar;
  const std::string bytes = EncodeFrame(content);
  EXPECT_EQ(bytes.size() % 4, 0u);

  testing::ReadFrame f;
  ASSERT_TRUE(testing::Read(bytes, &f));
  EXPECT_EQ(f.sequence, 42u);
  EXPECT_EQ(f.width_px, 640);
  EXPECT_EQ(f.height_px, 480);
  EXPECT_NEAR(f.stamp_s, 1700000000.123456789, 1e-6);
  EXPECT_NEAR(f.scan_stamp_s, 1700000000.1, 1e-6);
  EXPECT_FLOAT_EQ(f.point_size_px, 4.5f);
  ASSERT_EQ(f.triangles.size(), 3u);
  EXPECT_FLOAT_EQ(f.triangles[2].u_px, 5.5f);
  EXPECT_FLOAT_EQ(f.triangles[2].v_px, -6.25f);
  EXPECT_EQ(f.triangles[2].rgba[0], 12);
  EXPECT_EQ(f.triangles[2].rgba[3], 200);
  ASSERT_EQ(f.lines.size(), 2u);
  EXPECT_EQ(f.lines[1].rgba[0], 21);
  ASSERT_EQ(f.points.size(), 1u);
  ASSERT_EQ(f.map.size(), 2u);
  EXPECT_FLOAT_EQ(f.map[1].x_m, 1.25f);
  EXPECT_FLOAT_EQ(f.map[1].y_m, -0.5f);
  EXPECT_EQ(f.map[1].rgba[2], 7);
  ASSERT_EQ(f.sonar_triangles.size(), 3u);
  EXPECT_FLOAT_EQ(f.sonar_triangles[1].v_px, 23);
  EXPECT_EQ(f.sonar_triangles[2].rgba[0], 42);
  ASSERT_EQ(f.sonar_lines.size(), 2u);
  EXPECT_EQ(f.sonar_lines[1].rgba[0], 51);
  ASSERT_EQ(f.sonar_map_triangles.size(), 3u);
  EXPECT_FLOAT_EQ(f.sonar_map_triangles[2].x_m, 0.75f);
  EXPECT_EQ(f.sonar_map_triangles[2].rgba[0], 60);
  ASSERT_EQ(f.sonar_map_lines.size(), 4u);
  EXPECT_FLOAT_EQ(f.sonar_map_lines[3].y_m, -1.5f);
  EXPECT_EQ(f.sonar_echoes, 6);
  EXPECT_EQ(f.sonar_unseen, 2);
  EXPECT_EQ(f.possible_obstacles, 9u);
  EXPECT_EQ(f.flags, kFrameEdges | kFrameSonar);
  EXPECT_EQ(f.labels_json, R"([{"u":100.0,"v":50.0,"c":"#00ff00","t":"1.35 m"}])");
  EXPECT_EQ(f.left_jpeg, std::string(left.begin(), left.end()));
  EXPECT_EQ(f.right_jpeg, std::string(right.begin(), right.end()));
}

TEST(EncodeFrameTest, LeftEyeOnlyAndNoOverlay) {
  const std::vector<uint8_t> left(1001, 0x55);
  FrameContent content;
  content.width_px = 320;
  content.height_px = 240;
  content.left_jpeg = &left;
  testing::ReadFrame f;
  ASSERT_TRUE(testing::Read(EncodeFrame(content), &f));
  EXPECT_TRUE(f.triangles.empty());
  EXPECT_TRUE(f.sonar_triangles.empty());
  EXPECT_TRUE(f.sonar_map_lines.empty());
  EXPECT_EQ(f.flags, 0u);
  EXPECT_EQ(f.labels_json, "[]");
  EXPECT_EQ(f.left_jpeg.size(), 1001u);
  EXPECT_TRUE(f.right_jpeg.empty());
  EXPECT_EQ(f.scan_stamp_s, 0.0);
}

TEST(JsonStringTest, EscapesQuotesControlsAndInvalidUtf8) {
  EXPECT_EQ(JsonString("a\"b\\c"), R"("a\"b\\c")");
  EXPECT_EQ(JsonString("line\nnext\x01"), R"("line\u000anext\u0001")");
  EXPECT_EQ(JsonString("caf\xc3\xa9"), "\"caf\xc3\xa9\"");
  EXPECT_EQ(JsonString("bad\xff\xc3"), R"("bad\ufffd\ufffd")");
  EXPECT_EQ(JsonString("\xed\xa0\x80"), R"("\ufffd\ufffd\ufffd")");  // a surrogate
}

TEST(EncodeHudTest, HoldsEveryFieldAsJson) {
  HudState hud;
  hud.sequence = 7;
  hud.frame_age_ms = 83.26;
  hud.scan_age_ms = -1;
  hud.link = "ok";
  hud.robot_id = "morduc";
  hud.pilot = "ope\"rator";
  hud.watchdog = "driving";
  hud.estop_engaged = true;
  hud.warnings = {"laser warn: slow"};
  hud.browsers = 3;
  hud.video_fps = std::numeric_limits<double>::infinity();
  const std::string json = EncodeHud(hud);
  EXPECT_NE(json.find(R"("seq":7)"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("frame_age_ms":83.3)"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("scan_age_ms":-1.0)"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("video_fps":-1)"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("pilot":"ope\"rator")"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("estop":true)"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("warnings":["laser warn: slow"])"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("browsers":3)"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("bumpers":{"segments":[],"alert":false)"), std::string::npos) << json;
}

TEST(EncodeHudTest, HoldsTheBumperBelt) {
  HudState hud;
  hud.bumper_segments = {"idle", "pressed", "latched"};
  hud.bumper_alert = true;
  hud.bumper_status = "BUMPER CONTACT: front-left - robot stopped";
  hud.footprint_radius_m = 0.35;
  const std::string json = EncodeHud(hud);
  EXPECT_NE(json.find(R"("bumpers":{"segments":["idle","pressed","latched"],"alert":true,)"
                      R"("stale":false,"status":"BUMPER CONTACT: front-left - robot stopped",)"
                      R"("radius_m":0.350}})"),
            std::string::npos)
      << json;
}

}  // namespace
}  // namespace mostar::web
