#include "robot_server/drive/drive_config.h"

#include <chrono>

#include "common/identity/client_id.h"

namespace mostar::drive {
namespace {

Duration Ms(int32_t ms) { return std::chrono::milliseconds(ms); }

}  // namespace

bool DriveSettingsFromProto(const DriveConfig& config, DriveSettings* settings,
                            std::string* error) {
  const RobotGeometry& g = config.geometry();
  const DriveLimits& l = config.limits();
  const SafetyRules& s = config.safety();
  const MotorBoard& m = config.motor_board();

  OdometryOptions& odom = settings->odometry;
  odom.wheel_radius_m = g.wheel_radius_m();
  odom.axle_x_m = g.axle_x_m();
  odom.track_width_m = g.track_width_m();
  odom.ticks_per_turn = g.ticks_per_turn();
  odom.counter_bits = g.counter_bits();
  odom.wheel_variance_m2_per_m = config.odometry().wheel_variance_m2_per_m();
  odom.max_wheel_speed_mps = config.odometry().max_wheel_speed_mps();
  if (!odom.IsValid(error)) {
    *error = "geometry/odometry: " + *error;
    return false;
  }

  SafetyOptions& safety = settings->safety;
  safety.max_linear_mps = l.max_linear_mps();
  safety.max_reverse_mps = l.max_reverse_mps();
  safety.max_angular_radps = l.max_angular_radps();
  safety.max_linear_accel_mps2 = l.max_linear_accel_mps2();
  safety.max_linear_decel_mps2 = l.max_linear_decel_mps2();
  safety.max_angular_accel_radps2 = l.max_angular_accel_radps2();
  safety.max_angular_decel_radps2 = l.max_angular_decel_radps2();
  safety.deadman_period = Ms(s.deadman_period_ms());
  safety.max_command_age = Ms(s.max_command_age_ms());
  safety.delay_window = Ms(s.delay_window_ms());
  safety.require_arm_at_start = s.require_arm_at_start();
  safety.robot_width_m = g.robot_width_m();
  safety.lateral_margin_m = s.lateral_margin_m();
  safety.front_extent_m = g.front_extent_m();
  safety.stop_distance_m = s.stop_distance_m();
  safety.slow_distance_m = s.slow_distance_m();
  safety.scan_max_age = Ms(s.scan_max_age_ms());
  safety.unknown_scan_speed_factor = s.unknown_scan_speed_factor();
  safety.sonar_max_age = Ms(s.sonar_max_age_ms());
  safety.sonar_arc_step_m = s.sonar_arc_step_m();
  settings->control_period = Ms(s.control_period_ms());
  safety.max_cycle = 5 * settings->control_period;
  if (!safety.IsValid(error)) {
    *error = "limits/safety: " + *error;
    return false;
  }

  SerialDriveMotorsOptions& motors = settings->motors;
  motors.port = m.port();
  motors.baud = m.baud();
  motors.wheel_radius_m = g.wheel_radius_m();
  motors.track_width_m = g.track_width_m();
  motors.ticks_per_turn = g.ticks_per_turn();
  motors.counter_bits = g.counter_bits();
  motors.max_wheel_speed_mps = m.max_wheel_speed_mps();
  motors.link_timeout = Ms(m.link_timeout_ms());
  if (!motors.IsValid(error)) {
    *error = "motor_board: " + *error;
    return false;
  }

  settings->roles = RoleTable{};
  for (const PilotRole& role : config.roles()) {
    std::string why;
    if (!identity::IsValidClientId(role.client_id(), &why)) {
      *error = "roles: client_id '" + role.client_id() + "': " + why;
      return false;
    }
    if (settings->roles.Known(role.client_id())) {
      *error = "roles: client_id '" + role.client_id() + "' is listed twice";
      return false;
    }
    settings->roles.Set(role.client_id(),
                        RoleEntry{role.role() == PilotRole::PILOT ? Role::kPilot : Role::kObserver,
                                  role.strength()});
  }
  return true;
}

}  // namespace mostar::drive
