#include "robot_server/sim/scene.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "robot_server/sim/sim_test_helpers.h"
#include "robot_server/sim/sim_world.h"

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
                         ::testing::Values("corridor", "open_room", "checkerboard_room"));

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
