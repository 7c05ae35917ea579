// Scores the edge processing against the simulator's ground truth and prints a table (the one in
// docs/vision.md; the scoring is tests/vision/groundtruth_score.h). Per scene: precision and
// recall of "obstacle below the laser" dots (mono = right image alone, thesis 8; stereo = NESC,
// thesis 9.2; both with the client's defaults, so with the neighbour and isolated-dot rules), the
// share of stray NEPs NESC removes, and the overlay misalignment in pixels before and after NEP
// correction under a deliberately perturbed calibration. Images carry sensor noise and a one-eye
// artefact (right eye, every other frame on average). Run from the repository root (or set
// MOSTAR_SOURCE_DIR).
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <string>

#include "common/config/config_loader.h"
#include "operator_client/client_config.pb.h"
#include "tests/vision/groundtruth_score.h"

namespace mostar::vision {
namespace {

int Run(int argc, char** argv) {
  CLI::App app{"Edge processing against the simulator's ground truth"};
  GroundTruthRun run;
  app.add_option("--frames", run.frames, "frames per scene")->check(CLI::Range(1, 1000));
  app.add_flag("--held_out", run.held_out,
               "score the held-out frames (half a second later, turning right first) instead of "
               "the tuning frames");
  app.add_option("--noise", run.noise_sigma, "image noise sigma, grey levels");
  app.add_option("--artifact_probability", run.artifact_probability, "one-eye artefact per frame");
  app.add_option("--tilt_error_rad", run.tilt_error_rad, "calibration perturbation: tilt");
  app.add_option("--height_error_m", run.height_error_m, "calibration perturbation: camera height");
  app.add_option("--right_vertical_offset_px", run.right_vertical_offset_px,
                 "right principal point shift unknown to the calibration");
  app.add_option("--k1", run.k1, "radial lens distortion k1 of both cameras (known to the client)")
      ->check(CLI::Range(-0.5, 0.5));
  app.add_option("--images_out", run.images_out, "directory for before/after images");
  std::string client_config;
  app.add_option("--client_config", client_config,
                 "take the edge-processing options from this client configuration's vision "
                 "(e.g. deploy/config/client_thesis.pbtxt); the per-scene stretch thresholds and "
                 "step test stay unless the file sets them");
  app.add_flag("--below_laser_only", run.below_laser_only,
               "positives: only bases below the scan plane (not beams without an echo)");
  bool list_dots = false;
  app.add_flag("--list_dots", list_dots,
               "list every stereo dot (TP/FP) and every missed positive on stderr");
  CLI11_PARSE(app, argc, argv);
  client::ClientConfig client;
  if (!client_config.empty()) {
    std::string error;
    if (!LoadTextConfig(client_config, &client, &error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      return 2;
    }
  }

  if (list_dots) run.list_dots = stderr;
  std::printf("%s\n", GroundTruthTableHeader().c_str());
  for (const GroundTruthScene& scene : GroundTruthScenes()) {
    GroundTruthScore score;
    std::string error;
    if (!ScoreAgainstGroundTruth(scene, client.vision(), run, &score, &error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      return 1;
    }
    std::printf("%s\n", score.TableRow(scene).c_str());
    std::fflush(stdout);
    if (run.right_vertical_offset_px != 0.0) {
      std::fprintf(stderr,
                   "%s: stereo offset hint valid in %d/%d frames, mean %.2f px (true %.2f)\n",
                   scene.name.c_str(), score.offset_valid, score.frames,
                   score.offset_valid > 0 ? score.offset_sum_px / score.offset_valid : std::nan(""),
                   run.right_vertical_offset_px);
    }
  }
  return 0;
}

}  // namespace
}  // namespace mostar::vision

int main(int argc, char** argv) { return mostar::vision::Run(argc, argv); }
