// Nearest edges discovery, NED (thesis 8.2).
//
// For each laser beam, the "virtual ray" is the floor half-line from the robot base (the floor
// point under the laser origin) along the beam's azimuth, through the floor projection of the
// laser point and beyond, up to NearestEdgeOptions::max_range_m. It is projected into the edge
// image with the camera model (distortion included: the 3D ray is sampled finely and each sample
// projected, so the curved image of the line is followed) and walked from the robot outwards
// until the first edge pixel. That pixel's point on the virtual ray is the beam's nearest edge
// point (NEP): a floor point, usually the base of an obstacle.
//
// Frames: floor points are in the laser frame (x forward, y left, z up; the floor is
// z = -laser_height_m). Distances are measured on the floor from the robot base. Pixels follow
// common/math/camera_model.h (u right, v down, (0, 0) = centre of the top-left pixel).
//
// Pure functions: safe to call from any thread.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "common/math/camera_model.h"
#include "common/types/laser_scan.h"
#include "operator_client/vision/floor_stereo.h"

namespace mostar::vision {

struct NearestEdgeOptions {
  // Farthest floor distance from the robot base walked along each virtual ray, metres; > 0.
  // Beyond the laser point so that edges "further than the laser" are seen too (thesis 8.4).
  double max_range_m = 8.0;
  // Walking step along the image of the ray, pixels; in (0, 1]. Smaller is slower and never
  // skips a pixel of the (8-connected) edge curves Canny produces.
  double step_px = 0.5;
  // Also accept edge pixels up to this many pixels across the walking direction (0 = only the
  // pixels the ray passes through); in [0, 10].
  int lateral_tolerance_px = 0;
  // Rows at the bottom of the image that show the robot itself and are never searched; in
  // [0, image height).
  int bottom_margin_px = 0;
  // Base refinement, metres of floor distance beyond the first edge pixel; in [0, 1]. The first
  // edge along a ray is often the outer rim of an obstacle's contact shadow a few centimetres in
  // front of its base. Within this distance the NEP moves to the edge pixel with the strongest
  // gradient (Sobel, L1, on the stretched grey image). 0 = the thesis' first edge pixel alone.
  double base_search_m = 0.06;
  // Step test: an edge pixel counts only when the mean stretched grey of the ray pixels
  // [step_offset_px, 2 step_offset_px] beyond it differs from that of the same span before it
  // by at least min_step_grey levels. Thin lines on the floor (tile joints, drawings) have floor
  // on both sides and fail it; obstacle bases pass. An edge with no ray pixels before it (within
  // step_offset_px of the image border) cannot be told from a line and fails. Needs the grey
  // image. 0 = off (the thesis).
  int min_step_grey = 0;
  int step_offset_px = 3;  // in [1, 20]
  // Direction test, degrees; in [0, 85]. The edge through an edge pixel runs perpendicular to
  // the image gradient there (Sobel over the pixel's 3x3 neighbourhood, stretched grey image).
  // An obstacle's base runs across the rays. The silhouette of its vertical edges runs along
  // them (vertical lines and floor rays both meet near the image of the point under the camera),
  // and so do the sides of a box a ray passes beside. A NEP whose first edge pixel crosses the
  // ray's image less steeply than this angle is marked Nep::along_ray. An edge with no gradient
  // crosses. Needs the grey image. 0 = off (the thesis).
  double min_crossing_angle_deg = 30.0;
  // Start test, grey levels of the stretched image; in [0, 255]. The rays that enter the image
  // at its bottom start on the floor near the robot, all of the same look. A ray whose first
  // pixels there differ from the median of those rays by more than this starts on an object
  // whose base is below the image: its first edge may be that object's top, far beyond its
  // base, and its NEP is marked Nep::starts_on_object. Needs the grey image and at least
  // kMinStartRays such rays. 0 = off (the thesis).
  int start_grey_deviation = 80;
  static constexpr int kMinStartRays = 9;
  // Floor test (ground-plane stereo, floor_stereo.h): an edge pixel whose region beyond it along
  // the ray is judged floor under the floor warp of the other eye lies on the floor (a tile
  // border, tape) and the walk goes on past it. Needs both eyes (FloorStereoImages).
  FloorStereoOptions floor_stereo;

  bool IsValid(std::string* error) const;
};

// A nearest edge point of one beam. When `found` is false the other fields are meaningless.
struct Nep {
  bool found = false;
  // Floor distance from the robot base along the beam's azimuth, metres.
  double distance_m = std::numeric_limits<double>::quiet_NaN();
  // The point on the floor, laser frame (z = -laser_height_m).
  Eigen::Vector3d floor_point_laser = Eigen::Vector3d::Zero();
  // The edge pixel (integer pixel centre) in the image it was found in; for a fused stereo NEP,
  // the fused point projected into the right image.
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  // Floor distance covered by one pixel along the ray's image at the NEP, metres: the
  // resolution of distance_m (grows roughly with the square of the distance).
  double metres_per_px = 0.0;
  // NESC's verdict (thesis 9.2): false when seen by one eye only or when the eyes disagree; such
  // a NEP is used only when it agrees with the laser. NED on one image (thesis 8) sets true.
  bool reliable = true;
  // The edge runs along the ray (NearestEdgeOptions::min_crossing_angle_deg): the silhouette of
  // something the ray passes beside or behind, not a base on this beam. It may agree with the
  // laser or be further, but never makes a possible-obstacle dot. NESC: set when either eye's is.
  bool along_ray = false;
  // The ray starts on an object at the image bottom (NearestEdgeOptions::start_grey_deviation):
  // the NEP may be that object's top edge, not a base. It may agree with the laser or be
  // further, but never makes a possible-obstacle dot. NESC: set when either eye's is.
  bool starts_on_object = false;
};

// NED over one image: neps[i] belongs to beam i of the scan.
struct NedResult {
  std::vector<Nep> neps;
  int visible_rays = 0;  // beams whose virtual ray has a visible part in the image
  int found = 0;         // beams with a NEP
  int floor_edges = 0;  // edge pixels the floor test walked past (NearestEdgeOptions::floor_stereo)
};

// Runs NED for every beam of `scan` (any range value, NaN and Inf included: the virtual ray only
// needs the beam's azimuth). `edges` is the CV_8UC1 edge image of the camera `camera` describes
// (non-zero = edge); its size must match the camera's. On a size/type mismatch or invalid
// options, returns false with `error` set and `out` holds one not-found NEP per beam.
// `grey`: as in FindNearestEdgeOnPixels (empty = no base refinement).
bool FindNearestEdges(const cv::Mat& edges, const math::CameraModel& camera, const LaserScan& scan,
                      const NearestEdgeOptions& options, NedResult* out, std::string* error,
                      const cv::Mat& grey = cv::Mat());

// The NEP along one virtual ray: the floor half-line from the robot base with azimuth
// `azimuth_rad` (laser frame, counter-clockwise, 0 = ahead). Preconditions as above (checked by
// FindNearestEdges; this one asserts).
Nep FindNearestEdgeOnRay(const cv::Mat& edges, const math::CameraModel& camera, double azimuth_rad,
                         const NearestEdgeOptions& options, bool* ray_visible = nullptr);

// The pixels one virtual ray crosses, in walking order, computed once per camera and beam
// (they depend on the calibration and the scan geometry only, not on the image).
struct RayPixels {
  struct Pixel {
    int16_t col = 0;
    int16_t row = 0;
    int16_t previous_col = -1;  // the pixel walked before (for diagonal steps), -1 = none
    int16_t previous_row = -1;
    bool walking_vertically = true;  // the image of the ray is steeper than 45 degrees here
    float direction_u = 0.f;         // unit direction of the ray's image here, walking outwards
    float direction_v = -1.f;
    float enter_t_m = 0.f;      // distance along the ray where the walk enters the pixel
    float centre_t_m = 0.f;     // middle of the ray's crossing of the pixel
    float metres_per_px = 0.f;  // floor distance per pixel of the ray's image here
  };
  bool visible = false;
  double azimuth_rad = 0.0;
  std::vector<Pixel> pixels;
};

// Walks the image of one virtual ray (see FindNearestEdgeOnRay) and records its pixels.
RayPixels TraceRayPixels(const math::CameraModel& camera, double azimuth_rad,
                         const NearestEdgeOptions& options);

// The NEP along precomputed ray pixels; `edges` as in FindNearestEdges. `grey` is the stretched
// grey image the edges came from (CV_8UC1, same size), for the base refinement; empty = none.
// `floor`: this eye's images for the floor test (null or options.floor_stereo off = no test);
// `floor_edges` counts the edge pixels it walked past.
Nep FindNearestEdgeOnPixels(const cv::Mat& edges, const RayPixels& ray,
                            const NearestEdgeOptions& options, double laser_height_m,
                            const cv::Mat& grey = cv::Mat(),
                            const FloorStereoImages* floor = nullptr, int* floor_edges = nullptr);

// NED with the ray pixels of every beam cached: they are rebuilt only when the camera model
// (compared by pointer: hand over the same shared_ptr while the calibration is unchanged), the
// options or the scan's beam geometry change. Not thread-safe: one finder per thread and eye.
class NearestEdgeFinder {
 public:
  explicit NearestEdgeFinder(const NearestEdgeOptions& options) : options_(options) {}

  // As FindNearestEdges; `floor` as in FindNearestEdgeOnPixels.
  bool Find(const cv::Mat& edges, const std::shared_ptr<const math::CameraModel>& camera,
            const LaserScan& scan, NedResult* out, std::string* error,
            const cv::Mat& grey = cv::Mat(), const FloorStereoImages* floor = nullptr);

  // Builds (or keeps) the ray pixel cache for this camera and scan geometry; false with `error`
  // on invalid options or scan angles, or a missing camera.
  bool Prepare(const std::shared_ptr<const math::CameraModel>& camera, const LaserScan& scan,
               std::string* error);
  // After Prepare: the highest image row any cached ray pixel (or its lateral and diagonal
  // neighbours) touches; the image height when no ray is visible. Rows above it are never read.
  int top_row() const { return top_row_; }

 private:
  NearestEdgeOptions options_;
  std::shared_ptr<const math::CameraModel> camera_;
  float angle_min_rad_ = 0.f;
  float angle_increment_rad_ = 0.f;
  std::vector<RayPixels> rays_;
  int top_row_ = 0;
};

// The direction test of NearestEdgeOptions::min_crossing_angle_deg at pixel (col, row) of the
// stretched grey image `grey` (CV_8UC1), for a ray whose image runs along `ray_direction` there
// (any length > 0). True when the test is off, the gradient is zero, or the edge crosses the ray
// at least that steeply.
bool EdgeCrossesRay(const cv::Mat& grey, int col, int row, const Eigen::Vector2d& ray_direction,
                    double min_crossing_angle_deg);

// Floor point (laser frame) at `distance_m` from the robot base along `azimuth_rad`.
Eigen::Vector3d FloorPointLaser(double azimuth_rad, double distance_m, double laser_height_m);

}  // namespace mostar::vision
