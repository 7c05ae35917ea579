// CPU stereo renderer of the World: what the MORDUC's two parallel, downward-tilted cameras see.
//
// One ray per pixel (pixel centre), pinhole with optional radial distortion. Because the
// cameras are rigid on a robot that moves in the plane, each pixel's ray is fixed in the base
// frame: its azimuth bin, elevation, floor point, the distance to the floor or ceiling and the
// vignetting are computed once. Per frame, obstacles are crossed once per thin azimuth bin (a
// quarter of a pixel wide) and each pixel only resolves the heights of the few obstacles its
// bin crossed. Then: Lambert shading, floor occlusion at obstacle bases, distance fall-off,
// vignetting, per-eye gain, optical blur, Gaussian sensor noise and an optional artefact in one
// eye. Output images are BGR8.
//
// Render is const and thread-safe (noise and artefacts are derived from the config seed and
// the frame index, so a frame is reproducible); it shades bands of rows of both eyes on
// OpenCV's worker threads (cv::parallel_for_, no thread started per frame).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "common/types/odometry.h"
#include "common/types/stereo_frame.h"
#include "robot_server/sim/ground_truth.h"
#include "robot_server/sim/sim_config.pb.h"
#include "robot_server/sim/world.h"

namespace mostar::sim {

struct CameraParams {
  LaserCameraCalibration calibration;
  double left_gain = 1.0;
  double right_gain = 0.96;
  double noise_sigma = 2.0;    // grey levels
  double blur_sigma_px = 0.6;  // 0 = off
  bool vignetting = true;
  bool contact_shadows = true;  // see CameraConfig.contact_shadows
  uint64_t seed = 2;
  proto::ArtifactConfig artifact;

  static CameraParams FromProto(const proto::CameraConfig& config);
};

struct StereoImages {
  cv::Mat left;                 // BGR8
  cv::Mat right;                // BGR8
  ImageGroundTruth left_truth;  // filled when asked for
  ImageGroundTruth right_truth;
};

class StereoRenderer {
 public:
  // `world` must outlive the renderer. `laser_height_m`: laser above the floor (base frame).
  StereoRenderer(const World& world, const CameraParams& params, double laser_height_m);

  // Renders both eyes at world_from_base. `frame_index` selects the noise and artefacts.
  // With `with_truth`, labels and base rows are filled as well.
  void Render(const Pose2D& world_from_base, uint64_t frame_index, bool with_truth,
              StereoImages* out) const;
  // One eye, on the calling thread.
  cv::Mat RenderEye(Eye eye, const Pose2D& world_from_base, uint64_t frame_index,
                    ImageGroundTruth* truth) const;

  const CameraParams& params() const { return params_; }

 private:
  // What the ray of one pixel meets when no obstacle is in the way.
  enum class Backdrop : uint8_t { kFloor, kCeiling, kNothing };
  // Fixed per-pixel ray, in the robot base frame.
  struct PixelRay {
    int32_t bin = 0;         // azimuth bin
    float tan_el = 0.f;      // tangent of the elevation
    float h_backdrop_m = 0;  // horizontal distance to the floor or ceiling; +inf for nothing
    float floor_x_m = 0.f;   // floor point (kFloor only)
    float floor_y_m = 0.f;
    float gain = 0.f;           // eye gain x vignetting
    float gain_backdrop = 0.f;  // gain with the distance fall-off of the floor or ceiling
    Backdrop backdrop = Backdrop::kNothing;
  };
  struct EyeTables {
    double cam_x_m = 0, cam_y_m = 0, cam_z_m = 0;  // camera centre, base frame
    double az_min_rad = 0, bin_width_rad = 0;
    int bin_count = 0;
    std::vector<PixelRay> rays;  // row-major
  };
  struct EyeFrame;  // per-frame state of one eye (stereo_renderer.cc)

  void BuildTables(Eye eye, EyeTables* tables) const;
  void PrepareEye(Eye eye, const Pose2D& world_from_base, EyeFrame* frame) const;
  // Shades rows [row_begin, row_end) into `image` (and `labels` when not null).
  void ShadeRows(const EyeFrame& frame, int row_begin, int row_end, cv::Mat* image,
                 cv::Mat* labels) const;
  // Blur, noise, artefact and base rows of a shaded image.
  void FinishEye(Eye eye, uint64_t frame_index, cv::Mat* image, ImageGroundTruth* truth) const;

  const World& world_;
  CameraParams params_;
  double laser_height_m_;
  EyeTables eyes_[2];
  Rgb ceiling_colour_;  // lit, before the fall-off
  Rgb void_colour_;
  // Gaussian noise field (sigma = noise_sigma), 1.5 times the image, as its positive and
  // negative parts: image + n saturated = (image + max(n, 0)) - max(-n, 0), both saturated.
  cv::Mat noise_up_;    // CV_8UC3
  cv::Mat noise_down_;  // CV_8UC3
};

}  // namespace mostar::sim
