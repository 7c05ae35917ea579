#include "robot_server/sim/sim_range_source.h"

#include <gtest/gtest.h>

#include <cmath>

#include "robot_server/sim/sim_test_helpers.h"

namespace mostar::sim {
namespace {

TEST(SimWorldRangeSourceTest, SamplesTheWorldAtTheMappedTime) {
  std::string error;
  auto sim = SimWorld::Create(testing::OpenFloor("wall { x0_m: 3 y0_m: -20 x1_m: 3 y1_m: 20 }"),
                              testing::NoiselessConfig(), Time(), &error);
  ASSERT_NE(sim, nullptr) << error;
  sim->SetVelocity(0.5, 0.0);
  const SteadyTime origin{};
  SimWorldRangeSource source(sim.get(), origin, Time());
  std::vector<float> ranges;
  source.Sample(origin + FromSeconds(2), -M_PI / 2, M_PI / 180, 181, &ranges);
  ASSERT_EQ(ranges.size(), 181u);
  const double x = sim->StateAt(Time() + FromSeconds(2)).world_from_base.x_m;
  EXPECT_GT(x, 0.5);
  EXPECT_NEAR(ranges[90], 3.0 - x, 1e-4);
  EXPECT_TRUE(LaserScan::IsFreeRange(ranges[0]));  // nothing in range: the emulator's "no echo"
}

}  // namespace
}  // namespace mostar::sim
