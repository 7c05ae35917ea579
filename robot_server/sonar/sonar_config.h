// SonarConfig (sonar_config.proto) to the driver's options.
#pragma once

#include <string>

#include "robot_server/sonar/sonar_config.pb.h"
#include "robot_server/sonar/srf08.h"

namespace mostar::sonar {

// False with a message naming the field when the belt is inconsistent (addresses, groups).
bool Srf08RingOptionsFromConfig(const SonarConfig& config, Srf08RingOptions* options,
                                std::string* error);

}  // namespace mostar::sonar
