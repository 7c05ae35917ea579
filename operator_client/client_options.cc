#include "operator_client/client_options.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "common/config/config_loader.h"
#include "common/config/config_paths.h"
#include "common/dds/profile_check.h"
#include "common/identity/client_id.h"
#include "common/math/calibration_io.h"
#include "operator_client/render/display_mode.h"

namespace mostar::client {
namespace {

// --window-size bounds, pixels.
constexpr int kMinWindowPx = 160;
constexpr int kMaxWindowPx = 8192;

// The self-calibration keys over the defaults of ConsoleSelfCalibration::Options.
bool SelfCalibrationFromConfig(const SelfCalibrationConfig& config,
                               ui::ConsoleSelfCalibration::Options* options, std::string* error) {
  options->enabled = config.enabled();
  options->window_points = static_cast<size_t>(config.window_points());
  options->window_age = FromSeconds(config.window_age_s());
  options->fit_period = FromSeconds(config.fit_period_s());
  options->min_motion_m = config.min_motion_m();
  options->min_turn_rad = config.min_turn_deg() * M_PI / 180.0;
  options->fit.free = {config.fit_focal(),    config.fit_camera_x(), config.fit_camera_y(),
                       config.fit_camera_z(), config.fit_tilt(),     config.fit_pan(),
                       config.fit_roll()};
  options->fit.loss_px = config.loss_px();
  options->fit.inlier_px = config.inlier_px();
  options->fit.min_points = static_cast<size_t>(config.min_points());
  options->correspondences.max_range_m = config.max_range_m();
  options->correspondences.min_incidence_rad = config.min_incidence_deg() * M_PI / 180.0;
  if (!options->IsValid(error)) {
    *error = "self_calibration: " + *error;
    return false;
  }
  return true;
}

}  // namespace

bool ConsoleOptionsFromConfig(const ClientConfig& config, const std::string& config_dir,
                              ui::ConsoleOptions* options, std::string* error) {
  if (config.has_calibration_profile()) {
    const std::string path = ResolveConfigPath(config.calibration_profile(), config_dir);
    if (!math::LoadCalibrationProfile(path, &options->calibration, error)) return false;
    options->calibration_path = path;
  }
  const ArConfig& ar = config.ar();
  options->ar.min_distance_m = static_cast<float>(ar.min_distance_m());
  options->ar.max_distance_m = static_cast<float>(ar.max_distance_m());
  options->ar.wall_height_m = static_cast<float>(ar.wall_height_m());
  options->ar.segmentation.slope_threshold = static_cast<float>(ar.slope_threshold());
  options->ar.walls_enabled = ar.walls();
  options->ar.rays_enabled = ar.rays();
  options->ar.vertical_lines_enabled = ar.vertical_lines();
  options->ar.circles_enabled = ar.circles();
  options->ar.circle_spacing_m = static_cast<float>(ar.circle_spacing_m());
  options->ar.labels_enabled = ar.labels();
  options->ar.label_count = ar.label_count();
  options->sonar.enabled = ar.sonar_sectors();
  options->sonar.max_age_s = static_cast<float>(ar.sonar_max_age_s());
  if (!options->ar.IsValid(error)) {
    *error = "ar: " + *error;
    return false;
  }
  options->motion.enabled = ar.motion_compensation();
  options->motion.compensation.max_extrapolation =
      FromMilliseconds(ar.motion_max_extrapolation_ms());
  options->motion.compensation.smoothing_window =
      FromMilliseconds(ar.motion_heading_smoothing_ms());
  if (!options->motion.IsValid(error)) {
    *error = "ar: motion: " + *error;
    return false;
  }
  options->intrinsics_from_robot = config.intrinsics_from_robot();
  options->vision_enabled = config.vision_enabled();
  options->vision_result_wait = FromMilliseconds(config.vision_result_wait_ms());
  options->vision = vision::FromProto(config.vision());
  if (!options->vision.IsValid(error)) {
    *error = "vision: " + *error;
    return false;
  }
  if (!SelfCalibrationFromConfig(config.self_calibration(), &options->self_calibration, error)) {
    return false;
  }
  options->drive.max_linear_mps = config.drive().max_linear_mps();
  options->drive.max_angular_radps = config.drive().max_angular_radps();
  options->drive.stick_deadzone = config.drive().stick_deadzone();
  if (!options->drive.IsValid(error)) {
    *error = "drive: " + *error;
    return false;
  }
  return true;
}

bool ApplyClientFlags(const ClientFlags& flags, const ClientConfig& config,
                      ui::ConsoleOptions* options, std::string* error) {
  std::string why;
  if (!identity::IsValidClientId(flags.client_id, &why)) {
    *error = "--id '" + flags.client_id + "': " + why;
    return false;
  }
  options->client_id = flags.client_id;
  options->pilot = flags.role == "pilot";
  options->headless = flags.headless;
  if (flags.no_hud) options->show_hud = false;
  options->show_calibration_panel = flags.calibration_panel;
  std::string display = flags.display;
  if (display.empty()) display = config.has_display_mode() ? config.display_mode() : "mono-left";
  if (!render::ParseDisplayMode(display, &options->mode)) {
    *error = "unknown display mode '" + display + "'";
    return false;
  }
  if (!flags.window_size.empty() &&
      (flags.window_size.size() != 2 ||
       std::any_of(flags.window_size.begin(), flags.window_size.end(),
                   [](int v) { return v < kMinWindowPx || v > kMaxWindowPx; }))) {
    *error = "--window-size: give WIDTHxHEIGHT, each in [" + std::to_string(kMinWindowPx) + ", " +
             std::to_string(kMaxWindowPx) + "] pixels";
    return false;
  }
  if (!flags.calibration_path.empty()) {
    if (!math::LoadCalibrationProfile(flags.calibration_path, &options->calibration, error)) {
      *error = "--calibration: " + *error;
      return false;
    }
    options->calibration_path = flags.calibration_path;
  }
  return true;
}

ui::WindowOptions WindowOptionsFor(const ClientFlags& flags, const ui::ConsoleOptions& options) {
  ui::WindowOptions window;
  if (flags.window_size.size() == 2) {
    window.width = flags.window_size[0];
    window.height = flags.window_size[1];
  } else {
    render::WindowSizeFor(options.mode, options.calibration.image_width_px,
                          options.calibration.image_height_px, &window.width, &window.height);
  }
  window.visible = !options.headless;
  window.request_quad_buffer = options.mode == render::DisplayMode::kQuadBuffer;
  return window;
}

bool ResolveClientId(const ClientFlags& flags, bool secure, const std::string& certificate_cn,
                     std::string* client_id, std::string* error) {
  if (!secure) {
    *client_id = flags.client_id;
    return true;
  }
  if (certificate_cn.empty()) {
    *error = "this client's certificate has no CN that is a client id (1-64 of [A-Za-z0-9_.-])";
    return false;
  }
  if (flags.client_id_given && flags.client_id != certificate_cn) {
    *error = "--id " + flags.client_id + " is not the CN of this client's certificate (" +
             certificate_cn + "): the robot would drop everything it sends";
    return false;
  }
  *client_id = certificate_cn;
  return true;
}

void CheckConsoleConfig(const std::string& config_path, const ClientFlags& flags,
                        const dds::ParticipantOptions& dds,
                        const dds::ParticipantOptions* video_dds, ConfigReport* report) {
  ClientConfig config;
  std::string error;
  if (!config_path.empty()) {
    if (!LoadTextConfig(config_path, &config, &error)) {
      report->Fail("the configuration does not load: " + error,
                   "correct the line named (schema: operator_client/client_config.proto; "
                   "examples in " +
                       InstalledConfigDir() + ")");
      return;
    }
    report->Ok("configuration " + config_path + " loads");
  }
  ui::ConsoleOptions options;
  if (!ConsoleOptionsFromConfig(config, DirectoryOf(config_path), &options, &error) ||
      !ApplyClientFlags(flags, config, &options, &error)) {
    report->Fail(error, "correct the configuration key or flag named");
  } else {
    report->Ok("console options valid (calibration, AR, vision, display)");
  }
  const dds::ProfileCheck profile = dds::CheckDdsProfile(dds, "", report);
  if (video_dds != nullptr) dds::CheckDdsProfile(*video_dds, "", report);
  std::string client_id;
  if (profile.secure || !profile.certificate_path.empty()) {
    if (ResolveClientId(flags, profile.secure, profile.own_client_id.value_or(""), &client_id,
                        &error)) {
      report->Ok("client id '" + client_id + "' (the certificate's name)");
    } else {
      report->Fail(error, "leave --id out: with DDS Security the certificate names the client");
    }
  }
  if (!flags.headless && std::getenv("DISPLAY") == nullptr &&
      std::getenv("WAYLAND_DISPLAY") == nullptr) {
    report->Fail("no display (neither DISPLAY nor WAYLAND_DISPLAY is set) for the window",
                 "run it in a desktop session, or with --headless under xvfb-run");
  }
}

}  // namespace mostar::client
