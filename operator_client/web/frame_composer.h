// One browser frame from one stereo pair: the scan nearest in time through the console's own
// AR feature builder (ArBuilderCache) and overlay assembly (AssembleOverlay), projected into the
// left camera image (ProjectOverlay), with the bird's-eye map points and the robot's JPEG bytes,
// encoded once for every browser (EncodeFrame). Pure: no DDS, no sockets; one thread at a time.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/math/camera_model.h"
#include "common/types/laser_scan.h"
#include "common/types/stereo_frame.h"
#include "operator_client/render/eye_geometry.h"
#include "operator_client/ui/ar_builder_cache.h"
#include "operator_client/ui/intrinsics_adoption.h"
#include "operator_client/vision/nep_classifier.h"
#include "operator_client/web/image_overlay.h"

namespace mostar::web {

struct ComposerOptions {
  math::LaserCameraCalibration calibration;  // the shared (thesis) or the left eye's calibration
  fusion::ArFeatureOptions ar;
  render::AlignmentModel alignment_model = render::AlignmentModel::kSharedModel;
  render::EyeAlignment left_alignment;
  render::EyeAlignment right_alignment;
  bool intrinsics_from_robot = true;  // adopt the left intrinsics the robot publishes

  bool IsValid(std::string* error) const;
};

struct ComposedFrame {
  std::shared_ptr<const std::string> left_only;  // EncodeFrame without the right JPEG
  std::shared_ptr<const std::string> both_eyes;  // with it (for the anaglyph); null unless asked
  size_t triangles = 0;                          // wall triangles in the overlay
  size_t unprojectable = 0;
};

class FrameComposer {
 public:
  // `options` must be valid (asserted).
  explicit FrameComposer(const ComposerOptions& options);

  // The robot's left intrinsics (when adopted): later frames use them. A refusal is said in
  // `message` (empty otherwise).
  void SetRobotIntrinsics(const std::optional<CameraIntrinsicsInfo>& left, std::string* message);

  // `scan`: the scan nearest to the pair's stamp (none: image and circles only); `obstacles`:
  // possible obstacles from edge processing (magenta dots). `sequence` numbers the frame.
  ComposedFrame Compose(const CompressedStereoPair& pair, const std::optional<LaserScan>& scan,
                        const std::vector<vision::PossibleObstacle>& obstacles, uint32_t sequence,
                        bool both_eyes);

  // The left eye's image model in force.
  const math::CameraModel& left_image_model() const { return geometry_.eye(0).image; }

 private:
  void RefreshGeometry();

  ComposerOptions options_;
  ui::ArBuilderCache builders_;
  ui::IntrinsicsAdopter intrinsics_;
  render::StereoGeometry geometry_;
};

}  // namespace mostar::web
