#include "operator_client/ui/operator_console.h"

#include <algorithm>

#include "common/check/check.h"
#include "common/log/log.h"
#include "common/math/calibration_io.h"
#include "common/stats/percentile.h"
#include "operator_client/render/gl.h"
#include "operator_client/render/screenshot.h"
#include "operator_client/ui/bumper_display.h"
#include "operator_client/ui/overlay_assembly.h"
#include "operator_client/ui/panels/calibration_panel.h"
#include "operator_client/ui/panels/help_panel.h"
#include "operator_client/ui/panels/hud_panel.h"
#include "operator_client/ui/panels/labels_panel.h"
#include "operator_client/ui/panels/latency_panel.h"
#include "operator_client/ui/panels/map_panel.h"

namespace mostar::ui {

OperatorConsole::OperatorConsole(const ConsoleOptions& options, Window* window,
                                 client::StereoReceiver* video, client::RobotState* robot,
                                 CommandSender* commands, const Clock* clock)
    : options_(options),
      window_(window),
      video_(video),
      robot_(robot),
      commands_(commands),
      clock_(clock),
      mapper_(options.drive),
      lease_(options.client_id, options.pilot) {}

OperatorConsole::~OperatorConsole() = default;

bool OperatorConsole::Init(std::string* error) {
  if (!eyes_[0].Init(error) || !eyes_[1].Init(error) || !compositor_.Init(error)) return false;
  if (!options_.ar.IsValid(error)) return false;
  ar_builders_.emplace(options_.ar);
  if (!options_.calibration.IsValid(error)) return false;
  // The stereo alignment saved beside the calibration in its profile.
  if (!options_.calibration_path.empty()) {
    math::LaserCameraCalibration calibration;
    math::StereoAlignmentProfile alignment;
    std::string why;
    if (math::LoadCalibrationProfile(options_.calibration_path, &calibration, &alignment, &why)) {
      render::FromProfile(alignment, &options_.alignment_model, &options_.left_alignment,
                          &options_.right_alignment);
    } else {
      MOSTAR_LOG(WARNING) << "stereo alignment not loaded, starting without offsets: " << why;
    }
  }
  imgui_ = std::make_unique<ImGuiLayer>(window_->get());
  if (!options_.vision.IsValid(error)) return false;
  edge_worker_ = std::make_unique<vision::EdgeWorker>(options_.vision);
  vision_settings_.emplace(options_.vision);
  return true;
}

void OperatorConsole::Send(ControlRequest request) {
  if (request != ControlRequest::kNone) {
    commands_->RequestControl(request == ControlRequest::kTake);
  }
}

void OperatorConsole::AdoptRobotIntrinsics(const client::RobotSnapshot& robot) {
  if (!options_.intrinsics_from_robot) return;
  const IntrinsicsAdopter::Result result =
      intrinsics_.Apply(robot.left_intrinsics, &options_.calibration);
  if (result.outcome == IntrinsicsAdopter::Outcome::kRefused) status_line_ = result.message;
  if (result.outcome == IntrinsicsAdopter::Outcome::kAdopted) {
    const CameraIntrinsicsInfo& k = *robot.left_intrinsics;
    MOSTAR_LOG(INFO) << "using the robot's camera intrinsics: f " << k.fx << "/" << k.fy
                     << " px, principal point (" << k.cx << ", " << k.cy << ") for " << k.width_px
                     << "x" << k.height_px << " images";
  }
}

void OperatorConsole::HandleInput() {
  const ConsoleInput in = keys_.Poll(window_->get(), imgui_ && imgui_->WantsKeyboard());
  if (in.quit) window_->RequestClose();
  if (in.toggle_help) show_help_ = !show_help_;
  if (in.toggle_calibration) options_.show_calibration_panel = !options_.show_calibration_panel;
  if (in.toggle_hud) options_.show_hud = !options_.show_hud;
  if (in.toggle_map) options_.show_map = !options_.show_map;
  if (in.toggle_sonar) options_.sonar.enabled = !options_.sonar.enabled;
  if (in.toggle_latency) show_latency_ = !show_latency_;
  if (in.toggle_vision) options_.vision_enabled = !options_.vision_enabled;
  if (in.toggle_edge_view) show_edge_view_ = !show_edge_view_;
  if (in.mode) options_.mode = *in.mode;
  if (in.take_control) lease_.Take();
  if (in.release_control) Send(lease_.Release());
  if (in.emergency_stop) commands_->SendEmergencyStop(true);
  if (in.release_emergency_stop) commands_->SendEmergencyStop(false);
  if (in.speed_up) mapper_.ScaleUp();
  if (in.speed_down) mapper_.ScaleDown();
  if (scripted_drive_) {
    drive_ = lease_.armed(clock_->SteadyNow()) ? *scripted_drive_ : DriveOutput{};
  } else {
    drive_ = options_.pilot ? mapper_.Map(in.drive) : DriveOutput{};
  }
  commands_->SetDrive(drive_);
  commands_->SetActive(lease_.active());
}

void OperatorConsole::CapturePair(std::optional<Time> stamp) {
  const auto latest = video_->Latest();
  capture_.emplace(stamp, latest ? latest->sequence : 0);
}

std::optional<Time> OperatorConsole::captured_stamp() const {
  return capture_ ? capture_->latched_stamp() : std::nullopt;
}

std::optional<client::DecodedStereoPair> OperatorConsole::CaptureFilter(
    const std::optional<client::DecodedStereoPair>& latest) {
  if (!capture_) return latest;
  const std::optional<LaserScan> scan = robot_->Snapshot().latest_scan;
  return capture_->Filter(latest, scan ? std::optional<Time>(scan->stamp) : std::nullopt,
                          clock_->SteadyNow());
}

math::LaserCameraCalibration OperatorConsole::EyeCalibration(math::Eye eye,
                                                             const client::RobotSnapshot& robot) {
  if (options_.alignment_model != render::AlignmentModel::kPerEyeIntrinsics ||
      eye != math::Eye::kRight || !options_.intrinsics_from_robot || !robot.right_intrinsics) {
    return options_.calibration;
  }
  math::LaserCameraCalibration right;
  std::string error;
  if (!WithRobotIntrinsics(options_.calibration, *robot.right_intrinsics, &right, &error)) {
    return options_.calibration;
  }
  return right;
}

void OperatorConsole::RefreshGeometry(const client::RobotSnapshot& robot) {
  std::string error;
  image_scale_ = ScaleOfPair(options_.calibration, video_->Latest(), image_scale_);
  const bool changed = geometry_.Update(
      ScaledCalibration(EyeCalibration(math::Eye::kLeft, robot), image_scale_),
      ScaledCalibration(EyeCalibration(math::Eye::kRight, robot), image_scale_),
      options_.alignment_model, ScaledAlignment(options_.left_alignment, image_scale_),
      ScaledAlignment(options_.right_alignment, image_scale_), &error);
  if (!error.empty()) status_line_ = "alignment: " + error;
  // The calibration without offsets was checked in Init: there is always a geometry.
  MOSTAR_CHECK(geometry_.ready()) << error;
  if (!changed) return;
  hint_gate_.GeometryChanged(last_submitted_);
  left_model_ = std::make_shared<const math::CameraModel>(geometry_.eye(0).image);
  right_model_ = std::make_shared<const math::CameraModel>(geometry_.eye(1).image);
}

void OperatorConsole::UpdateVision(const std::optional<client::DecodedStereoPair>& latest) {
  if (latest && (picked_.empty() || picked_.back().first != latest->sequence)) {
    picked_.emplace_back(latest->sequence, clock_->SteadyNow());
    while (picked_.size() > 16) picked_.pop_front();
  }
  if (!options_.vision_enabled) {
    picker_.ShowUnprocessed(latest);
    return;
  }
  if (picker_.TakeNew(latest)) {
    vision::VisionInput input;
    input.stamp = latest->stamp;
    input.sequence = latest->sequence;
    input.left = latest->left;
    input.right = latest->right;
    if (auto scan = robot_->NearestScan(latest->stamp)) {
      input.scan = *scan;
      // The overlay's builder: a live slopeTh edit moves the outliers the edges check too.
      std::string error;
      input.potential_outliers = PotentialOutliers(OverlayBuilder(&error), *scan);
    }
    input.left_camera = left_model_;
    input.right_camera = right_model_;
    last_submitted_ = input.sequence;
    edge_worker_->Submit(std::move(input));
  }
  picker_.OnResult(edge_worker_->LatestResult(), latest);
}

const fusion::ArFeatureBuilder& OperatorConsole::OverlayBuilder(std::string* error) {
  return ar_builders_->For(
      OverlayArOptions(options_.ar, options_.calibration.laser_height_m,
                       options_.show_calibration_panel),  // rays help calibrate
      error);
}

void OperatorConsole::BuildOverlay(const client::RobotSnapshot& robot,
                                   const std::optional<LaserScan>& scan,
                                   render::OverlayGeometry* overlay, fusion::ArFeatures* features,
                                   fusion::SonarFeatures* sonar) {
  if (scan) {
    std::string error;
    OverlayBuilder(&error).Build(*scan, features);
    if (!error.empty()) status_line_ = "AR options: " + error;
  }
  // The belt cycles at about 5 Hz: a cycle older than a second no longer shows where things are.
  const bool sonar_fresh =
      robot.sonar && clock_->SteadyNow() - robot.last_sonar_received < std::chrono::seconds(1);
  if (sonar_fresh) {
    fusion::ArFeatureOptions colors = options_.ar;
    colors.laser_height_m = static_cast<float>(options_.calibration.laser_height_m);
    fusion::LaserFieldOfView fov;  // none without a scan: nothing compared
    if (scan) fov = {scan->angle_min_rad, scan->angle_max_rad()};
    fusion::BuildSonarFeatures(*robot.sonar, features->points, fov, colors, options_.sonar, sonar);
  }
  // Possible obstacles the laser missed (NEPs much nearer than the laser point): magenta dots.
  static const std::vector<vision::PossibleObstacle> kNone;
  const auto& result = picker_.shown_result();
  fusion::VertexArray predicted;
  if (drive_.enable) {
    fusion::PredictedPathOptions path = options_.path;
    path.laser_height_m = static_cast<float>(options_.calibration.laser_height_m);
    fusion::BuildPredictedPath(drive_.linear_mps, drive_.angular_radps, path, &predicted);
  }
  AssembleOverlay(sonar_fresh ? sonar : nullptr, scan ? features : nullptr,
                  result ? result->classification.possible_obstacles : kNone, predicted, overlay);
}

bool OperatorConsole::Frame() {
  Window::PollEvents();
  int fb_w = 0;
  int fb_h = 0;
  window_->FramebufferSize(&fb_w, &fb_h);
  video_->SetDecodeTarget(
      DecodeTargetFor(options_.mode, fb_w, fb_h, options_.vision_enabled, options_.vision.stereo));
  {
    const client::RobotSnapshot snapshot = robot_->Snapshot();
    Send(lease_.Update(snapshot.lease, clock_->SteadyNow()));
    AdoptRobotIntrinsics(snapshot);
    RefreshGeometry(snapshot);
  }
  HandleInput();
  UpdateVision(CaptureFilter(video_->Latest()));
  const std::optional<client::DecodedStereoPair>& pair = picker_.shown_pair();
  const std::shared_ptr<const vision::VisionResult>& result = picker_.shown_result();
  const bool new_pair = pair && pair->sequence != last_pair_;
  // A render of the captured pair with its scans and edge result in.
  const bool capture_render = capture_ && capture_->IsCaptureRender(pair, options_.vision_enabled,
                                                                    picker_.result_sequence());
  if (options_.headless && !new_pair && !capture_render) return false;
  const SteadyTime start = clock_->SteadyNow();

  const client::RobotSnapshot robot = robot_->Snapshot();
  std::optional<LaserScan> scan = pair ? robot_->NearestScan(pair->stamp) : robot.latest_scan;
  // With an edge result for this very pair, draw the corrected scan (NEP-corrected points,
  // confirmed outliers removed).
  if (result && pair && result->sequence == pair->sequence &&
      !result->classification.corrected_scan.ranges_m.empty()) {
    scan = result->classification.corrected_scan;
  }
  render::OverlayGeometry overlay;
  fusion::ArFeatures features;
  fusion::SonarFeatures sonar;
  BuildOverlay(robot, scan, &overlay, &features, &sonar);
  sonar_echoes_ = sonar.echoes;
  sonar_unseen_ = sonar.unseen;

  for (int e = 0; e < 2; ++e) {
    static const cv::Mat kEmpty;
    const cv::Mat& image = pair ? (e == 0 ? pair->left : pair->right) : kEmpty;
    eyes_[e].Render(
        image, render::MakeEyeView(geometry_.eye(e)), overlay,
        ScaledAlignment(e == 0 ? options_.left_alignment : options_.right_alignment, image_scale_));
  }
  compositor_.Compose(options_.mode, eyes_[0].texture(), eyes_[1].texture(), fb_w, fb_h,
                      window_->quad_buffer());
  imgui_->BeginFrame();
  DrawPanels(robot, features, sonar, pair, fb_w, fb_h);
  imgui_->EndFrame();
  const SteadyTime drawn = clock_->SteadyNow();
  if (new_pair) {
    last_pair_ = pair->sequence;
    ++rendered_pairs_;
    if (options_.headless && options_.keep_last_frame) {
      last_frame_ = render::ReadFramebuffer(fb_w, fb_h);
    }
    // Capture-to-display age, on the robot's clock when the offset is known.
    Time now = clock_->Now();
    if (robot.clock.known) now = robot.clock.ToResponderTime(now);
    display_age_ms_ = ToSeconds(now - pair->stamp) * 1e3;
    if (display_ages_ms_.size() < 100000) display_ages_ms_.push_back(display_age_ms_);
  }
  if (capture_render && capture_->CountRender()) last_frame_ = render::ReadFramebuffer(fb_w, fb_h);
  window_->SwapBuffers();
  glFinish();  // presented: the frame is on screen, not queued in the driver
  const SteadyTime presented = clock_->SteadyNow();
  if (new_pair) TracePair(*pair, robot, start, drawn, presented);
  frame_time_ms_ = ToSeconds(presented - start) * 1e3;
  if (new_pair && frame_times_ms_.size() < 100000) frame_times_ms_.push_back(frame_time_ms_);
  return new_pair;
}

Time OperatorConsole::ToRobotTime(SteadyTime t, const client::RobotSnapshot& robot) const {
  const Time local = clock_->Now() - (clock_->SteadyNow() - t);
  return robot.clock.known ? robot.clock.ToResponderTime(local) : local;
}

void OperatorConsole::TracePair(const client::DecodedStereoPair& pair,
                                const client::RobotSnapshot& robot, SteadyTime frame_start,
                                SteadyTime drawn, SteadyTime presented) {
  PairTimeline timeline;
  timeline.capture = pair.stamp;
  if (const std::optional<FrameTiming> timing = robot_->TimingOf(pair.stamp)) {
    timeline.Set(LatencyStage::kEncoded, timing->encoded);
    timeline.Set(LatencyStage::kWritten, timing->written);
  }
  timeline.Set(LatencyStage::kReceived, ToRobotTime(pair.received, robot));
  timeline.Set(LatencyStage::kDecoded, ToRobotTime(pair.decoded, robot));
  std::optional<Time> picked;
  for (const auto& [sequence, at] : picked_) {
    if (sequence == pair.sequence) picked = ToRobotTime(at, robot);
  }
  if (picked) timeline.Set(LatencyStage::kPicked, *picked);
  // With edge processing on, the pair is shown in the first frame that has its result.
  if (options_.vision_enabled) {
    timeline.Set(LatencyStage::kVision, ToRobotTime(frame_start, robot));
  } else if (picked) {
    timeline.Set(LatencyStage::kVision, *picked);
  }
  timeline.Set(LatencyStage::kDrawn, ToRobotTime(drawn, robot));
  timeline.Set(LatencyStage::kPresented, ToRobotTime(presented, robot));
  latency_.Add(timeline);
}

double OperatorConsole::DisplayAgePercentileMs(double percentile) const {
  return Percentile(display_ages_ms_, percentile / 100.0).value_or(0.0);
}

double OperatorConsole::FrameTimePercentileMs(double percentile) const {
  return Percentile(frame_times_ms_, percentile / 100.0).value_or(0.0);
}

std::optional<StereoOffsetHint> OperatorConsole::OffsetHint() const {
  const std::shared_ptr<const vision::VisionResult>& result = picker_.shown_result();
  if (!result || !result->ok || !result->stereo) return std::nullopt;
  const vision::StereoOffsetEstimate& estimate = result->nesc.offset;
  return hint_gate_.Hint(
      result->sequence, estimate,
      render::SuggestedRightOffsetY(geometry_.eye(0), geometry_.eye(1),
                                    ScaledAlignment(options_.left_alignment, image_scale_),
                                    estimate.vertical_offset_px) /
          static_cast<float>(image_scale_.y));  // in the profile's pixels
}

void OperatorConsole::DrawPanels(const client::RobotSnapshot& robot,
                                 const fusion::ArFeatures& features,
                                 const fusion::SonarFeatures& sonar,
                                 const std::optional<client::DecodedStereoPair>& pair, int fb_w,
                                 int fb_h) {
  if (options_.ar.labels_enabled) {
    DrawLabelsPanel(features, geometry_.eye(0).display, geometry_.eye(1).display, options_.mode,
                    fb_w, fb_h);
  }
  if (options_.show_hud) {
    HudStatus hud;
    hud.has_pair = pair.has_value();
    if (pair) hud.pair_received = pair->received;
    hud.display_age_ms = display_age_ms_;
    hud.frame_time_ms = frame_time_ms_;
    hud.mode = options_.mode;
    hud.client_id = options_.client_id;
    hud.pilot = options_.pilot;
    hud.dds_security_off = options_.dds_security_off;
    hud.drive = drive_;
    hud.drive_scale = mapper_.scale();
    hud.status_line = status_line_;
    hud.pending_estop = commands_->pending_estop();
    hud.sonar_echoes = sonar.echoes;
    hud.sonar_unseen = sonar.unseen;
    DrawHudPanel(robot, video_->Stats(), hud, clock_->SteadyNow());
  }
  if (options_.show_map) {
    DrawMapPanel(features, sonar,
                 ViewBumpers(robot.bumpers, robot.last_bumpers_received, clock_->SteadyNow()),
                 options_.path.half_width_m);
  }
  if (options_.show_calibration_panel) {
    DrawCalibrationPanel(options_.calibration_path,
                         {&options_.show_calibration_panel, &options_.calibration, &options_.ar,
                          &options_.left_alignment, &options_.right_alignment,
                          &options_.alignment_model, &options_.mode, &status_line_},
                         OffsetHint());
  }
  if (show_edge_view_) {
    const std::optional<VisionSettings> next =
        edge_view_.Draw(picker_.shown_result().get(), *vision_settings_,
                        VisionSettingsPath(options_.calibration_path), &show_edge_view_,
                        &options_.vision_enabled, &status_line_);
    std::string error;
    if (next && edge_worker_->SetOptions(next->options(), &error)) {
      vision_settings_ = next;
      options_.vision = next->options();
    } else if (next) {
      status_line_ = "edges: " + error;
    }
  }
  if (show_latency_) DrawLatencyPanel(latency_, &show_latency_);
  if (show_help_) DrawHelpPanel(&show_help_);
}

}  // namespace mostar::ui
