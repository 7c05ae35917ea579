#include "operator_client/client_command_line.h"

namespace mostar::client {

void AddClientOptions(CLI::App* app, ClientCommandLine* line) {
  app->add_option("--domain", line->domain, "DDS domain id (default: MOSTAR_DDS_DOMAIN, then 0)")
      ->check(CLI::Range(0, 232));
  app->add_option("--dds-profile", line->dds_profile, "'loopback' or a Fast DDS XML profiles file");
  auto* via_relay_option = app->add_flag(
      "--video-via-relay", line->video_via_relay,
      "take the camera streams from mostar_relay (participant profile 'operator_video' of "
      "--dds-profile, on --video-domain), so that the robot's uplink carries the video once; "
      "commands, e-stop, lease, clock, scans and the rest stay direct");
  app->add_option("--video-domain", line->video_domain,
                  "with --video-via-relay: the relay's observer domain (default --domain + 1)")
      ->check(CLI::Range(0, 232))
      ->needs(via_relay_option);
  app->add_option_function<std::string>(
      "--id",
      [line](const std::string& id) {
        line->flags.client_id = id;
        line->flags.client_id_given = true;
      },
      "this client's id (shown in the lease); with DDS Security the CN of its certificate, "
      "which is also the default");
  app->add_flag("--insecure", line->flags.insecure,
                "allow a network DDS profile without DDS Security (anyone on the network can "
                "watch and drive; docs/security.md)");
  app->add_option("--role", line->flags.role, "pilot | observer")
      ->check(CLI::IsMember({"pilot", "observer"}));
  app->add_option("--strength", line->strength_ignored,
                  "ignored (accepted for old scripts): the robot's role table gives strengths and "
                  "cmd_vel ownership is shared");
  app->add_option("--display", line->flags.display,
                  "mono-left | mono-right | anaglyph | anaglyph-color | sbs | sbs-half | "
                  "top-bottom | interlaced | quad-buffer");
  app->add_option("-c,--config", line->config_path, "client configuration (protobuf text format)")
      ->check(CLI::ExistingFile);
  app->add_option("--calibration", line->flags.calibration_path,
                  "laser-camera calibration profile (protobuf text); the panel saves here");
  app->add_flag("--calibration-panel", line->flags.calibration_panel,
                "open the calibration panel at start");
  app->add_flag("--headless", line->flags.headless,
                "hidden window; render to --screenshot (needs an X server, e.g. xvfb-run)");
  app->add_option("--frames", line->max_frames, "exit after rendering this many video frames")
      ->check(CLI::NonNegativeNumber);
  app->add_option("--duration", line->duration_s, "exit after this many seconds")
      ->check(CLI::NonNegativeNumber);
  app->add_option("--rejoin-after", line->rejoin_after_s,
                  "seconds without the robot after which the console joins DDS again as a new "
                  "participant (a handshake that never ends), doubling each time up to 120; 0: "
                  "never")
      ->check(CLI::Range(0.0, 120.0));
  app->add_option("--screenshot", line->screenshot, "write the last rendered frame to this PNG");
  auto* capture_stamp_option =
      app->add_option("--capture-stamp", line->capture_stamp_ns,
                      "render only the pair with this capture stamp (ns since the epoch) once its "
                      "scans are in, write it to --screenshot and exit (reproducible screenshots)")
          ->check(CLI::NonNegativeNumber);
  app->add_option("--capture-after", line->capture_after,
                  "like --capture-stamp for the first pair decoded after this many; the report "
                  "gives its stamp (captured_stamp_ns)")
      ->check(CLI::NonNegativeNumber)
      ->excludes(capture_stamp_option);
  app->add_option("--window-size", line->flags.window_size,
                  "window size WIDTHxHEIGHT in pixels (default: the image's, doubled in width "
                  "for sbs)")
      ->expected(2)
      ->delimiter('x');
  app->add_flag("--no-hud", line->flags.no_hud,
                "hide the HUD (changing rates and ages; H toggles it)");
  app->add_option("--drive", line->scripted_drive,
                  "scripted command V,W (m/s, rad/s) held throughout")
      ->expected(2)
      ->delimiter(',');
  app->add_option("--trace", line->trace_path,
                  "write received stamps and sent commands to this CSV");
  app->add_option("--record", line->record_path,
                  "record everything received (and the commands sent) to this file");
  app->add_option("--log-level", line->log_level, "debug | info | warning | error")
      ->check(CLI::IsMember({"debug", "info", "warning", "error"}));
  app->add_flag("--check-config", line->check_config,
                "check the configuration, calibration, DDS profile (certificates, addresses), "
                "client id and display, print each problem with its fix, and exit: 0 when all is "
                "well");
}

}  // namespace mostar::client
