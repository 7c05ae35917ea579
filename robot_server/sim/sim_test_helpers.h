// Scenes and configs built in code for the simulator's tests.
#pragma once

#include <google/protobuf/text_format.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "robot_server/sim/scene.pb.h"
#include "robot_server/sim/sim_config.pb.h"

namespace mostar::sim::testing {

inline std::string SourceDir() {
  const char* dir = std::getenv("MOSTAR_SOURCE_DIR");
  return dir ? dir : ".";
}

// Parses text-format `text` into a message of type T (test input, assumed valid).
template <typename T>
T FromText(const std::string& text) {
  T message;
  EXPECT_TRUE(google::protobuf::TextFormat::ParseFromString(text, &message)) << text;
  return message;
}

// A 20 x 20 m floor (plain unless `extra` has its own `floor { ... }`, which then gets the
// same extent) with no ceiling and the robot at the origin looking along +x, plus `extra`.
inline proto::Scene OpenFloor(std::string extra) {
  const std::string extent = "min_x_m: -10 max_x_m: 10 min_y_m: -10 max_y_m: 10 ";
  const size_t floor = extra.find("floor {");
  if (floor == std::string::npos) {
    extra = "floor { " + extent + "}\n" + extra;
  } else {
    extra.insert(floor + 7, " " + extent);
  }
  return FromText<proto::Scene>("ceiling_height_m: 0\n" + extra);
}

// The default MORDUC config with every random effect off (exact geometry).
inline proto::SimConfig NoiselessConfig() {
  proto::SimConfig c;
  c.mutable_laser()->set_noise_sigma_m(0);
  c.mutable_camera()->set_noise_sigma(0);
  c.mutable_camera()->set_blur_sigma_px(0);
  c.mutable_camera()->set_vignetting(false);
  return c;
}

}  // namespace mostar::sim::testing
