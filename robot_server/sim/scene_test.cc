#include "robot_server/sim/scene.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <utility>
#include <vector>

#include "robot_server/sim/sim_test_helpers.h"
#include "robot_server/sim/sim_world.h"
#include "robot_server/sim/world.h"

namespace mostar::sim {
namespace {

using ::testing::HasSubstr;
using testing::SourceDir;

class ShippedSceneTest : public ::testing::TestWithParam<const char*> {};

TEST_P(ShippedSceneTest, LoadsAndBuildsAWorld) {
  const std::string path = SourceDir() + "/deploy/scenes/" + GetParam() + ".pbtxt";
  proto::Scene scene;
  std::string error;
  ASSERT_TRUE(LoadScene(path, &scene, &error)) << error;
  EXPECT_EQ(scene.name(), GetParam());
  proto::SimConfig config;
  ASSERT_TRUE(LoadSimConfig(SourceDir() + "/deploy/config/sim_morduc.pbtxt", &config, &error))
      << error;
  auto sim = SimWorld::Create(scene, config, Time(), &error);
  ASSERT_NE(sim, nullptr) << error;
  EXPECT_FALSE(sim->world().obstacles().empty());
  // The laser sees something from the start pose.
  const LaserScan scan = sim->ScanAt(Time());
  int valid = 0;
  for (float r : scan.ranges_m) valid += LaserScan::IsValidRange(r);
  EXPECT_GT(valid, 50);
}

INSTANTIATE_TEST_SUITE_P(AllScenes, ShippedSceneTest,
                         ::testing::Values("corridor", "open_room", "checkerboard_room",
                                           "tiled_room"));

TEST(SceneTest, MissingFileNamesTheFile) {
  proto::Scene scene;
  std::string error;
  EXPECT_FALSE(LoadScene("no/such/scene.pbtxt", &scene, &error));
  EXPECT_THAT(error, HasSubstr("no/such/scene.pbtxt"));
}

TEST(SceneTest, UnknownKeyIsRejectedWithFileAndKey) {
  proto::Scene scene;
  std::string error;
  EXPECT_FALSE(ParseScene("floor { min_x_m: -1 }\nwal { x0_m: 1 }\n", "bad.pbtxt", &scene, &error));
  EXPECT_THAT(error, HasSubstr("bad.pbtxt:2"));
  EXPECT_THAT(error, HasSubstr("wal"));
}

TEST(SceneTest, NegativeSizeIsOutOfRange) {
  proto::Scene scene;
  std::string error;
  EXPECT_FALSE(ParseScene("box { x_m: 1 y_m: 0 size_x_m: -0.5 size_y_m: 1 height_m: 1 }",
                          "neg.pbtxt", &scene, &error));
  EXPECT_THAT(error, HasSubstr("neg.pbtxt"));
  EXPECT_THAT(error, HasSubstr("size_x_m"));
}

TEST(SceneTest, BoxWithoutHeightNamesTheKey) {
  proto::Scene scene;
  std::string error;
  EXPECT_FALSE(
      ParseScene("box { x_m: 1 y_m: 0 size_x_m: 1 size_y_m: 1 }\n"
                 "box { x_m: 3 y_m: 0 size_x_m: 1 size_y_m: 1 }",
                 "s.pbtxt", &scene, &error));
  EXPECT_EQ(error, "s.pbtxt: box[0].height_m: must be set");
}

TEST(SceneTest, ZeroLengthWallIsRejected) {
  proto::Scene scene;
  std::string error;
  EXPECT_FALSE(ParseScene("wall { x0_m: 1 y0_m: 1 x1_m: 1 y1_m: 1 }", "w.pbtxt", &scene, &error));
  EXPECT_THAT(error, HasSubstr("wall[0]"));
  EXPECT_THAT(error, HasSubstr("zero length"));
}

TEST(SceneTest, ZeroLengthTapeIsRejected) {
  proto::Scene scene;
  std::string error;
  EXPECT_FALSE(ParseScene("tape { x0_m: 1 y0_m: 1 x1_m: 1 y1_m: 1 }", "t.pbtxt", &scene, &error));
  EXPECT_THAT(error, HasSubstr("tape[0]"));
}

// TILES: joints `joint_m` wide centred on the tile borders in colour2, tiles within
// tile_variation of colour; tape over the pattern, with square ends.
TEST(SceneTest, TiledFloorHasJointsTilesAndTape) {
  proto::Scene scene;
  std::string error;
  ASSERT_TRUE(ParseScene(
      "floor { pattern: TILES square_m: 0.3 joint_m: 0.02 tile_variation: 0.2 "
      "colour { r: 200 g: 200 b: 200 } colour2 { r: 50 g: 40 b: 30 } }\n"
      "tape { x0_m: 1.0 y0_m: -1 x1_m: 1.0 y1_m: 1 width_m: 0.06 colour { r: 230 g: 190 b: 40 } }",
      "tiles.pbtxt", &scene, &error))
      << error;
  const World world(scene);
  bool inside = false, dark = false;
  // On a border (x = 0.3), and within half a joint of it.
  for (const double x : {0.3, 0.291, 0.309}) {
    const Rgb joint = world.FloorAlbedo(x, 0.15, &inside, &dark);
    EXPECT_TRUE(inside);
    EXPECT_FLOAT_EQ(joint.r, 50) << x;
    EXPECT_FLOAT_EQ(joint.b, 30) << x;
  }
  // Tile centres: colour x (1 +- 0.1), not all the same.
  double lowest = 1e9, highest = 0;
  for (int i = 0; i < 10; ++i) {
    const Rgb tile = world.FloorAlbedo(0.15 + 0.3 * i, 0.45, &inside, &dark);
    EXPECT_GE(tile.r, 180 - 1e-3);
    EXPECT_LE(tile.r, 220 + 1e-3);
    lowest = std::min<double>(lowest, tile.r);
    highest = std::max<double>(highest, tile.r);
  }
  EXPECT_GT(highest - lowest, 5);
  // The tape covers joints and tiles alike, 3 cm either side of its line, up to its ends.
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{
           {1.0, 0.0}, {1.029, 0.5}, {0.971, -0.99}, {1.0, 0.9}}) {
    const Rgb tape = world.FloorAlbedo(x, y, &inside, &dark);
    EXPECT_FLOAT_EQ(tape.g, 190) << x << " " << y;
  }
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{{1.04, 0.0}, {1.0, 1.05}}) {
    EXPECT_NE(world.FloorAlbedo(x, y, &inside, &dark).g, 190) << x << " " << y;
  }
}

TEST(SceneTest, EmptyFloorIsRejected) {
  proto::Scene scene;
  std::string error;
  EXPECT_FALSE(ParseScene("floor { min_x_m: 2 max_x_m: 1 }", "f.pbtxt", &scene, &error));
  EXPECT_THAT(error, HasSubstr("floor.max_x_m"));
}

TEST(SceneTest, StartOutsideTheFloorIsRejected) {
  proto::Scene scene;
  std::string error;
  EXPECT_FALSE(ParseScene("start { x_m: 50 }", "o.pbtxt", &scene, &error));
  EXPECT_THAT(error, HasSubstr("start"));
}

TEST(SceneTest, TexturedMaterialNeedsSecondColour) {
  proto::Scene scene;
  std::string error;
  EXPECT_FALSE(
      ParseScene("box { x_m: 2 y_m: 0 size_x_m: 1 size_y_m: 1 height_m: 1 "
                 "material { texture: CHECKERBOARD } }",
                 "t.pbtxt", &scene, &error));
  EXPECT_THAT(error, HasSubstr("box[0].material.colour2"));
}

TEST(SceneTest, StartInsideAnObstacleIsRefusedBySimWorld) {
  proto::Scene scene;
  std::string error;
  ASSERT_TRUE(
      ParseScene("name: \"blocked\"\n"
                 "cylinder { x_m: 0 y_m: 0 radius_m: 0.2 height_m: 1 }",
                 "b.pbtxt", &scene, &error))
      << error;
  EXPECT_EQ(SimWorld::Create(scene, proto::SimConfig(), Time(), &error), nullptr);
  EXPECT_THAT(error, HasSubstr("overlaps"));
}

TEST(SimConfigTest, QuarterDegreeNeedsTheNarrowField) {
  proto::SimConfig config;
  config.mutable_laser()->set_resolution(proto::LaserConfig::RES_0_25_DEG);
  std::string error;
  EXPECT_FALSE(ValidateSimConfig(config, "c.pbtxt", &error));
  EXPECT_THAT(error, HasSubstr("laser.resolution"));
  config.mutable_laser()->set_fov(proto::LaserConfig::FOV_100);
  EXPECT_TRUE(ValidateSimConfig(config, "c.pbtxt", &error)) << error;
}

TEST(SimConfigTest, OutOfRangeValueNamesFileAndKey) {
  proto::SimConfig config;
  config.mutable_camera()->set_baseline_m(3.0);
  std::string error;
  EXPECT_FALSE(ValidateSimConfig(config, "c.pbtxt", &error));
  EXPECT_THAT(error, HasSubstr("c.pbtxt"));
  EXPECT_THAT(error, HasSubstr("baseline_m"));
}

}  // namespace
}  // namespace mostar::sim
