// The operator console: one render loop that shows the latest stereo pair with the AR overlay
// built from the scan nearest in time, the HUD, the bird's-eye laser map, the calibration and
// display panels, and turns keyboard/gamepad input into drive requests. It wires the tested
// parts (LeaseClient, IntrinsicsAdopter, ConsoleVision, PairCapture, ArBuilderCache, PairTracer,
// ShownPairStats) to the devices, the renderer and the panels (ui/panels).
//
// Render thread only. It never waits on the network or on JPEG decoding: it takes the latest
// decoded pair from StereoReceiver and the latest robot state from RobotState.
#pragma once

#include <memory>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/math/camera_model.h"
#include "operator_client/fusion/predicted_path.h"
#include "operator_client/fusion/sonar_features.h"
#include "operator_client/net/robot_state.h"
#include "operator_client/render/eye_renderer.h"
#include "operator_client/render/stereo_view.h"
#include "operator_client/ui/ar_builder_cache.h"
#include "operator_client/ui/command_sender.h"
#include "operator_client/ui/console_input.h"
#include "operator_client/ui/console_self_calibration.h"
#include "operator_client/ui/console_vision.h"
#include "operator_client/ui/decode_scaling.h"
#include "operator_client/ui/drive_input.h"
#include "operator_client/ui/frame_parts.h"
#include "operator_client/ui/frame_picker.h"
#include "operator_client/ui/frame_schedule.h"
#include "operator_client/ui/imgui_layer.h"
#include "operator_client/ui/intrinsics_adoption.h"
#include "operator_client/ui/latency_trace.h"
#include "operator_client/ui/lease_client.h"
#include "operator_client/ui/motion_overlay.h"
#include "operator_client/ui/pair_capture.h"
#include "operator_client/ui/pair_tracer.h"
#include "operator_client/ui/panels/edge_view_panel.h"
#include "operator_client/ui/rearm_guide.h"
#include "operator_client/ui/run_report.h"
#include "operator_client/ui/shown_pair_stats.h"
#include "operator_client/ui/stereo_hint.h"
#include "operator_client/ui/vision_settings.h"
#include "operator_client/ui/window.h"
#include "operator_client/video/stereo_receiver.h"
#include "operator_client/vision/edge_worker.h"
#include "operator_client/vision/vision_pipeline.h"

namespace mostar::ui {

struct ConsoleOptions {
  std::string client_id = "operator";
  bool pilot = true;
  bool dds_security_off = false;  // --insecure on a network profile: the HUD warns
  render::DisplayMode mode = render::DisplayMode::kMonoLeft;
  bool headless = false;
  bool show_calibration_panel = false;
  bool show_hud = true;
  bool show_map = true;
  // Headless: keep a copy of each frame that shows a new pair (for --screenshot); a read-back
  // of the framebuffer per pair, so off unless a screenshot is wanted.
  bool keep_last_frame = true;
  std::string calibration_path;  // where "save" writes; empty: calibration_profile.pbtxt
  math::LaserCameraCalibration calibration;
  fusion::ArFeatureOptions ar;
  fusion::SonarFeatureOptions sonar;  // colours and floor from `ar`
  fusion::PredictedPathOptions path;
  MotionOverlayOptions motion;  // each scan drawn at its image's capture time
  DriveLimits drive;
  // Edge processing (thesis 8, 9.2): NEPs correct the overlay, mark obstacles the laser
  // missed and confirm outliers. Toggled with E; thresholds in the edge view (V).
  bool vision_enabled = true;
  // How long a new pair waits for its edge result before it is shown without it (its dots and
  // correction are added when the result comes, unless a newer pair is on screen by then).
  Duration vision_result_wait = std::chrono::milliseconds(10);
  // Pairs shown in this long after the first one are left out of the latency trace (start-up:
  // discovery, the first decodes, caches filling).
  Duration trace_warmup = std::chrono::seconds(2);
  // Use the intrinsics the robot publishes (focal, principal point, distortion).
  bool intrinsics_from_robot = true;
  vision::VisionOptions vision;
  render::EyeAlignment left_alignment;  // thesis 9.1 stereo alignment (image offsets, crop)
  render::EyeAlignment right_alignment;
  // What `calibration` describes (render/eye_geometry.h): the displayed, aligned images with
  // parameters shared by both eyes (the thesis), or each camera's own image (the right eye then
  // takes the robot's right intrinsics when it publishes them).
  render::AlignmentModel alignment_model = render::AlignmentModel::kSharedModel;
  // Proposals of a refined calibration from the agreeing NEPs (calibration panel); valid.
  ConsoleSelfCalibration::Options self_calibration;
};

class OperatorConsole {
 public:
  OperatorConsole(const ConsoleOptions& options, Window* window, client::StereoReceiver* video,
                  client::RobotState* robot, CommandSender* commands, const Clock* clock);
  ~OperatorConsole();
  // GL and ImGui set-up; false with a message.
  bool Init(std::string* error);
  // Polls input and renders one frame (in headless mode only when the shown pair or its edge
  // result changed). Returns true when a frame was drawn.
  bool Frame();
  // How long the render loop may sleep before the next Frame() when nothing wakes it: at most
  // `idle`, less when a pair's result wait ends sooner.
  Duration IdleWait(Duration idle) const;
  // Wakes the render loop when a new pair is decoded or an edge result is published (set on
  // the receiver by the caller); not owned, outlives the console.
  void SetWakeSignal(WakeSignal* signal);
  // The last composed frame that showed a new pair (BGR8), for --screenshot.
  const cv::Mat& last_frame() const { return last_frame_; }
  uint64_t rendered_pairs() const { return rendered_pairs_; }
  // Re-arms of a scripted drive after the robot stopped driving (RearmGuide).
  uint64_t scripted_rearms() const { return rearm_guide_.scripted_rearms(); }
  // Percentile (0..100) of the capture-to-display age and of the render time of frames that
  // showed a new pair, in ms; 0 when none.
  double DisplayAgePercentileMs(double percentile) const {
    return shown_.DisplayAgePercentileMs(percentile);
  }
  double FrameTimePercentileMs(double percentile) const {
    return shown_.FrameTimePercentileMs(percentile);
  }
  // Where the capture-to-screen time of the shown pairs went, stage by stage (robot clock).
  const LatencyTrace& latency() const { return latency_; }
  // Sonar sectors of the last frame drawn: echoes, and those the laser does not see.
  size_t sonar_echoes() const { return sonar_echoes_; }
  size_t sonar_unseen() const { return sonar_unseen_; }
  // The scan of the last frame drawn: moved to its image's time, or faded and why.
  const MotionOverlayStatus& motion() const { return motion_; }
  // The options in force (after Init: with the alignment from the calibration profile).
  const ConsoleOptions& options() const { return options_; }
  const ShownPairStats& shown() const { return shown_; }
  // What this run counted, for its report line; `run` is the render loop's length.
  ConsoleRunTotals RunTotals(Duration run) const;
  // Holds a fixed command (for scripted/headless runs); keyboard and gamepad are then ignored.
  // The console first waits to hold the lease, then arms (LeaseClient::armed), then drives.
  void SetScriptedDrive(const DriveOutput& drive) { scripted_drive_ = drive; }

  // Deterministic screenshot of one pair (--capture-stamp, --capture-after; see PairCapture):
  // from this call on only the pair stamped `stamp` is shown, or with nullopt the next new pair
  // decoded after the call; once it has been rendered with its scans and edge result in,
  // captured() is true and last_frame() holds it.
  void CapturePair(std::optional<Time> stamp);
  bool capturing() const { return capture_.has_value(); }
  bool captured() const { return capture_ && capture_->done(); }
  // Capture stamp of the captured (or latched) pair.
  std::optional<Time> captured_stamp() const;

 private:
  void HandleInput();
  void Send(ControlRequest request);
  void AdoptRobotIntrinsics(const client::RobotSnapshot& robot);
  // While capturing: the captured pair once it may be shown, else nothing.
  std::optional<client::DecodedStereoPair> CaptureFilter(
      const std::optional<client::DecodedStereoPair>& latest);
  // Rebuilds both eyes' geometry when the calibration, the alignment or its model changed; an
  // invalid combination keeps the previous geometry and says why on the status line.
  void RefreshGeometry(const client::RobotSnapshot& robot);
  // Notes when the pair was picked and runs ConsoleVision's tick.
  void UpdateVision(const std::optional<client::DecodedStereoPair>& latest);
  // The AR builder of the overlay's current options (the configured one, with `error`, when
  // they are invalid); rebuilt only when they change.
  const fusion::ArFeatureBuilder& OverlayBuilder(std::string* error);
  // The frame's overlay: AR features of `scan`, the sonar sectors of the robot's latest belt
  // cycle (when fresh), possible obstacles and the predicted path.
  void BuildOverlay(const client::RobotSnapshot& robot, const FramePicker::DrawnScan& drawn,
                    render::OverlayGeometry* overlay, fusion::ArFeatures* features,
                    fusion::SonarFeatures* sonar);
  void DrawPanels(const client::RobotSnapshot& robot, const fusion::ArFeatures& features,
                  const fusion::SonarFeatures& sonar,
                  const std::optional<client::DecodedStereoPair>& pair, int fb_w, int fb_h);

  ConsoleOptions options_;
  Window* window_;
  client::StereoReceiver* video_;
  client::RobotState* robot_;
  CommandSender* commands_;
  const Clock* clock_;
  std::unique_ptr<ImGuiLayer> imgui_;
  render::StereoView stereo_view_;
  std::optional<ArBuilderCache> ar_builders_;  // from Init()
  ConsoleKeys keys_;
  DriveMapper mapper_;
  std::optional<DriveOutput> scripted_drive_;
  DriveOutput drive_;
  LeaseClient lease_;
  RearmGuide rearm_guide_;    // why driving stopped, and the re-arm of scripted drives
  RearmGuide::Advice rearm_;  // as of the last frame
  IntrinsicsAdopter intrinsics_;

  // Each eye's image and display models (eye_geometry.h); the image models are shared with the
  // edge worker (its ray cache) until the geometry changes.
  render::StereoGeometry geometry_;  // both eyes, rebuilt when an input changes
  ImageScale image_scale_;  // the decoded images against the calibration; geometry_ uses it
  std::unique_ptr<ConsoleVision> vision_;  // from Init()
  ConsoleSelfCalibration selfcal_;         // proposals from the shown edge results
  std::optional<PairCapture> capture_;

  EdgeViewPanel edge_view_;
  bool show_edge_view_ = false;
  bool show_help_ = false;
  std::string status_line_;
  FrameSchedule schedule_;  // which frames are drawn, and the trace's warm-up
  uint64_t rendered_pairs_ = 0;
  cv::Mat last_frame_;
  double frame_time_ms_ = 0;
  ShownPairStats shown_;
  LatencyTrace latency_;
  FrameParts frame_parts_;  // `drawn` by part, for frames that showed a new pair
  PairTracer tracer_;       // when the render loop first took each recent pair
  bool show_latency_ = false;
  size_t sonar_echoes_ = 0;
  size_t sonar_unseen_ = 0;
  fusion::MovedScan moved_;  // the last scan moved to its image's time (reused)
  MotionOverlayStatus motion_;
};

}  // namespace mostar::ui
