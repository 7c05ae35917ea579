// operator_client: shows the robot's stereo video with the laser fused over it as AR, and
// drives the robot. Wiring only: flags and configuration choose the pieces and connect them.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <iostream>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "common/dds/domain.h"
#include "common/dds/participant.h"
#include "common/log/log.h"
#include "common/log/stamp_trace.h"
#include "common/math/camera_model.h"
#include "common/timesync/clock_offset_estimator.h"
#include "operator_client/fusion/ar_features.h"
#include "operator_client/fusion/predicted_path.h"
#include "operator_client/net/operator_node.h"
#include "operator_client/render/eye_renderer.h"
#include "operator_client/render/gl.h"
#include "operator_client/render/screenshot.h"
#include "operator_client/render/stereo_compositor.h"
#include "operator_client/ui/drive_input.h"
#include "operator_client/ui/window.h"
#include "operator_client/video/stereo_receiver.h"

namespace mostar::client {
namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop = true; }

// Keeps recent scans to match each image with the scan nearest in time. Thread-safe.
class ScanHistory {
 public:
  void Add(const LaserScan& scan) {
    std::lock_guard<std::mutex> lock(mutex_);
    scans_.push_back(scan);
    while (scans_.size() > 32) scans_.pop_front();
    ++count_;
  }
  std::optional<LaserScan> Nearest(Time stamp) const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::optional<LaserScan> best;
    Duration best_gap = Duration::max();
    for (const LaserScan& s : scans_) {
      const Duration gap = s.stamp > stamp ? s.stamp - stamp : stamp - s.stamp;
      if (gap < best_gap) {
        best_gap = gap;
        best = s;
      }
    }
    return best;
  }
  uint64_t count() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return count_;
  }

 private:
  mutable std::mutex mutex_;
  std::deque<LaserScan> scans_;
  uint64_t count_ = 0;
};

void AppendArray(const fusion::VertexArray& from, fusion::VertexArray* to) {
  to->positions.insert(to->positions.end(), from.positions.begin(), from.positions.end());
  to->colors.insert(to->colors.end(), from.colors.begin(), from.colors.end());
}

int Run(int argc, char** argv) {
  CLI::App app{"operator_client: stereoscopic AR view of the robot and driving console."};
  int domain = -1;
  std::string dds_profile = "loopback";
  std::string client_id = "operator";
  std::string role = "pilot";
  int strength = 10;
  std::string display = "mono-left";
  bool headless = false;
  int max_frames = 0;
  double duration_s = 0;
  std::string screenshot;
  std::vector<double> scripted_drive;
  std::string trace_path;
  std::string log_level = "info";
  app.add_option("--domain", domain, "DDS domain id (default: MOSTAR_DDS_DOMAIN, then 0)")
      ->check(CLI::Range(0, 232));
  app.add_option("--dds-profile", dds_profile, "'loopback' or a Fast DDS XML profiles file");
  app.add_option("--id", client_id, "this client's id (shown in the lease)");
  app.add_option("--role", role, "pilot | observer")->check(CLI::IsMember({"pilot", "observer"}));
  app.add_option("--strength", strength, "command ownership strength (pilots)")
      ->check(CLI::Range(1, 1000));
  app.add_option("--display", display,
                 "mono-left | mono-right | anaglyph | anaglyph-color | sbs | sbs-half | "
                 "top-bottom | interlaced | quad-buffer");
  app.add_flag("--headless", headless, "hidden window; render to --screenshot (needs an X "
                                       "server, e.g. xvfb-run)");
  app.add_option("--frames", max_frames, "exit after rendering this many video frames")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--duration", duration_s, "exit after this many seconds")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--screenshot", screenshot, "write the last rendered frame to this PNG");
  app.add_option("--drive", scripted_drive, "scripted command V,W (m/s, rad/s) held throughout")
      ->expected(2)
      ->delimiter(',');
  app.add_option("--trace", trace_path, "write received stamps and sent commands to this CSV");
  app.add_option("--log-level", log_level, "debug | info | warning | error")
      ->check(CLI::IsMember({"debug", "info", "warning", "error"}));
  CLI11_PARSE(app, argc, argv);
  LogLevel level;
  ParseLogLevel(log_level, &level);
  SetLogLevel(level);

  render::DisplayMode mode;
  if (!render::ParseDisplayMode(display, &mode)) {
    std::cerr << "operator_client: unknown display mode '" << display << "'\n";
    return 2;
  }
  StampTrace trace;
  if (!trace.Open(trace_path)) {
    std::cerr << "operator_client: cannot write " << trace_path << "\n";
    return 2;
  }
  if (!headless && std::getenv("DISPLAY") == nullptr && std::getenv("WAYLAND_DISPLAY") == nullptr) {
    std::cerr << "operator_client: no display; use --headless under xvfb-run\n";
    return 2;
  }

  std::string error;
  dds::ParticipantOptions dds_options;
  dds_options.domain_id = domain >= 0 ? domain : dds::DomainIdFromEnvironment(0);
  dds_options.profile = dds_profile;
  dds_options.name = "operator";
  auto participant = dds::Participant::Create(dds_options, &error);
  if (!participant) {
    std::cerr << "operator_client: " << error << "\n";
    return 1;
  }

  const Clock* clock = &SystemClock::Instance();
  StereoReceiver receiver(clock);
  ScanHistory scans;
  std::mutex state_mutex;
  std::optional<RobotHealth> health;
  std::optional<ControlLease> lease;
  timesync::ClockOffsetEstimator clock_offset;
  OperatorNode::Callbacks callbacks;
  callbacks.on_image = [&](Eye eye, const CompressedImage& image) {
    trace.Add(eye == Eye::kLeft ? "left" : "right", image.stamp, 0);
    receiver.Push(eye, image);
  };
  callbacks.on_scan = [&](const LaserScan& scan) {
    trace.Add("scan", scan.stamp, 0);
    scans.Add(scan);
  };
  callbacks.on_health = [&](const RobotHealth& h) {
    trace.Add("health", h.stamp, h.last_command_sequence);
    std::lock_guard<std::mutex> lock(state_mutex);
    health = h;
  };
  callbacks.on_lease = [&](const ControlLease& l) {
    std::lock_guard<std::mutex> lock(state_mutex);
    lease = l;
  };
  callbacks.on_pong = [&](const ClockProbe& probe) {
    if (probe.sender_id != client_id) return;
    std::lock_guard<std::mutex> lock(state_mutex);
    clock_offset.AddSample({probe.t0, probe.t1, probe.t2, clock->Now()});
  };
  OperatorNode::Options node_options;
  node_options.client_id = client_id;
  node_options.pilot = role == "pilot";
  node_options.command_strength = strength;
  auto node = OperatorNode::Create(participant.get(), node_options, callbacks, &error);
  if (!node) {
    std::cerr << "operator_client: " << error << "\n";
    return 1;
  }

  // Window and renderers.
  math::LaserCameraCalibration calibration;
  int window_w = 0;
  int window_h = 0;
  render::WindowSizeFor(mode, calibration.image_width_px, calibration.image_height_px, &window_w,
                        &window_h);
  ui::WindowOptions window_options;
  window_options.width = window_w;
  window_options.height = window_h;
  window_options.visible = !headless;
  window_options.request_quad_buffer = mode == render::DisplayMode::kQuadBuffer;
  auto window = ui::Window::Create(window_options, &error);
  if (!window) {
    std::cerr << "operator_client: " << error << "\n";
    return 1;
  }
  if (mode == render::DisplayMode::kQuadBuffer && !window->quad_buffer()) {
    std::cerr << "operator_client: quad-buffer stereo is not available with "
              << window->renderer() << "; showing the left eye\n";
  }
  MOSTAR_LOG(INFO) << "operator_client '" << client_id << "' (" << role << ") on DDS domain "
                   << dds_options.domain_id << ", " << window->renderer() << ", display "
                   << render::DisplayModeName(mode);
  render::EyeRenderer eyes[2];
  render::StereoCompositor compositor;
  if (!eyes[0].Init(&error) || !eyes[1].Init(&error) || !compositor.Init(&error)) {
    std::cerr << "operator_client: OpenGL set-up failed: " << error << "\n";
    return 1;
  }
  auto builder = fusion::ArFeatureBuilder::Create(fusion::ArFeatureOptions{}, &error);
  if (!builder) {
    std::cerr << "operator_client: " << error << "\n";
    return 1;
  }

  // Command thread: steady 20 Hz, independent of rendering.
  ui::DriveMapper mapper(ui::DriveLimits{});
  std::atomic<double> drive_v{0};
  std::atomic<double> drive_w{0};
  std::atomic<bool> drive_enable{false};
  if (scripted_drive.size() == 2) {
    drive_v = scripted_drive[0];
    drive_w = scripted_drive[1];
    drive_enable = true;
  }
  std::atomic<uint64_t> commands_sent{0};
  std::thread command_thread([&] {
    uint64_t sequence = 0;
    uint64_t ping_sequence = 0;
    SteadyTime next = clock->SteadyNow();
    SteadyTime next_ping = next;
    while (!g_stop) {
      next += std::chrono::milliseconds(50);
      if (node->is_pilot()) {
        VelocityCommand cmd;
        cmd.stamp = clock->Now();
        cmd.sequence = ++sequence;
        cmd.sender_id = client_id;
        cmd.enable = drive_enable;
        cmd.linear_mps = cmd.enable ? drive_v.load() : 0.0;
        cmd.angular_radps = cmd.enable ? drive_w.load() : 0.0;
        if (node->SendCommand(cmd)) {
          ++commands_sent;
          trace.Add("command", cmd.stamp, cmd.sequence);
        }
      }
      if (clock->SteadyNow() >= next_ping) {
        next_ping += std::chrono::seconds(1);
        node->SendPing({client_id, ++ping_sequence, clock->Now(), {}, {}});
      }
      std::this_thread::sleep_until(next);
    }
  });

  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  const SteadyTime start = clock->SteadyNow();
  uint64_t rendered_frames = 0;
  uint64_t last_pair = 0;
  cv::Mat last_screenshot;
  while (!g_stop && !window->ShouldClose()) {
    ui::Window::PollEvents();
    if (!headless && scripted_drive.size() != 2) {
      ui::DriveInputState input;
      GLFWwindow* w = window->get();
      auto down = [w](int key) { return glfwGetKey(w, key) == GLFW_PRESS; };
      input.forward = down(GLFW_KEY_UP) || down(GLFW_KEY_W);
      input.backward = down(GLFW_KEY_DOWN) || down(GLFW_KEY_S);
      input.left = down(GLFW_KEY_LEFT) || down(GLFW_KEY_A);
      input.right = down(GLFW_KEY_RIGHT) || down(GLFW_KEY_D);
      GLFWgamepadstate pad;
      if (glfwJoystickIsGamepad(GLFW_JOYSTICK_1) && glfwGetGamepadState(GLFW_JOYSTICK_1, &pad)) {
        input.gamepad_present = true;
        input.stick_linear = -pad.axes[GLFW_GAMEPAD_AXIS_LEFT_Y];
        input.stick_angular = -pad.axes[GLFW_GAMEPAD_AXIS_RIGHT_X];
        input.gamepad_deadman = pad.buttons[GLFW_GAMEPAD_BUTTON_RIGHT_BUMPER] == GLFW_PRESS;
      }
      if (down(GLFW_KEY_ESCAPE)) window->RequestClose();
      const ui::DriveOutput out = mapper.Map(input);
      drive_v = out.linear_mps;
      drive_w = out.angular_radps;
      drive_enable = out.enable;
    }

    const std::optional<DecodedStereoPair> pair = receiver.Latest();
    const bool new_frame = pair && pair->sequence != last_pair;
    if (new_frame || !headless) {
      render::OverlayGeometry overlay;
      std::optional<LaserScan> scan = pair ? scans.Nearest(pair->stamp) : std::nullopt;
      if (scan) {
        const fusion::ArFeatures features = builder->Build(*scan);
        overlay.triangles = features.walls;
        AppendArray(features.rays, &overlay.lines);
        AppendArray(features.circles, &overlay.lines);
        overlay.points = features.laser_points;
      }
      fusion::PredictedPathOptions path_options;
      if (drive_enable) {
        fusion::BuildPredictedPath(drive_v, drive_w, path_options, &overlay.lines);
      }
      for (int e = 0; e < 2; ++e) {
        const math::CameraModel model(calibration, e == 0 ? math::Eye::kLeft : math::Eye::kRight);
        const math::GlMatrices m = model.OpenGlMatrices(0.05, 50.0);
        const cv::Mat empty;
        const cv::Mat& image = pair ? (e == 0 ? pair->left : pair->right) : empty;
        eyes[e].Render(image, m.projection, m.view, overlay, render::EyeAlignment{});
      }
      int fb_w = 0;
      int fb_h = 0;
      window->FramebufferSize(&fb_w, &fb_h);
      compositor.Compose(mode, eyes[0].texture(), eyes[1].texture(), fb_w, fb_h,
                         window->quad_buffer());
      if (new_frame) {
        last_pair = pair->sequence;
        ++rendered_frames;
        if (!screenshot.empty()) last_screenshot = render::ReadFramebuffer(fb_w, fb_h);
      }
      window->SwapBuffers();
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    if (max_frames > 0 && rendered_frames >= static_cast<uint64_t>(max_frames)) break;
    if (duration_s > 0 && clock->SteadyNow() - start > FromSeconds(duration_s)) break;
  }
  g_stop = true;
  command_thread.join();
  trace.Flush();
  if (!screenshot.empty()) {
    if (last_screenshot.empty()) {
      std::cerr << "operator_client: no video frame was rendered; no screenshot written\n";
    } else if (!cv::imwrite(screenshot, last_screenshot)) {
      std::cerr << "operator_client: cannot write " << screenshot << "\n";
    }
  }
  const ReceiverStats stats = receiver.Stats();
  std::cout << "report: rendered_frames=" << rendered_frames
            << " pairs_decoded=" << stats.pairs_decoded << " images=" << stats.images
            << " broken_images=" << stats.broken_images << " scans=" << scans.count()
            << " commands_sent=" << commands_sent.load() << "\n";
  return 0;
}

}  // namespace
}  // namespace mostar::client

int main(int argc, char** argv) { return mostar::client::Run(argc, argv); }
