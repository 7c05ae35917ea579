#include "operator_client/client_options.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "common/config/config_loader.h"
#include "common/testing/subprocess.h"

namespace mostar::client {
namespace {

const std::string kConfigDir = std::string(MOSTAR_TEST_SOURCE_DIR) + "/deploy/config";

TEST(ClientOptionsTest, ShippedSimConfigGivesValidOptionsWithItsCalibration) {
  ClientConfig config;
  std::string error;
  ASSERT_TRUE(LoadTextConfig(kConfigDir + "/client_sim.pbtxt", &config, &error)) << error;
  ui::ConsoleOptions options;
  ASSERT_TRUE(ConsoleOptionsFromConfig(config, kConfigDir, &options, &error)) << error;
  if (config.has_calibration_profile()) {
    EXPECT_EQ(options.calibration_path, kConfigDir + "/" + config.calibration_profile())
        << "relative to the configuration file";
  }
  EXPECT_TRUE(options.calibration.IsValid(&error)) << error;
  EXPECT_TRUE(options.ar.IsValid(&error)) << error;
  EXPECT_TRUE(options.motion.enabled) << "on by default";
}

TEST(ClientOptionsTest, ConfigValuesReachTheConsole) {
  ClientConfig config;
  config.mutable_ar()->set_min_distance_m(0.7);
  config.mutable_ar()->set_circles(false);
  config.mutable_ar()->set_motion_compensation(false);
  config.mutable_ar()->set_motion_max_extrapolation_ms(30);
  config.mutable_ar()->set_motion_heading_smoothing_ms(0);
  config.set_vision_enabled(false);
  config.set_intrinsics_from_robot(false);
  config.mutable_drive()->set_max_linear_mps(0.25);
  ui::ConsoleOptions options;
  std::string error;
  ASSERT_TRUE(ConsoleOptionsFromConfig(config, "", &options, &error)) << error;
  EXPECT_FLOAT_EQ(options.ar.min_distance_m, 0.7f);
  EXPECT_FALSE(options.ar.circles_enabled);
  EXPECT_FALSE(options.motion.enabled);
  EXPECT_EQ(options.motion.compensation.max_extrapolation, std::chrono::milliseconds(30));
  EXPECT_EQ(options.motion.compensation.smoothing_window, Duration::zero());
  EXPECT_FALSE(options.vision_enabled);
  EXPECT_FALSE(options.intrinsics_from_robot);
  EXPECT_DOUBLE_EQ(options.drive.max_linear_mps, 0.25);
}

TEST(ClientOptionsTest, SelfCalibrationKeysReachTheConsole) {
  ClientConfig config;
  ui::ConsoleOptions defaults;
  std::string error;
  ASSERT_TRUE(ConsoleOptionsFromConfig(config, "", &defaults, &error)) << error;
  const ui::ConsoleSelfCalibration::Options built_in;
  EXPECT_TRUE(defaults.self_calibration.enabled);
  EXPECT_EQ(defaults.self_calibration.window_points, built_in.window_points);
  EXPECT_EQ(defaults.self_calibration.window_age, built_in.window_age);
  EXPECT_EQ(defaults.self_calibration.fit_period, built_in.fit_period);
  EXPECT_DOUBLE_EQ(defaults.self_calibration.min_motion_m, built_in.min_motion_m);
  EXPECT_NEAR(defaults.self_calibration.min_turn_rad, built_in.min_turn_rad, 1e-12);
  EXPECT_EQ(defaults.self_calibration.fit.free, built_in.fit.free) << "x, z and roll held";
  EXPECT_EQ(defaults.self_calibration.fit.min_points, built_in.fit.min_points);
  EXPECT_DOUBLE_EQ(defaults.self_calibration.fit.inlier_px, built_in.fit.inlier_px);
  EXPECT_NEAR(defaults.self_calibration.correspondences.min_incidence_rad,
              built_in.correspondences.min_incidence_rad, 1e-12);

  SelfCalibrationConfig* self = config.mutable_self_calibration();
  self->set_enabled(false);
  self->set_window_points(500);
  self->set_window_age_s(20);
  self->set_fit_period_s(0.5);
  self->set_min_motion_m(0.1);
  self->set_min_turn_deg(0);
  self->set_fit_roll(true);
  self->set_fit_pan(false);
  self->set_loss_px(2.0);
  self->set_inlier_px(4.0);
  self->set_min_points(40);
  self->set_max_range_m(4.0);
  self->set_min_incidence_deg(30);
  ui::ConsoleOptions options;
  ASSERT_TRUE(ConsoleOptionsFromConfig(config, "", &options, &error)) << error;
  const ui::ConsoleSelfCalibration::Options& o = options.self_calibration;
  EXPECT_FALSE(o.enabled);
  EXPECT_EQ(o.window_points, 500u);
  EXPECT_EQ(o.window_age, std::chrono::seconds(20));
  EXPECT_EQ(o.fit_period, std::chrono::milliseconds(500));
  EXPECT_DOUBLE_EQ(o.min_motion_m, 0.1);
  EXPECT_EQ(o.min_turn_rad, 0.0);
  EXPECT_TRUE(o.fit.free[calibration::kRoll]);
  EXPECT_FALSE(o.fit.free[calibration::kPan]);
  EXPECT_TRUE(o.fit.free[calibration::kTilt]);
  EXPECT_DOUBLE_EQ(o.fit.loss_px, 2.0);
  EXPECT_DOUBLE_EQ(o.fit.inlier_px, 4.0);
  EXPECT_EQ(o.fit.min_points, 40u);
  EXPECT_DOUBLE_EQ(o.correspondences.max_range_m, 4.0);
  EXPECT_NEAR(o.correspondences.min_incidence_rad, M_PI / 6, 1e-12);
}

TEST(ClientOptionsTest, ASelfCalibrationWithNothingFreeIsRefused) {
  ClientConfig config;
  SelfCalibrationConfig* self = config.mutable_self_calibration();
  for (auto set : {&SelfCalibrationConfig::set_fit_focal, &SelfCalibrationConfig::set_fit_camera_y,
                   &SelfCalibrationConfig::set_fit_tilt, &SelfCalibrationConfig::set_fit_pan}) {
    (self->*set)(false);
  }
  ui::ConsoleOptions options;
  std::string error;
  EXPECT_FALSE(ConsoleOptionsFromConfig(config, "", &options, &error));
  EXPECT_EQ(error, "self_calibration: fit: no parameter is free");
}

TEST(ClientOptionsTest, InconsistentValuesAreRefusedNamingTheSection) {
  ClientConfig config;
  config.mutable_ar()->set_min_distance_m(3);
  config.mutable_ar()->set_max_distance_m(1);  // green before red
  ui::ConsoleOptions options;
  std::string error;
  EXPECT_FALSE(ConsoleOptionsFromConfig(config, "", &options, &error));
  EXPECT_EQ(error.rfind("ar: ", 0), 0u) << error;
}

TEST(ClientOptionsTest, AMissingCalibrationProfileIsRefused) {
  ClientConfig config;
  config.set_calibration_profile("no_such_profile.pbtxt");
  ui::ConsoleOptions options;
  std::string error;
  EXPECT_FALSE(ConsoleOptionsFromConfig(config, "/nonexistent", &options, &error));
  EXPECT_NE(error.find("/nonexistent/no_such_profile.pbtxt"), std::string::npos) << error;
}

TEST(ClientOptionsTest, FlagsOverrideAndTheConfigGivesTheDisplayModeOtherwise) {
  ClientConfig config;
  config.set_display_mode("anaglyph");
  ui::ConsoleOptions options;
  std::string error;
  ClientFlags flags;
  flags.client_id = "bob";
  flags.role = "observer";
  flags.no_hud = true;
  flags.headless = true;
  ASSERT_TRUE(ApplyClientFlags(flags, config, &options, &error)) << error;
  EXPECT_EQ(options.client_id, "bob");
  EXPECT_FALSE(options.pilot);
  EXPECT_FALSE(options.show_hud);
  EXPECT_TRUE(options.headless);
  EXPECT_EQ(options.mode, render::DisplayMode::kAnaglyphGrey);
  flags.display = "sbs";
  ASSERT_TRUE(ApplyClientFlags(flags, config, &options, &error)) << error;
  EXPECT_EQ(options.mode, render::DisplayMode::kSideBySideFull);
}

TEST(ClientOptionsTest, TheWindowIsSizedForTheImageUnlessGiven) {
  ui::ConsoleOptions options;
  std::string error;
  ClientFlags flags;
  flags.headless = true;
  flags.display = "sbs";
  ASSERT_TRUE(ApplyClientFlags(flags, ClientConfig{}, &options, &error)) << error;
  ui::WindowOptions window = WindowOptionsFor(flags, options);
  EXPECT_EQ(window.width, 2 * options.calibration.image_width_px) << "both eyes side by side";
  EXPECT_EQ(window.height, options.calibration.image_height_px);
  EXPECT_FALSE(window.visible);
  EXPECT_FALSE(window.request_quad_buffer);
  flags.window_size = {900, 1000};
  flags.headless = false;
  flags.display = "quad-buffer";
  ASSERT_TRUE(ApplyClientFlags(flags, ClientConfig{}, &options, &error)) << error;
  window = WindowOptionsFor(flags, options);
  EXPECT_EQ(window.width, 900);
  EXPECT_EQ(window.height, 1000);
  EXPECT_TRUE(window.visible);
  EXPECT_TRUE(window.request_quad_buffer);
  for (const std::vector<int>& bad :
       std::vector<std::vector<int>>{{100, 480}, {640, 9000}, {640}}) {
    flags.window_size = bad;
    EXPECT_FALSE(ApplyClientFlags(flags, ClientConfig{}, &options, &error));
    EXPECT_EQ(error.rfind("--window-size: ", 0), 0u) << error;
  }
}

TEST(ClientOptionsTest, BadFlagsAreRefusedWithTheValue) {
  ui::ConsoleOptions options;
  std::string error;
  ClientFlags flags;
  flags.display = "holographic";
  EXPECT_FALSE(ApplyClientFlags(flags, ClientConfig{}, &options, &error));
  EXPECT_EQ(error, "unknown display mode 'holographic'");
  flags.display = "";
  flags.calibration_path = "/nonexistent/calibration.pbtxt";
  EXPECT_FALSE(ApplyClientFlags(flags, ClientConfig{}, &options, &error));
  EXPECT_EQ(error.rfind("--calibration: ", 0), 0u) << error;
  flags.calibration_path = "";
  flags.client_id = "pilot one";  // ids are certificate CNs: no spaces
  EXPECT_FALSE(ApplyClientFlags(flags, ClientConfig{}, &options, &error));
  EXPECT_EQ(error.rfind("--id 'pilot one': ", 0), 0u) << error;
}

TEST(ResolveClientIdTest, WithoutSecurityTheFlagIsTheId) {
  ClientFlags flags;
  std::string id;
  std::string error;
  ASSERT_TRUE(ResolveClientId(flags, /*secure=*/false, "", &id, &error)) << error;
  EXPECT_EQ(id, "operator");
  flags.client_id = "alice";
  flags.client_id_given = true;
  ASSERT_TRUE(ResolveClientId(flags, false, "bob", &id, &error)) << error;
  EXPECT_EQ(id, "alice") << "no certificate to believe without DDS Security";
}

TEST(ResolveClientIdTest, WithSecurityTheCertificatesCnIsTheId) {
  ClientFlags flags;  // no --id: the default is not used
  std::string id;
  std::string error;
  ASSERT_TRUE(ResolveClientId(flags, /*secure=*/true, "alice", &id, &error)) << error;
  EXPECT_EQ(id, "alice");
  flags.client_id = "alice";
  flags.client_id_given = true;
  ASSERT_TRUE(ResolveClientId(flags, true, "alice", &id, &error)) << error;
  EXPECT_EQ(id, "alice");
}

TEST(ResolveClientIdTest, WithSecurityAnotherIdOrNoCnIsRefused) {
  ClientFlags flags;
  flags.client_id = "bob";
  flags.client_id_given = true;
  std::string id = "unchanged";
  std::string error;
  EXPECT_FALSE(ResolveClientId(flags, /*secure=*/true, "alice", &id, &error));
  EXPECT_NE(error.find("--id bob is not the CN"), std::string::npos) << error;
  EXPECT_NE(error.find("(alice)"), std::string::npos) << error;
  EXPECT_EQ(id, "unchanged");
  error.clear();
  EXPECT_FALSE(ResolveClientId(ClientFlags{}, true, "", &id, &error));
  EXPECT_NE(error.find("no CN"), std::string::npos) << error;
}

// --check-config: the shipped simulator configuration passes; a certificate that names another
// client than --id, and a missing display for a window, are each a problem with its fix.
TEST(CheckConsoleConfigTest, TheShippedConfigurationPassesAndMistakesAreNamed) {
  const std::string config =
      std::string(MOSTAR_TEST_SOURCE_DIR) + "/deploy/config/client_sim.pbtxt";
  ClientFlags flags;
  flags.headless = true;
  dds::ParticipantOptions dds;
  dds.name = "operator";
  ConfigReport report;
  CheckConsoleConfig(config, flags, dds, nullptr, &report);
  for (const auto& p : report.problems()) ADD_FAILURE() << p.what;

  const std::string dir = mostar::testing::MakeTempDir("console_check");
  const std::string make_pki = std::string(MOSTAR_TEST_SOURCE_DIR) +
                               "/deploy/security/make_pki.sh " + dir +
                               "/pki --robot robot --pilot alice >/dev/null 2>&1";
  ASSERT_EQ(std::system(make_pki.c_str()), 0);
  dds.profile = dir + "/pki/alice.xml";
  flags.client_id = "bob";
  flags.client_id_given = true;
  ConfigReport wrong_id;
  CheckConsoleConfig(config, flags, dds, nullptr, &wrong_id);
  EXPECT_TRUE(wrong_id.HasProblem("leave --id out")) << wrong_id.problems().size();

  flags.client_id_given = false;
  flags.headless = false;
  const char* display = std::getenv("DISPLAY");
  const std::string saved = display != nullptr ? display : "";
  unsetenv("DISPLAY");
  ConfigReport no_display;
  CheckConsoleConfig(config, flags, dds, nullptr, &no_display);
  if (!saved.empty()) setenv("DISPLAY", saved.c_str(), 1);
  if (std::getenv("WAYLAND_DISPLAY") == nullptr) {
    EXPECT_TRUE(no_display.HasProblem("no display"));
  }
  EXPECT_FALSE(no_display.HasProblem("--id"));  // alice's certificate names alice
}

}  // namespace
}  // namespace mostar::client
