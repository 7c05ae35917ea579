#include "operator_client/ui/operator_console.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "common/log/log.h"
#include "common/math/calibration_io.h"
#include "operator_client/render/gl.h"
#include "operator_client/render/screenshot.h"

namespace mostar::ui {

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

void Append(const fusion::VertexArray& from, fusion::VertexArray* to) {
  to->positions.insert(to->positions.end(), from.positions.begin(), from.positions.end());
  to->colors.insert(to->colors.end(), from.colors.begin(), from.colors.end());
}

// Rising edges of keys, so that a held key acts once.
class KeyEdges {
 public:
  bool Pressed(GLFWwindow* window, int key) {
    const bool down = glfwGetKey(window, key) == GLFW_PRESS;
    const bool was = state_[key];
    state_[key] = down;
    return down && !was;
  }

 private:
  std::map<int, bool> state_;
};

KeyEdges& Keys() {
  static KeyEdges keys;
  return keys;
}

ImU32 ToImColor(const fusion::Rgba& c, float alpha = 1.f) {
  return ImGui::ColorConvertFloat4ToU32(ImVec4(c.r, c.g, c.b, c.a * alpha));
}

const render::DisplayMode kModes[] = {
    render::DisplayMode::kMonoLeft,       render::DisplayMode::kMonoRight,
    render::DisplayMode::kAnaglyphGrey,   render::DisplayMode::kAnaglyphColor,
    render::DisplayMode::kSideBySideFull, render::DisplayMode::kSideBySideHalf,
    render::DisplayMode::kTopBottom,      render::DisplayMode::kRowInterlaced,
    render::DisplayMode::kQuadBuffer,
};

}  // namespace

OperatorConsole::OperatorConsole(const ConsoleOptions& options, Window* window,
                                 client::StereoReceiver* video, client::RobotState* robot,
                                 CommandSender* commands, const Clock* clock)
    : options_(options),
      window_(window),
      video_(video),
      robot_(robot),
      commands_(commands),
      clock_(clock),
      mapper_(options.drive) {}

OperatorConsole::~OperatorConsole() {
  if (edge_textures_[0] != 0) glDeleteTextures(2, edge_textures_);
}

unsigned OperatorConsole::UploadTexture(const cv::Mat& image, unsigned texture) {
  if (texture == 0) glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, static_cast<GLint>(image.step / image.elemSize()));
  const GLenum format = image.channels() == 1 ? GL_RED : GL_BGR;
  glTexImage2D(GL_TEXTURE_2D, 0, image.channels() == 1 ? GL_R8 : GL_RGB8, image.cols, image.rows, 0,
               format, GL_UNSIGNED_BYTE, image.data);
  if (image.channels() == 1) {
    const GLint swizzle[] = {GL_RED, GL_RED, GL_RED, GL_ONE};
    glTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_RGBA, swizzle);
  }
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  return texture;
}

void OperatorConsole::UpdateVision(const std::optional<client::DecodedStereoPair>& latest) {
  if (!options_.vision_enabled) {
    shown_pair_ = latest;
    shown_result_.reset();
    in_flight_.clear();
    return;
  }
  // Camera models are shared with the worker (its ray cache) until the calibration changes.
  const bool calibration_changed =
      !left_model_ || math::ToProto(models_calibration_).SerializeAsString() !=
                          math::ToProto(options_.calibration).SerializeAsString();
  if (calibration_changed) {
    models_calibration_ = options_.calibration;
    left_model_ = std::make_shared<const math::CameraModel>(options_.calibration, math::Eye::kLeft);
    right_model_ =
        std::make_shared<const math::CameraModel>(options_.calibration, math::Eye::kRight);
  }
  if (latest && latest->sequence != submitted_pair_) {
    submitted_pair_ = latest->sequence;
    vision::VisionInput input;
    input.stamp = latest->stamp;
    input.sequence = latest->sequence;
    input.left = latest->left;
    input.right = latest->right;
    if (auto scan = robot_->NearestScan(latest->stamp)) {
      input.scan = *scan;
      fusion::ArFeatures features;
      builder_->Build(*scan, &features);
      for (const fusion::ScanPointLabel& p : features.points) {
        input.potential_outliers.push_back(p.potential_outlier);
      }
    }
    input.left_camera = left_model_;
    input.right_camera = right_model_;
    edge_worker_->Submit(std::move(input));
    in_flight_[latest->sequence] = *latest;
    while (in_flight_.size() > 4) in_flight_.erase(in_flight_.begin());
  }
  // Show the newest pair whose edge result is ready: overlay and image stay matched.
  const std::shared_ptr<const vision::VisionResult> result = edge_worker_->LatestResult();
  if (result) {
    auto it = in_flight_.find(result->sequence);
    if (it != in_flight_.end()) {
      shown_pair_ = it->second;
      shown_result_ = result->ok ? result : nullptr;
      result_sequence_ = result->sequence;
      in_flight_.erase(in_flight_.begin(), std::next(it));
    }
  }
  if (!shown_pair_) shown_pair_ = latest;  // nothing processed yet
}

bool OperatorConsole::Init(std::string* error) {
  if (!eyes_[0].Init(error) || !eyes_[1].Init(error) || !compositor_.Init(error)) return false;
  builder_ = fusion::ArFeatureBuilder::Create(options_.ar, error);
  if (!builder_) return false;
  if (!options_.calibration.IsValid(error)) return false;
  imgui_ = std::make_unique<ImGuiLayer>(window_->get());
  last_frame_start_ = clock_->SteadyNow();
  if (!options_.vision.IsValid(error)) return false;
  edge_worker_ = std::make_unique<vision::EdgeWorker>(options_.vision);
  want_control_ = options_.pilot;
  next_control_request_ = clock_->SteadyNow();
  return true;
}

void OperatorConsole::ApplyRobotIntrinsics(const client::RobotSnapshot& robot) {
  if (!options_.intrinsics_from_robot || !robot.left_intrinsics) return;
  const CameraIntrinsicsInfo& k = *robot.left_intrinsics;
  if (applied_intrinsics_ && applied_intrinsics_->fx == k.fx && applied_intrinsics_->fy == k.fy &&
      applied_intrinsics_->cx == k.cx && applied_intrinsics_->cy == k.cy &&
      applied_intrinsics_->distortion == k.distortion) {
    return;
  }
  applied_intrinsics_ = k;
  math::LaserCameraCalibration next = options_.calibration;
  if (k.width_px != next.image_width_px || k.height_px != next.image_height_px) {
    status_line_ = "robot intrinsics are for " + std::to_string(k.width_px) + "x" +
                   std::to_string(k.height_px) + " images: not used";
    return;
  }
  next.focal_px = k.fx;
  next.focal_y_px = k.fy;
  next.principal_x_px = k.cx;
  next.principal_y_px = k.cy;
  const auto d = [&k](size_t i) { return i < k.distortion.size() ? k.distortion[i] : 0.0; };
  next.distortion = {d(0), d(1), d(2), d(3), d(4)};
  std::string error;
  if (next.IsValid(&error)) {
    options_.calibration = next;
    MOSTAR_LOG(INFO) << "using the robot's camera intrinsics: f " << k.fx << "/" << k.fy
                     << " px, principal point (" << k.cx << ", " << k.cy << ")";
  } else {
    status_line_ = "robot intrinsics refused: " + error;
  }
}

void OperatorConsole::ManageLease(const client::RobotSnapshot& robot) {
  const SteadyTime now = clock_->SteadyNow();
  holding_lease_ = robot.lease && robot.lease->holder_id == options_.client_id;
  if (holding_lease_ && !holding_since_) holding_since_ = now;
  if (!holding_lease_) holding_since_.reset();
  // Control requests travel on a volatile topic: repeat until the lease shows the answer.
  if (want_control_ && !holding_lease_ && now >= next_control_request_) {
    commands_->RequestControl(true);
    next_control_request_ = now + std::chrono::seconds(1);
  }
}

void OperatorConsole::HandleInput() {
  GLFWwindow* w = window_->get();
  KeyEdges& keys = Keys();
  const bool typing = imgui_ && imgui_->WantsKeyboard();
  if (!typing) {
    if (keys.Pressed(w, GLFW_KEY_ESCAPE)) window_->RequestClose();
    if (keys.Pressed(w, GLFW_KEY_F1)) show_help_ = !show_help_;
    if (keys.Pressed(w, GLFW_KEY_C))
      options_.show_calibration_panel = !options_.show_calibration_panel;
    if (keys.Pressed(w, GLFW_KEY_H)) options_.show_hud = !options_.show_hud;
    if (keys.Pressed(w, GLFW_KEY_M)) options_.show_map = !options_.show_map;
    if (keys.Pressed(w, GLFW_KEY_E)) options_.vision_enabled = !options_.vision_enabled;
    if (keys.Pressed(w, GLFW_KEY_V)) show_edge_view_ = !show_edge_view_;
    for (int i = 0; i < 9; ++i) {
      if (keys.Pressed(w, GLFW_KEY_1 + i)) options_.mode = kModes[i];
    }
    if (keys.Pressed(w, GLFW_KEY_T) && options_.pilot) {
      want_control_ = true;
      next_control_request_ = clock_->SteadyNow();
    }
    if (keys.Pressed(w, GLFW_KEY_R)) {
      want_control_ = false;
      commands_->RequestControl(false);
    }
    if (keys.Pressed(w, GLFW_KEY_X)) commands_->SendEmergencyStop(true);
    if (keys.Pressed(w, GLFW_KEY_U)) commands_->SendEmergencyStop(false);
    if (keys.Pressed(w, GLFW_KEY_EQUAL) || keys.Pressed(w, GLFW_KEY_KP_ADD) ||
        keys.Pressed(w, GLFW_KEY_PAGE_UP)) {
      mapper_.ScaleUp();
    }
    if (keys.Pressed(w, GLFW_KEY_MINUS) || keys.Pressed(w, GLFW_KEY_KP_SUBTRACT) ||
        keys.Pressed(w, GLFW_KEY_PAGE_DOWN)) {
      mapper_.ScaleDown();
    }
  }
  if (scripted_drive_) {
    // Hold the lease, then arm with the deadman up for 0.5 s, then drive.
    const bool armed =
        holding_since_ && clock_->SteadyNow() - *holding_since_ > std::chrono::milliseconds(500);
    drive_ = armed ? *scripted_drive_ : DriveOutput{};
  } else {
    DriveInputState input;
    auto down = [w, typing](int key) { return !typing && glfwGetKey(w, key) == GLFW_PRESS; };
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
    drive_ = options_.pilot ? mapper_.Map(input) : DriveOutput{};
  }
  commands_->SetDrive(drive_);
  commands_->SetActive(want_control_ || holding_lease_);
}

void OperatorConsole::BuildOverlay(const std::optional<LaserScan>& scan,
                                   render::OverlayGeometry* overlay, fusion::ArFeatures* features) {
  if (scan) {
    fusion::ArFeatureOptions ar = options_.ar;
    ar.laser_height_m = static_cast<float>(options_.calibration.laser_height_m);
    if (options_.show_calibration_panel) {  // rays and lines help while calibrating
      ar.rays_enabled = true;
      ar.vertical_lines_enabled = true;
    }
    std::string error;
    auto builder = fusion::ArFeatureBuilder::Create(ar, &error);
    if (!builder) {
      status_line_ = "AR options: " + error;
      builder = builder_;
    }
    builder->Build(*scan, features);
    overlay->triangles = features->walls;
    Append(features->rays, &overlay->lines);
    Append(features->circles, &overlay->lines);
    Append(features->vertical_lines, &overlay->lines);
    overlay->points = features->laser_points;
  }
  // Possible obstacles the laser missed (NEPs much nearer than the laser point): magenta dots.
  if (shown_result_) {
    for (const vision::PossibleObstacle& o : shown_result_->classification.possible_obstacles) {
      overlay->points.Add(static_cast<float>(o.floor_point_laser.x()),
                          static_cast<float>(o.floor_point_laser.y()),
                          static_cast<float>(o.floor_point_laser.z()), {1.f, 0.f, 1.f, 1.f});
    }
  }
  if (drive_.enable) {
    fusion::PredictedPathOptions path = options_.path;
    path.laser_height_m = static_cast<float>(options_.calibration.laser_height_m);
    fusion::BuildPredictedPath(drive_.linear_mps, drive_.angular_radps, path, &overlay->lines);
  }
}

void OperatorConsole::CapturePair(std::optional<Time> stamp) {
  Capture capture;
  capture.stamp = stamp;
  if (const auto latest = video_->Latest()) capture.after_sequence = latest->sequence;
  capture_ = capture;
}

std::optional<Time> OperatorConsole::captured_stamp() const {
  if (!capture_ || !capture_->pair) return std::nullopt;
  return capture_->pair->stamp;
}

std::optional<client::DecodedStereoPair> OperatorConsole::CaptureFilter(
    const std::optional<client::DecodedStereoPair>& latest) {
  if (!capture_) return latest;
  Capture& c = *capture_;
  if (!c.pair && latest &&
      (c.stamp ? latest->stamp == *c.stamp : latest->sequence > c.after_sequence)) {
    c.pair = latest;
    c.latched_at = clock_->SteadyNow();
  }
  if (!c.pair) return std::nullopt;
  if (!c.ready) {
    const std::optional<LaserScan> scan = robot_->Snapshot().latest_scan;
    if (scan && scan->stamp >= c.pair->stamp) {
      c.ready = true;
    } else if (clock_->SteadyNow() - c.latched_at > kCaptureScanWait) {
      c.ready = true;
      MOSTAR_LOG(WARNING) << "capture: no scan stamped after the pair within "
                          << ToSeconds(kCaptureScanWait) << " s; rendering with what is here";
    }
  }
  if (!c.ready) return std::nullopt;
  return c.pair;
}

bool OperatorConsole::Frame() {
  Window::PollEvents();
  {
    const client::RobotSnapshot snapshot = robot_->Snapshot();
    ManageLease(snapshot);
    ApplyRobotIntrinsics(snapshot);
  }
  HandleInput();
  UpdateVision(CaptureFilter(video_->Latest()));
  const std::optional<client::DecodedStereoPair>& pair = shown_pair_;
  const bool new_pair = pair && pair->sequence != last_pair_;
  // A render of the captured pair with its scans and edge result in.
  const bool capture_render = capture_ && !capture_->done && capture_->ready && pair &&
                              pair->sequence == capture_->pair->sequence &&
                              (!options_.vision_enabled || result_sequence_ == pair->sequence);
  if (options_.headless && !new_pair && !capture_render) return false;
  const SteadyTime start = clock_->SteadyNow();

  const client::RobotSnapshot robot = robot_->Snapshot();
  std::optional<LaserScan> scan = pair ? robot_->NearestScan(pair->stamp) : robot.latest_scan;
  // With an edge result for this very pair, draw the corrected scan (NEP-corrected points,
  // confirmed outliers removed).
  if (shown_result_ && pair && shown_result_->sequence == pair->sequence &&
      !shown_result_->classification.corrected_scan.ranges_m.empty()) {
    scan = shown_result_->classification.corrected_scan;
  }
  render::OverlayGeometry overlay;
  fusion::ArFeatures features;
  BuildOverlay(scan, &overlay, &features);

  for (int e = 0; e < 2; ++e) {
    const math::CameraModel model(options_.calibration,
                                  e == 0 ? math::Eye::kLeft : math::Eye::kRight);
    const math::GlMatrices m = model.OpenGlMatrices(0.05, 100.0);
    static const cv::Mat kEmpty;
    const cv::Mat& image = pair ? (e == 0 ? pair->left : pair->right) : kEmpty;
    eyes_[e].Render(image, m.projection, m.view, overlay,
                    e == 0 ? options_.left_alignment : options_.right_alignment);
  }
  int fb_w = 0;
  int fb_h = 0;
  window_->FramebufferSize(&fb_w, &fb_h);
  compositor_.Compose(options_.mode, eyes_[0].texture(), eyes_[1].texture(), fb_w, fb_h,
                      window_->quad_buffer());
  imgui_->BeginFrame();
  DrawPanels(robot, features, pair, fb_w, fb_h);
  imgui_->EndFrame();
  if (new_pair) {
    last_pair_ = pair->sequence;
    ++rendered_pairs_;
    if (options_.headless) last_frame_ = render::ReadFramebuffer(fb_w, fb_h);
    // Capture-to-display age, on the robot's clock when the offset is known.
    Time now = clock_->Now();
    if (robot.clock.known) now = robot.clock.ToResponderTime(now);
    display_age_ms_ = ToSeconds(now - pair->stamp) * 1e3;
    if (display_ages_ms_.size() < 100000) display_ages_ms_.push_back(display_age_ms_);
  }
  if (capture_render && ++capture_->renders >= kCaptureRenders) {
    last_frame_ = render::ReadFramebuffer(fb_w, fb_h);
    capture_->done = true;
  }
  window_->SwapBuffers();
  frame_time_ms_ = ToSeconds(clock_->SteadyNow() - start) * 1e3;
  if (new_pair && frame_times_ms_.size() < 100000) frame_times_ms_.push_back(frame_time_ms_);
  return new_pair;
}

namespace {
double Percentile(std::vector<double> values, double percentile) {
  if (values.empty()) return 0;
  const size_t index =
      std::min(values.size() - 1,
               static_cast<size_t>(percentile / 100.0 * static_cast<double>(values.size())));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(index),
                   values.end());
  return values[index];
}
}  // namespace

double OperatorConsole::DisplayAgePercentileMs(double percentile) const {
  return Percentile(display_ages_ms_, percentile);
}

double OperatorConsole::FrameTimePercentileMs(double percentile) const {
  return Percentile(frame_times_ms_, percentile);
}

void OperatorConsole::DrawPanels(const client::RobotSnapshot& robot,
                                 const fusion::ArFeatures& features,
                                 const std::optional<client::DecodedStereoPair>& pair, int fb_w,
                                 int fb_h) {
  if (options_.ar.labels_enabled) DrawLabels(features, fb_w, fb_h);
  if (options_.show_hud) DrawHud(robot, pair);
  if (options_.show_map) DrawMap(robot, features);
  if (options_.show_calibration_panel) DrawCalibrationPanel();
  if (show_edge_view_) DrawEdgeView();
  if (show_help_) DrawHelp();
}

void OperatorConsole::DrawLabels(const fusion::ArFeatures& features, int fb_w, int fb_h) {
  // Each eye's image occupies a rectangle of the window depending on the display mode.
  struct EyeRect {
    math::Eye eye;
    float x, y, w, h;
  };
  std::vector<EyeRect> rects;
  const float fw = static_cast<float>(fb_w);
  const float fh = static_cast<float>(fb_h);
  switch (options_.mode) {
    case render::DisplayMode::kSideBySideFull:
    case render::DisplayMode::kSideBySideHalf:
      rects.push_back({math::Eye::kLeft, 0, 0, fw / 2, fh});
      rects.push_back({math::Eye::kRight, fw / 2, 0, fw / 2, fh});
      break;
    case render::DisplayMode::kTopBottom:
      rects.push_back({math::Eye::kLeft, 0, 0, fw, fh / 2});
      rects.push_back({math::Eye::kRight, 0, fh / 2, fw, fh / 2});
      break;
    case render::DisplayMode::kMonoRight:
      rects.push_back({math::Eye::kRight, 0, 0, fw, fh});
      break;
    default:
      rects.push_back({math::Eye::kLeft, 0, 0, fw, fh});
      break;
  }
  ImDrawList* draw = ImGui::GetForegroundDrawList();
  const ImVec2 scale = ImGui::GetIO().DisplayFramebufferScale;
  for (const EyeRect& r : rects) {
    const math::CameraModel model(options_.calibration, r.eye);
    for (const fusion::DistanceLabel& label : features.labels) {
      const auto px =
          model.Project(Eigen::Vector3d(label.anchor_x_m, label.anchor_y_m, label.anchor_z_m));
      if (!px || !model.IsInImage(*px)) continue;
      const float x = (r.x + static_cast<float>((*px)(0) + 0.5) * r.w / model.width_px()) / scale.x;
      const float y =
          (r.y + static_cast<float>((*px)(1) + 0.5) * r.h / model.height_px()) / scale.y;
      const ImVec2 size = ImGui::CalcTextSize(label.text.c_str());
      const ImVec2 top_left(x - size.x / 2 - 4, y - size.y - 4);
      draw->AddRectFilled(top_left, ImVec2(x + size.x / 2 + 4, y), IM_COL32(0, 0, 0, 170), 4);
      draw->AddText(ImVec2(x - size.x / 2, y - size.y - 2), ToImColor(label.color),
                    label.text.c_str());
    }
  }
}

void OperatorConsole::DrawHud(const client::RobotSnapshot& robot,
                              const std::optional<client::DecodedStereoPair>& pair) {
  const client::ReceiverStats video = video_->Stats();
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.55f);
  ImGui::Begin("HUD", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                   ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav |
                   ImGuiWindowFlags_NoMove);
  const SteadyTime now = clock_->SteadyNow();
  ImGui::Text("video %.1f fps  %.2f Mbit/s  age %.0f ms", video.pair_rate_hz,
              video.bitrate_bps / 1e6, pair ? display_age_ms_ : 0.0);
  ImGui::Text("scan %.1f Hz  frame %.1f ms  %s", robot.scan_rate_hz, frame_time_ms_,
              render::DisplayModeName(options_.mode));
  if (video.broken_images > 0 || video.pairs_dropped > 0) {
    ImGui::Text("dropped pairs %llu  broken JPEG %llu",
                static_cast<unsigned long long>(video.pairs_dropped),
                static_cast<unsigned long long>(video.broken_images));
  }
  if (robot.clock.known) {
    ImGui::Text("clock offset %+.1f ms  rtt %.1f ms",
                ToSeconds(robot.clock.responder_minus_requester) * 1e3,
                ToSeconds(robot.clock.round_trip) * 1e3);
  }
  // Link health: control-path ping loss and the age of the last sample of each stream.
  auto age_ms = [now](SteadyTime t) { return t == SteadyTime() ? -1.0 : ToSeconds(now - t) * 1e3; };
  const std::string loss =
      robot.ping_loss < 0 ? std::string("?")
                          : std::to_string(static_cast<int>(robot.ping_loss * 100 + 0.5)) + " %";
  ImGui::Text("link: ping loss %s  last video %.0f  scan %.0f  odom %.0f  health %.0f ms",
              loss.c_str(), pair ? age_ms(pair->received) : -1.0, age_ms(robot.last_scan_received),
              age_ms(robot.last_odometry_received), age_ms(robot.last_health_received));
  const uint64_t lost_pairs = video.pairs_dropped + video.unpaired_dropped + video.late_dropped;
  if (lost_pairs > 0) {
    ImGui::Text("video pairs lost here: %llu (replaced %llu, unpaired %llu, late %llu)",
                static_cast<unsigned long long>(lost_pairs),
                static_cast<unsigned long long>(video.pairs_dropped),
                static_cast<unsigned long long>(video.unpaired_dropped),
                static_cast<unsigned long long>(video.late_dropped));
  }
  const bool health_fresh =
      robot.health && now - robot.last_health_received < std::chrono::seconds(3);
  if (!health_fresh) {
    ImGui::TextColored(ImVec4(1, 0.3f, 0.2f, 1), "NO CONTACT WITH THE ROBOT");
  } else {
    const RobotHealth& h = *robot.health;
    const std::string holder = robot.lease ? robot.lease->holder_id : h.lease_holder;
    const bool me = holder == options_.client_id;
    ImGui::Text("pilot: %s%s   watchdog: %s", holder.empty() ? "(nobody)" : holder.c_str(),
                me ? " (you)" : "", WatchdogStateName(h.watchdog_state));
    if (h.estop_engaged)
      ImGui::TextColored(ImVec4(1, 0.2f, 0.2f, 1), "EMERGENCY STOP (U releases)");
    for (const DeviceHealth& d : h.devices) {
      if (d.state == DeviceState::kOk) continue;
      ImGui::TextColored(ImVec4(1, 0.7f, 0.1f, 1), "%s %s: %s", d.name.c_str(),
                         DeviceStateName(d.state), d.message.c_str());
    }
  }
  if (options_.pilot) {
    ImGui::Text("drive %s  v %.2f m/s  w %.2f rad/s  scale %.0f%%", drive_.enable ? "ON" : "off",
                drive_.linear_mps, drive_.angular_radps, mapper_.scale() * 100);
  } else {
    ImGui::Text("observer (no driving)");
  }
  if (!status_line_.empty()) ImGui::TextUnformatted(status_line_.c_str());
  ImGui::TextDisabled("F1 help");
  ImGui::End();
}

void OperatorConsole::DrawMap(const client::RobotSnapshot& robot,
                              const fusion::ArFeatures& features) {
  (void)robot;
  const float size = 220.f;
  const float range_m = 4.f;
  ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - size - 24, 8), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.55f);
  ImGui::Begin("Laser map", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                   ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav |
                   ImGuiWindowFlags_NoMove);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImGui::Dummy(ImVec2(size, size));
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const float scale = size / (2 * range_m);
  // Robot at the bottom centre, forward up; laser x forward -> screen up, y left -> screen left.
  const ImVec2 robot_px(origin.x + size / 2, origin.y + size - 10);
  auto to_screen = [&](float x, float y) {
    return ImVec2(robot_px.x - y * scale, robot_px.y - x * scale);
  };
  for (float r = 0.5f; r <= 2 * range_m; r += 0.5f) {
    draw->AddCircle(robot_px, r * scale, IM_COL32(255, 255, 255, r == std::floor(r) ? 70 : 35), 64);
  }
  for (const fusion::ScanPointLabel& p : features.points) {
    if (!p.valid) continue;
    const ImVec2 s = to_screen(p.x_m, p.y_m);
    if (s.x < origin.x || s.x > origin.x + size || s.y < origin.y || s.y > origin.y + size) {
      continue;
    }
    draw->AddRectFilled(ImVec2(s.x - 1.5f, s.y - 1.5f), ImVec2(s.x + 1.5f, s.y + 1.5f),
                        ToImColor(p.color));
  }
  draw->AddTriangleFilled(ImVec2(robot_px.x, robot_px.y - 9),
                          ImVec2(robot_px.x - 6, robot_px.y + 4),
                          ImVec2(robot_px.x + 6, robot_px.y + 4), IM_COL32(80, 160, 255, 255));
  ImGui::End();
}

void OperatorConsole::DrawCalibrationPanel() {
  math::LaserCameraCalibration& c = options_.calibration;
  ImGui::SetNextWindowPos(ImVec2(8, 190), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(430, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("Calibration", &options_.show_calibration_panel);
  ImGui::TextWrapped(
      "Order: 1 focal on far objects, 2 y and tilt on the floor, 3 z on near objects, "
      "4 x last. Rays and lines are shown while this panel is open.");
  math::LaserCameraCalibration edit = c;
  float focal = static_cast<float>(edit.focal_px);
  float y = static_cast<float>(edit.camera_y_m);
  float tilt_deg = static_cast<float>(edit.tilt_rad * kRadToDeg);
  float z = static_cast<float>(edit.camera_z_m);
  float x = static_cast<float>(edit.camera_x_m);
  float pan_deg = static_cast<float>(edit.pan_rad * kRadToDeg);
  float roll_deg = static_cast<float>(edit.roll_rad * kRadToDeg);
  float baseline = static_cast<float>(edit.baseline_m());
  float laser_h = static_cast<float>(edit.laser_height_m);
  bool changed = false;
  changed |= ImGui::SliderFloat("1 focal [px]", &focal, 150, 2000, "%.1f");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Scales the overlay: match far walls first.");
  changed |= ImGui::SliderFloat("2 camera y [m]", &y, -0.5f, 2.0f, "%.3f");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Height above the scan plane: moves floor rays.");
  changed |= ImGui::SliderFloat("2 tilt [deg]", &tilt_deg, -45, 45, "%.2f");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Down is positive: moves the overlay vertically.");
  changed |= ImGui::SliderFloat("3 camera z [m]", &z, -1.0f, 1.0f, "%.3f");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Ahead of the laser: matters on near objects.");
  changed |= ImGui::SliderFloat("4 camera x [m]", &x, -0.5f, 0.5f, "%.3f");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Right of the laser: shifts sideways.");
  changed |= ImGui::SliderFloat("pan [deg]", &pan_deg, -20, 20, "%.2f");
  changed |= ImGui::SliderFloat("roll [deg]", &roll_deg, -10, 10, "%.2f");
  changed |= ImGui::SliderFloat("baseline [m]", &baseline, 0.0f, 0.3f, "%.3f");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Distance between the eyes (5-20 cm).");
  changed |= ImGui::SliderFloat("laser height [m]", &laser_h, 0.05f, 1.5f, "%.3f");
  if (changed) {
    edit.focal_px = focal;
    edit.camera_y_m = y;
    edit.tilt_rad = tilt_deg / kRadToDeg;
    edit.camera_z_m = z;
    edit.camera_x_m = x;
    edit.pan_rad = pan_deg / kRadToDeg;
    edit.roll_rad = roll_deg / kRadToDeg;
    edit.left_eye_x_offset_m = -baseline / 2;
    edit.right_eye_x_offset_m = baseline / 2;
    edit.laser_height_m = laser_h;
    std::string error;
    if (edit.IsValid(&error)) {
      c = edit;
    } else {
      status_line_ = "calibration: " + error;
    }
  }
  const std::string path =
      options_.calibration_path.empty() ? "calibration_profile.pbtxt" : options_.calibration_path;
  if (ImGui::Button("Save")) {
    std::string error;
    status_line_ = math::SaveCalibrationProfile(path, c, "operator", &error)
                       ? "saved " + path
                       : "save failed: " + error;
  }
  ImGui::SameLine();
  if (ImGui::Button("Load")) {
    std::string error;
    math::LaserCameraCalibration loaded;
    if (math::LoadCalibrationProfile(path, &loaded, &error)) {
      c = loaded;
      status_line_ = "loaded " + path;
    } else {
      status_line_ = "load failed: " + error;
    }
  }
  ImGui::SameLine();
  if (ImGui::Button("Reset")) c = math::LaserCameraCalibration{};
  ImGui::Separator();
  ImGui::Text("AR features");
  ImGui::Checkbox("walls", &options_.ar.walls_enabled);
  ImGui::SameLine();
  ImGui::Checkbox("rays", &options_.ar.rays_enabled);
  ImGui::SameLine();
  ImGui::Checkbox("lines", &options_.ar.vertical_lines_enabled);
  ImGui::SameLine();
  ImGui::Checkbox("circles", &options_.ar.circles_enabled);
  ImGui::SameLine();
  ImGui::Checkbox("labels", &options_.ar.labels_enabled);
  ImGui::SliderFloat("red below [m]", &options_.ar.min_distance_m, 0.1f, 3.0f, "%.2f");
  ImGui::SliderFloat("green above [m]", &options_.ar.max_distance_m,
                     options_.ar.min_distance_m + 0.1f, 8.0f, "%.2f");
  ImGui::SliderFloat("slopeTh", &options_.ar.segmentation.slope_threshold, 0.005f, 0.5f, "%.3f");
  ImGui::Separator();
  ImGui::Text("Stereo alignment (right eye image offset, px)");
  ImGui::SliderFloat("dx", &options_.right_alignment.offset_x_px, -40, 40, "%.1f");
  ImGui::SliderFloat("dy", &options_.right_alignment.offset_y_px, -40, 40, "%.1f");
  // Crop the borders without correspondence in both eyes.
  const float dx = options_.right_alignment.offset_x_px;
  const float dy = options_.right_alignment.offset_y_px;
  for (render::EyeAlignment* a : {&options_.left_alignment, &options_.right_alignment}) {
    a->crop_left_px = dx > 0 ? dx : 0;
    a->crop_right_px = dx < 0 ? -dx : 0;
    a->crop_top_px = dy > 0 ? dy : 0;
    a->crop_bottom_px = dy < 0 ? -dy : 0;
  }
  int mode_index = 0;
  for (int i = 0; i < 9; ++i) {
    if (kModes[i] == options_.mode) mode_index = i;
  }
  const char* names[9];
  for (int i = 0; i < 9; ++i) names[i] = render::DisplayModeName(kModes[i]);
  if (ImGui::Combo("display", &mode_index, names, 9)) options_.mode = kModes[mode_index];
  ImGui::End();
}

void OperatorConsole::DrawEdgeView() {
  ImGui::SetNextWindowPos(ImVec2(20, 60), ImGuiCond_FirstUseEver);
  ImGui::Begin("Edges (thesis fig. 29)", &show_edge_view_, ImGuiWindowFlags_AlwaysAutoResize);
  vision::EdgeDetectorOptions& e = options_.vision.edges;
  bool changed = false;
  changed |= ImGui::SliderInt("lowTh", &e.low_threshold, 0, 254);
  changed |= ImGui::SliderInt("highTh", &e.high_threshold, 1, 255);
  float th1 = static_cast<float>(e.canny_threshold1);
  float th2 = static_cast<float>(e.canny_threshold2);
  changed |= ImGui::SliderFloat("th1", &th1, 0, 500, "%.0f");
  changed |= ImGui::SliderFloat("th2", &th2, 0, 800, "%.0f");
  float edge_th = static_cast<float>(options_.vision.classifier.edge_threshold_m);
  changed |= ImGui::SliderFloat("edgeTh [m]", &edge_th, 0.02f, 0.5f, "%.2f");
  ImGui::Checkbox("edge processing (E)", &options_.vision_enabled);
  if (changed) {
    vision::VisionOptions next = options_.vision;
    next.edges.canny_threshold1 = th1;
    next.edges.canny_threshold2 = th2;
    next.classifier.edge_threshold_m = edge_th;
    std::string error;
    if (edge_worker_->SetOptions(next, &error)) {
      options_.vision = next;
      status_line_.clear();
    } else {
      status_line_ = "edges: " + error;
    }
  }
  if (shown_result_ && !shown_result_->left_edges.edges.empty()) {
    edge_textures_[0] = UploadTexture(shown_result_->left_edges.stretched_grey, edge_textures_[0]);
    edge_textures_[1] = UploadTexture(shown_result_->left_edges.edges, edge_textures_[1]);
    const ImVec2 size(320, 240);
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(edge_textures_[0])), size);
    ImGui::SameLine();
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(edge_textures_[1])), size);
    const auto& c = shown_result_->classification;
    ImGui::Text("NEPs: %d corrected, %d possible obstacles; %.1f ms", c.corrected, c.nearer,
                ToSeconds(shown_result_->processing_time) * 1e3);
  } else {
    ImGui::TextUnformatted("no edge result yet");
  }
  ImGui::End();
}

void OperatorConsole::DrawHelp() {
  ImGui::SetNextWindowPos(ImVec2(240, 120), ImGuiCond_FirstUseEver);
  ImGui::Begin("Help", &show_help_, ImGuiWindowFlags_AlwaysAutoResize);
  ImGui::TextUnformatted(
      "Arrows / WASD   drive while held (release = stop)\n"
      "Gamepad         left stick drive, right stick turn, hold RB\n"
      "+ / -           speed scale\n"
      "T / R           take / release control\n"
      "X / U           emergency stop / release it\n"
      "1..9            display mode (mono L/R, anaglyph, colour anaglyph,\n"
      "                sbs, sbs-half, top-bottom, interlaced, quad-buffer)\n"
      "C               calibration and AR panel\n"
      "E / V           edge processing on/off / edge view (thresholds)\n"
      "H / M           HUD / laser map\n"
      "Esc             quit");
  ImGui::End();
}

}  // namespace mostar::ui
