#include "operator_client/ui/operator_console.h"

#include <algorithm>
#include <array>

#include "common/check/check.h"
#include "common/log/log.h"
#include "common/math/calibration_io.h"
#include "operator_client/render/eye_viewports.h"
#include "operator_client/render/gl.h"
#include "operator_client/render/screenshot.h"
#include "operator_client/ui/overlay_assembly.h"

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
      lease_(options.client_id, options.pilot),
      selfcal_(options.self_calibration) {}

OperatorConsole::~OperatorConsole() = default;

bool OperatorConsole::Init(std::string* error) {
  if (!stereo_view_.Init(error)) return false;
  if (!options_.ar.IsValid(error) || !options_.motion.IsValid(error)) return false;
  ar_builders_.emplace(options_.ar);
  if (!options_.calibration.IsValid(error)) return false;
  // The stereo alignment saved beside the calibration in its profile.
  std::string why;
  if (!options_.calibration_path.empty() &&
      !render::LoadAlignment(options_.calibration_path, &options_.alignment_model,
                             &options_.left_alignment, &options_.right_alignment, &why)) {
    MOSTAR_LOG(WARNING) << "stereo alignment not loaded, starting without offsets: " << why;
  }
  imgui_ = std::make_unique<ImGuiLayer>(window_->get());
  if (!options_.vision.IsValid(error)) return false;
  vision_ = std::make_unique<ConsoleVision>(options_.vision);
  vision_->SetResultWait(options_.vision_result_wait);
  return true;
}

void OperatorConsole::Send(ControlRequest request) {
  if (request != ControlRequest::kNone) commands_->RequestControl(request == ControlRequest::kTake);
}

void OperatorConsole::AdoptRobotIntrinsics(const client::RobotSnapshot& robot) {
  if (!options_.intrinsics_from_robot) return;
  const IntrinsicsAdopter::Result result =
      intrinsics_.Apply(robot.left_intrinsics, &options_.calibration);
  if (result.outcome == IntrinsicsAdopter::Outcome::kRefused) status_line_ = result.message;
  if (result.outcome == IntrinsicsAdopter::Outcome::kAdopted) MOSTAR_LOG(INFO) << result.message;
}

void OperatorConsole::HandleInput() {
  const ConsoleInput in = keys_.Poll(window_->get(), imgui_ && imgui_->WantsKeyboard());
  if (in.quit) window_->RequestClose();
  ApplyToggles(
      in, {&show_help_, &options_.show_calibration_panel, &options_.show_hud, &options_.show_map,
           &options_.sonar.enabled, &show_latency_, &options_.vision_enabled, &show_edge_view_});
  if (in.mode) options_.mode = *in.mode;
  if (in.take_control) lease_.Take();
  if (in.release_control) Send(lease_.Release());
  if (in.emergency_stop) commands_->SendEmergencyStop(true);
  if (in.release_emergency_stop) commands_->SendEmergencyStop(false);
  if (in.speed_up) mapper_.ScaleUp();
  if (in.speed_down) mapper_.ScaleDown();
  if (scripted_drive_) {
    // A scripted drive re-arms by itself after the robot stopped driving (RearmGuide).
    drive_ = lease_.armed(clock_->SteadyNow()) && !rearm_.hold_disarmed ? *scripted_drive_
                                                                        : DriveOutput{};
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
  const client::RobotSnapshot robot = robot_->Snapshot();
  return capture_->Filter(latest, StampOf(robot.latest_scan), clock_->SteadyNow(),
                          StampOf(robot.odometry));
}

void OperatorConsole::RefreshGeometry(const client::RobotSnapshot& robot) {
  std::string error;
  image_scale_ = ScaleOfPair(options_.calibration, video_->Latest(), image_scale_);
  // With per-eye intrinsics the right eye takes the robot's right intrinsics when valid.
  const bool own_right = options_.alignment_model == render::AlignmentModel::kPerEyeIntrinsics &&
                         options_.intrinsics_from_robot;
  const auto [left, right] = ScaledEyeCalibrations(
      options_.calibration, own_right ? robot.right_intrinsics : std::nullopt, image_scale_);
  const bool changed = geometry_.Update(
      left, right, options_.alignment_model, ScaledAlignment(options_.left_alignment, image_scale_),
      ScaledAlignment(options_.right_alignment, image_scale_), &error);
  if (!error.empty()) status_line_ = "alignment: " + error;
  // The calibration without offsets was checked in Init: there is always a geometry.
  MOSTAR_CHECK(geometry_.ready()) << error;
  if (!changed) return;
  vision_->GeometryChanged(std::make_shared<const math::CameraModel>(geometry_.eye(0).image),
                           std::make_shared<const math::CameraModel>(geometry_.eye(1).image));
}

void OperatorConsole::SetWakeSignal(WakeSignal* signal) { vision_->SetWakeSignal(signal); }

Duration OperatorConsole::IdleWait(Duration idle) const {
  if (!options_.vision_enabled) return idle;
  const std::optional<SteadyTime> wait_end = vision_->NextWaitEnd();
  if (!wait_end) return idle;
  return std::clamp<Duration>(*wait_end - clock_->SteadyNow(), Duration(0), idle);
}

void OperatorConsole::UpdateVision(const std::optional<client::DecodedStereoPair>& latest) {
  const SteadyTime now = clock_->SteadyNow();
  if (latest) tracer_.Picked(latest->sequence, now);
  std::string error;
  // Edge processing sees the nearest scan from the camera's pose: moved to the pair's capture
  // time and resampled on its beams (PlaceScanForVision); its corrected scan is drawn as it is.
  const auto scan_for = [this](Time stamp) -> std::optional<ConsoleVision::PlacedScan> {
    std::optional<LaserScan> nearest = robot_->NearestScan(stamp);
    if (!nearest) return std::nullopt;
    fusion::MovedScan moved;
    const bool compensate = options_.motion.enabled;
    if (compensate) {
      robot_->MoveScanToImageTime(*nearest, stamp, options_.motion.compensation, &moved);
    }
    ConsoleVision::PlacedScan placed;
    placed.placement = PlaceScanForVision(*nearest, compensate ? &moved : nullptr, &placed.scan);
    return placed;
  };
  vision_->Update(latest, options_.vision_enabled, now, scan_for, OverlayBuilder(&error));
  selfcal_.Update(vision_->picker().shown_result(), robot_->Snapshot().odometry, options_.vision,
                  geometry_);
}

const fusion::ArFeatureBuilder& OperatorConsole::OverlayBuilder(std::string* error) {
  return ar_builders_->For(
      OverlayArOptions(options_.ar, options_.calibration.laser_height_m,
                       options_.show_calibration_panel),  // rays help calibrate
      error);
}

void OperatorConsole::BuildOverlay(const client::RobotSnapshot& robot,
                                   const FramePicker::DrawnScan& drawn,
                                   render::OverlayGeometry* overlay, fusion::ArFeatures* features,
                                   fusion::SonarFeatures* sonar) {
  motion_ = {};
  const std::optional<client::DecodedStereoPair>& pair = vision_->picker().shown_pair();
  const std::optional<LaserScan>& scan = drawn.scan;
  if (scan) {
    std::string error;
    const fusion::ArFeatureBuilder& builder = OverlayBuilder(&error);
    const bool compensate = options_.motion.enabled && pair;
    if (drawn.placement && pair) {
      // Edge processing's corrected scan: already at the image's time (or known not to be).
      motion_ = BuildPlacedOverlayFeatures(builder, *scan, *drawn.placement, pair->stamp,
                                           compensate, options_.motion, features);
    } else {
      // The scan at the shown image's capture time (robot clock), moved with the odometry.
      fusion::MovedScan* moved = compensate ? &moved_ : nullptr;
      if (moved) {
        robot_->MoveScanToImageTime(*scan, pair->stamp, options_.motion.compensation, moved);
      }
      motion_ = BuildOverlayFeatures(builder, *scan, moved, options_.motion, features);
    }
    if (!error.empty()) status_line_ = "AR options: " + error;
  }
  fusion::ArFeatureOptions colors = options_.ar;
  colors.laser_height_m = static_cast<float>(options_.calibration.laser_height_m);
  const Duration sonar_age = fusion::SonarAgeAtImage(
      robot.sonar, StampOf(pair), clock_->SteadyNow() - robot.last_sonar_received);
  const bool sonar_fresh =
      fusion::BuildFreshSonarFeatures(robot.sonar, sonar_age, scan ? &*scan : nullptr,
                                      features->points, colors, options_.sonar, sonar);
  // Possible obstacles the laser missed (NEPs much nearer than the laser point): magenta dots.
  static const std::vector<vision::PossibleObstacle> kNone;
  const auto& result = vision_->picker().shown_result();
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
    const std::optional<WatchdogState> watchdog =
        snapshot.health ? std::optional<WatchdogState>(snapshot.health->watchdog_state)
                        : std::nullopt;
    rearm_ = rearm_guide_.Update(lease_.holding(), watchdog, snapshot.last_health_received,
                                 drive_.enable, scripted_drive_.has_value(), clock_->SteadyNow());
    AdoptRobotIntrinsics(snapshot);
    RefreshGeometry(snapshot);
  }
  HandleInput();
  UpdateVision(CaptureFilter(video_->Latest()));
  const FramePicker& picker = vision_->picker();
  const std::optional<client::DecodedStereoPair>& pair = picker.shown_pair();
  // A render of the captured pair with its scans and edge result in.
  const bool capture_render = capture_ && capture_->IsCaptureRender(pair, options_.vision_enabled,
                                                                    picker.result_sequence());
  const FrameSchedule::Decision frame =
      schedule_.Next(pair ? std::optional<uint64_t>(pair->sequence) : std::nullopt,
                     picker.shown_version(), options_.headless, capture_render);
  if (!frame.draw) return false;
  const bool new_pair = frame.new_pair;
  const SteadyTime start = clock_->SteadyNow();

  const client::RobotSnapshot robot = robot_->Snapshot();
  const FramePicker::DrawnScan scan =
      vision_->picker().ScanToDraw(pair ? robot_->NearestScan(pair->stamp) : robot.latest_scan);
  render::OverlayGeometry overlay;
  fusion::ArFeatures features;
  fusion::SonarFeatures sonar;
  BuildOverlay(robot, scan, &overlay, &features, &sonar);
  sonar_echoes_ = sonar.echoes;
  sonar_unseen_ = sonar.unseen;
  const SteadyTime overlay_built = clock_->SteadyNow();

  // Only the eyes the display mode shows are drawn (one in mono), in place where they can be.
  static const cv::Mat kEmpty;
  std::array<render::EyeInput, 2> eye_inputs;
  for (int e = 0; e < 2; ++e) {
    eye_inputs[static_cast<size_t>(e)] = {
        pair ? (e == 0 ? &pair->left : &pair->right) : &kEmpty,
        render::MakeEyeView(geometry_.eye(e)),
        ScaledAlignment(e == 0 ? options_.left_alignment : options_.right_alignment, image_scale_)};
  }
  stereo_view_.DrawEyes(options_.mode, window_->quad_buffer(), fb_w, fb_h, eye_inputs, overlay);
  const SteadyTime eyes_drawn = clock_->SteadyNow();
  stereo_view_.Compose(options_.mode, window_->quad_buffer(), fb_w, fb_h);
  const SteadyTime composed = clock_->SteadyNow();
  imgui_->BeginFrame();
  DrawPanels(robot, features, sonar, pair, fb_w, fb_h);
  imgui_->EndFrame();
  const SteadyTime drawn = clock_->SteadyNow();
  if (new_pair || frame.new_result) {
    if (new_pair) ++rendered_pairs_;
    if (options_.headless && options_.keep_last_frame) {
      last_frame_ = render::ReadFramebuffer(fb_w, fb_h);
    }
  }
  if (capture_render && capture_->CountRender()) last_frame_ = render::ReadFramebuffer(fb_w, fb_h);
  window_->SwapBuffers();
  glFinish();  // presented: the frame is on screen, not queued in the driver
  const SteadyTime presented = clock_->SteadyNow();
  frame_time_ms_ = ToSeconds(presented - start) * 1e3;
  if (new_pair) {
    const RobotTimeMapper to_robot(clock_->Now(), clock_->SteadyNow(), robot.clock);
    shown_.Add(ToSeconds(to_robot(drawn) - pair->stamp) * 1e3, frame_time_ms_);  // capture to drawn
    shown_.CountOverlay(motion_.moved, motion_.faded);
    if (schedule_.CountsForTrace(presented, options_.trace_warmup)) {
      const auto ms = [](SteadyTime from, SteadyTime to) { return ToSeconds(to - from) * 1e3; };
      frame_parts_.Add({ms(start, overlay_built), ms(overlay_built, eyes_drawn),
                        ms(eyes_drawn, composed), ms(composed, drawn)});
      latency_.Add(tracer_.Timeline(
          {pair->sequence, pair->stamp, pair->received, pair->decode_started, pair->decoded},
          robot_->TimingOf(pair->stamp), {picker.shown_ready_at(), start, drawn, presented},
          options_.vision_enabled, to_robot));
    }
  }
  return true;
}

ConsoleRunTotals OperatorConsole::RunTotals(Duration run) const {
  ConsoleRunTotals totals;
  totals.rendered_frames = rendered_pairs_;
  totals.scripted_rearms = rearm_guide_.scripted_rearms();
  totals.scans = robot_->Snapshot().scans;
  totals.commands_sent = commands_->commands_sent();
  totals.run_s = ToSeconds(run);
  totals.display_age_ms_p50 = shown_.DisplayAgePercentileMs(50);
  totals.display_age_ms_p95 = shown_.DisplayAgePercentileMs(95);
  totals.frame_time_ms_p50 = shown_.FrameTimePercentileMs(50);
  totals.frame_time_ms_p95 = shown_.FrameTimePercentileMs(95);
  if (captured()) totals.captured_stamp_ns = ToUnixNanos(*captured_stamp());
  totals.sonar_echoes = sonar_echoes_;
  totals.sonar_unseen = sonar_unseen_;
  totals.overlays_moved = shown_.overlays_moved();
  totals.overlays_faded = shown_.overlays_faded();
  totals.latency = latency_.Rows();
  totals.frame_parts = frame_parts_.Rows();
  const FramePicker::Counts& vision = vision_->picker().counts();
  totals.vision_in_time = vision.in_time;
  totals.vision_without_result = vision.without_result;
  totals.vision_added_late = vision.added_late;
  totals.vision_missed = vision.missed;
  return totals;
}

}  // namespace mostar::ui
