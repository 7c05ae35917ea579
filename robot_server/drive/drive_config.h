// DriveConfig (drive_config.proto) -> the option structs of the drive classes.
#pragma once

#include <string>

#include "robot_server/drive/drive_config.pb.h"
#include "robot_server/drive/odometry.h"
#include "robot_server/drive/pilot_lease.h"
#include "robot_server/drive/safety_governor.h"
#include "robot_server/drive/serial_drive_motors.h"

namespace mostar::drive {

struct DriveSettings {
  OdometryOptions odometry;
  SafetyOptions safety;
  SerialDriveMotorsOptions motors;
  RoleTable roles;
  Duration control_period = std::chrono::milliseconds(20);
};

// Converts and cross-checks (each options struct's IsValid, duplicate or empty client ids).
// False with a message naming the key on failure.
bool DriveSettingsFromProto(const DriveConfig& config, DriveSettings* settings, std::string* error);

}  // namespace mostar::drive
