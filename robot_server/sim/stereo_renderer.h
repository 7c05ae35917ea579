// CPU stereo renderer of the World: what the MORDUC's two parallel, downward-tilted cameras see.
//
// One ray per pixel (pixel centre), pinhole with optional radial distortion. Because the
// cameras are rigid on a robot that moves in the plane, each pixel's ray is fixed in the base
// frame: its azimuth, elevation and floor point are computed once. Per frame, obstacles are
// crossed once per thin azimuth bin (a quarter of a pixel wide) and each pixel only resolves
// the heights of the few obstacles its bin crossed. Then: Lambert shading, floor occlusion at
// obstacle bases, distance fall-off, vignetting, per-eye gain, optical blur, Gaussian sensor
// noise and an optional artefact in one eye. Output images are BGR8.
//
// Render is const and thread-safe (noise and artefacts are derived from the config seed and
// the frame index, so a frame is reproducible); the two eyes are rendered on two threads.
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
  // One eye (no threads).
  cv::Mat RenderEye(Eye eye, const Pose2D& world_from_base, uint64_t frame_index,
                    ImageGroundTruth* truth) const;

  const CameraParams& params() const { return params_; }

 private:
  // Fixed per-eye tables, in the robot base frame.
  struct EyeTables {
    double cam_x_m = 0, cam_y_m = 0, cam_z_m = 0;  // camera centre, base frame
    double az_min_rad = 0, bin_width_rad = 0;
    int bin_count = 0;
    std::vector<int32_t> bin;      // per pixel
    std::vector<float> tan_el;     // per pixel
    std::vector<float> h_floor_m;  // per pixel; +inf when the ray does not go down
    std::vector<float> floor_x_m;  // per pixel floor point, base frame
    std::vector<float> floor_y_m;
    std::vector<float> vignette;  // per pixel gain
  };
  void BuildTables(Eye eye, EyeTables* tables) const;

  const World& world_;
  CameraParams params_;
  double laser_height_m_;
  EyeTables eyes_[2];
  cv::Mat noise_;  // CV_16SC3 Gaussian noise field, sigma = noise_sigma
};

}  // namespace mostar::sim
