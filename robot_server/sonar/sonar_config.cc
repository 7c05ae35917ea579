#include "robot_server/sonar/sonar_config.h"

#include <cmath>

namespace mostar::sonar {

bool Srf08RingOptionsFromConfig(const SonarConfig& config, Srf08RingOptions* options,
                                std::string* error) {
  Srf08RingOptions o;
  for (int i = 0; i < config.sensors_size(); ++i) {
    const Srf08SensorConfig& c = config.sensors(i);
    Srf08Sensor s;
    s.address = static_cast<uint8_t>(c.address());
    s.mount.frame_id = c.frame_id().empty() ? "sonar_" + std::to_string(i) : c.frame_id();
    s.mount.x_m = c.x_m();
    s.mount.y_m = c.y_m();
    s.mount.yaw_rad = c.yaw_deg() * M_PI / 180.0;
    o.sensors.push_back(s);
  }
  for (const PingGroup& g : config.ping_groups()) {
    o.ping_groups.emplace_back(g.sensor().begin(), g.sensor().end());
  }
  o.max_range_m = config.max_range_m();
  o.gain = config.gain();
  o.ranging_time = std::chrono::milliseconds(config.ranging_time_ms());
  o.poll_timeout = std::chrono::milliseconds(config.poll_timeout_ms());
  o.min_range_m = config.min_range_m();
  o.field_of_view_rad = config.field_of_view_deg() * M_PI / 180.0;
  if (!o.IsValid(error)) {
    *error = "sonar: " + *error;
    return false;
  }
  *options = o;
  return true;
}

}  // namespace mostar::sonar
