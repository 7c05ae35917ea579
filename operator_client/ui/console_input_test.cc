#include "operator_client/ui/console_input.h"

#include <gtest/gtest.h>

namespace mostar::ui {
namespace {

TEST(ApplyTogglesTest, FlipsExactlyTheSwitchesWhoseKeysWerePressed) {
  bool help = false, calibration = false, hud = true, map = true, sonar = true, latency = false,
       vision = true, edge_view = false;
  const ViewSwitches switches{&help,  &calibration, &hud,    &map,
                              &sonar, &latency,     &vision, &edge_view};
  ConsoleInput in;
  in.toggle_help = true;
  in.toggle_hud = true;
  in.toggle_sonar = true;
  in.toggle_edge_view = true;
  ApplyToggles(in, switches);
  EXPECT_TRUE(help);
  EXPECT_FALSE(calibration);
  EXPECT_FALSE(hud);
  EXPECT_TRUE(map);
  EXPECT_FALSE(sonar);
  EXPECT_FALSE(latency);
  EXPECT_TRUE(vision);
  EXPECT_TRUE(edge_view);
  ApplyToggles(ConsoleInput{}, switches);  // nothing pressed: nothing changes
  EXPECT_TRUE(help);
  in = {};
  in.toggle_map = true;
  ApplyToggles(in, ViewSwitches{});  // no switches: nothing to flip, no crash
  EXPECT_TRUE(map);
}

}  // namespace
}  // namespace mostar::ui
