// One browser frame from one stereo pair: the scan nearest in time (or the NEP-corrected scan of
// the pair's edge result) through the console's own AR feature builder (ArBuilderCache) and
// overlay assembly (AssembleOverlay), with the edge result's possible obstacles and the sonar
// sectors (fusion::BuildSonarFeatures), projected into the left camera image (ProjectOverlay),
// with the bird's-eye map points and sonar fans and the robot's JPEG bytes, encoded once for
// every browser (EncodeFrame). Pure: no DDS, no sockets; one thread at a time.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/math/camera_model.h"
#include "common/types/laser_scan.h"
#include "common/types/sonar.h"
#include "common/types/stereo_frame.h"
#include "operator_client/fusion/sonar_features.h"
#include "operator_client/render/eye_geometry.h"
#include "operator_client/ui/ar_builder_cache.h"
#include "operator_client/ui/intrinsics_adoption.h"
#include "operator_client/ui/motion_overlay.h"
#include "operator_client/vision/vision_pipeline.h"
#include "operator_client/web/image_overlay.h"

namespace mostar::web {

struct ComposerOptions {
  math::LaserCameraCalibration calibration;  // the shared (thesis) or the left eye's calibration
  fusion::ArFeatureOptions ar;
  fusion::SonarFeatureOptions sonar;  // colours and floor from `ar` and the calibration
  render::AlignmentModel alignment_model = render::AlignmentModel::kSharedModel;
  render::EyeAlignment left_alignment;
  render::EyeAlignment right_alignment;
  bool intrinsics_from_robot = true;  // adopt the left intrinsics the robot publishes
  // As the console: each scan moved to its pair's capture time with the odometry, or drawn as
  // measured and faded when no odometry covers the gap (ui/motion_overlay.h).
  ui::MotionOverlayOptions motion;

  bool IsValid(std::string* error) const;
};

struct ComposedFrame {
  std::shared_ptr<const std::string> left_only;  // EncodeFrame without the right JPEG
  std::shared_ptr<const std::string> both_eyes;  // with it (for the anaglyph); null unless asked
  size_t triangles = 0;                          // wall triangles in the overlay
  size_t unprojectable = 0;
  size_t sonar_triangles = 0;  // sonar fan triangles in the image
  size_t possible_obstacles = 0;
  bool edges = false;              // the pair's edge result is in the overlay
  ui::MotionOverlayStatus motion;  // the scan moved to the pair's time, or faded
};

// What one frame is built from besides its pair.
struct FrameInputs {
  std::optional<LaserScan> scan;  // nearest to the pair's stamp; none: no walls, no map points
  // The pair's own edge result (null: none): its possible obstacles become magenta dots and,
  // when it holds one, its NEP-corrected scan replaces `scan`, drawn where the result's
  // placement puts it (not moved again). Ignored unless ok.
  std::shared_ptr<const vision::VisionResult> edges;
  // The belt's latest cycle when fresh (the caller judges the age); none: no sonar sectors.
  std::optional<SonarRanges> sonar;
  // Moves a scan's beams to the pair's capture time (client::RobotState::MoveScanToImageTime
  // with the options' compensation); null: the scan is drawn as measured.
  std::function<void(const LaserScan& scan, fusion::MovedScan* out)> move_to_pair_time;
};

class FrameComposer {
 public:
  // `options` must be valid (asserted).
  explicit FrameComposer(const ComposerOptions& options);

  // The robot's left intrinsics (when adopted): later frames use them. A refusal is said in
  // `message` (empty otherwise).
  void SetRobotIntrinsics(const std::optional<CameraIntrinsicsInfo>& left, std::string* message);

  // `sequence` numbers the frame.
  ComposedFrame Compose(const CompressedStereoPair& pair, const FrameInputs& inputs,
                        uint32_t sequence, bool both_eyes);

  // The potential-outlier labels of `scan` as the overlay's builder segments it (what edge
  // processing confirms or not), as the console hands them to its EdgeWorker.
  std::vector<bool> PotentialOutliers(const LaserScan& scan);

  // The left eye's image model in force.
  const math::CameraModel& left_image_model() const { return geometry_.eye(0).image; }
  // Both eyes' image models in force, shared with edge processing (new objects when the
  // geometry changes, never modified).
  const std::shared_ptr<const math::CameraModel>& left_model() const { return left_model_; }
  const std::shared_ptr<const math::CameraModel>& right_model() const { return right_model_; }

 private:
  void RefreshGeometry();

  ComposerOptions options_;
  ui::ArBuilderCache builders_;
  ui::IntrinsicsAdopter intrinsics_;
  render::StereoGeometry geometry_;
  std::shared_ptr<const math::CameraModel> left_model_;
  std::shared_ptr<const math::CameraModel> right_model_;
};

}  // namespace mostar::web
