// Laser-camera model: where a point of the laser frame appears in a camera image.
//
// Conventions (stated once for all of common/math):
// - Laser frame: ROS REP-103, x forward, y left, z up; metres. The scan plane is z = 0.
// - Robot base frame: origin on the floor under the laser, x forward, y left, z up. In the laser
//   frame the floor is the plane z = -laser_height_m.
// - Camera frame: OpenCV, x right, y down, z forward along the optical axis; metres.
// - Pixels: OpenCV, u right, v down, (0, 0) is the centre of the top-left pixel; the image covers
//   [-0.5, width - 0.5] x [-0.5, height - 0.5].
// - Transforms are named target_from_source: p_camera = camera_from_laser * p_laser.
// - Calibration parameters follow the thesis' laser-camera model, spelled in our frames:
//     camera_x_m: camera centre to the RIGHT of the laser origin (= -laser y);
//     camera_y_m: camera centre ABOVE the laser scan plane (= +laser z);
//     camera_z_m: camera centre AHEAD of the laser origin along the optical direction (= +laser x).
// - Rotation order (laser_from_camera): start from the level camera looking along laser +x, then
//     1. pan_rad  about the laser z axis, positive turns the camera to the left (counter-clockwise
//        seen from above, like beam angles);
//     2. tilt_rad about the (panned) camera x axis, positive looks DOWN towards the floor;
//     3. roll_rad about the (panned, tilted) optical axis, right-handed about camera +z: positive
//        turns the camera's x (right) axis towards its y (down) axis, i.e. the camera rolls
//        clockwise as seen from behind it and the scene appears rotated counter-clockwise.
//   laser_from_camera.rotation() = Rz(pan) * R_level * Rx(-tilt) * Rz(roll), where R_level maps
//   camera axes to laser axes for the level camera (x_cam = -y_laser, y_cam = -z_laser,
//   z_cam = +x_laser) and Rx, Rz are right-handed rotations in the camera frame.
// - Lens distortion: OpenCV's 5-parameter model (k1, k2, p1, p2, k3) applied to the normalised
//   image coordinates (x/z, y/z) before the intrinsics; the same as cv::projectPoints.
//
// All functions are pure and the classes immutable: safe to use from any thread.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "common/types/eye.h"

namespace mostar::math {

// Which camera of the stereo rig a CameraModel describes: one eye (common/types/eye.h), or the
// rig's centre (kMonoCamera), which ignores the per-eye offsets.
using Eye = ::mostar::Eye;
using RigCamera = std::optional<Eye>;
inline constexpr RigCamera kMonoCamera = std::nullopt;
// "mono", "left" or "right".
const char* RigCameraName(RigCamera camera);

// OpenCV distortion coefficients (dimensionless). All zero = ideal pinhole (the thesis' model).
struct DistortionCoefficients {
  double k1 = 0.0;
  double k2 = 0.0;
  double p1 = 0.0;
  double p2 = 0.0;
  double k3 = 0.0;

  bool IsZero() const { return k1 == 0.0 && k2 == 0.0 && p1 == 0.0 && p2 == 0.0 && k3 == 0.0; }
};

// The thesis' laser-camera parameters (focal length, camera x/y/z, tilt, optional pan, per-eye x
// offset) extended with the usual intrinsics when they are known (principal point, separate
// vertical focal length, roll, distortion). Defaults describe a MORDUC-like rig: cameras 0.95 m
// above the floor, tilted 12 degrees down, 0.12 m baseline, 640x480 images, focal 525 px.
struct LaserCameraCalibration {
  // Intrinsics.
  int image_width_px = 640;   // > 0
  int image_height_px = 480;  // > 0
  double focal_px = 525.0;    // horizontal focal length fx, pixels; > 0
  // Vertical focal length fy, pixels; unset = focal_px (square pixels, the thesis' model).
  std::optional<double> focal_y_px;
  // Principal point, pixels; unset = image centre ((width - 1) / 2, (height - 1) / 2).
  std::optional<double> principal_x_px;
  std::optional<double> principal_y_px;
  DistortionCoefficients distortion;

  // Extrinsics: camera centre relative to the laser origin (see the conventions above), metres.
  double camera_x_m = 0.0;    // to the right of the laser; the rig centre for stereo
  double camera_y_m = 0.55;   // above the scan plane
  double camera_z_m = -0.10;  // ahead of the laser (negative = behind it)
  double tilt_rad = 0.20944;  // positive = looking down; in (-pi/2, pi/2)
  double pan_rad = 0.0;       // positive = looking left; in (-pi/2, pi/2)
  double roll_rad = 0.0;      // see the conventions above; in (-pi/4, pi/4)
  // Added to camera_x_m for each eye (thesis 9.1: only the cameras' x differ). Their difference
  // is the stereo baseline. Left must not be to the right of right.
  double left_eye_x_offset_m = -0.06;
  double right_eye_x_offset_m = 0.06;

  // Height of the laser scan plane above the floor, metres; > 0. Floor: laser z = -laser_height_m.
  double laser_height_m = 0.40;

  double fx() const { return focal_px; }
  double fy() const { return focal_y_px.value_or(focal_px); }
  double cx() const { return principal_x_px.value_or(0.5 * (image_width_px - 1)); }
  double cy() const { return principal_y_px.value_or(0.5 * (image_height_px - 1)); }
  double baseline_m() const { return right_eye_x_offset_m - left_eye_x_offset_m; }
  // camera_x_m plus the eye's offset.
  double EyeX(RigCamera camera) const;

  // True when every parameter is finite and inside its documented range; otherwise false and
  // `error` (if not null) names the first violated constraint, e.g. "focal_px must be > 0 (got
  // -3)".
  bool IsValid(std::string* error) const;
};

// The part of a 3D ray (or segment) that is visible in the image, as computed by
// CameraModel::ProjectRayToImage. The ray is origin + t * direction with unit direction.
struct ImageRay {
  double start_t_m = 0.0;  // distance along the ray of the first visible point
  double end_t_m = 0.0;    // distance along the ray of the last visible point, >= start_t_m
  Eigen::Vector3d start_laser = Eigen::Vector3d::Zero();  // origin + start_t_m * direction
  Eigen::Vector3d end_laser = Eigen::Vector3d::Zero();
  Eigen::Vector2d start_px = Eigen::Vector2d::Zero();  // Project(start_laser), inside the image
  Eigen::Vector2d end_px = Eigen::Vector2d::Zero();    // Project(end_laser), inside the image
};

// Rectangle of the camera image shown by an OpenGL viewport, in pixel coordinates: left_px and
// top_px are the u and v of the region's left and top EDGES (the full image is
// {-0.5, -0.5, width, height}). A smaller or shifted region crops/offsets stereo images.
struct ImageRegion {
  double left_px = -0.5;
  double top_px = -0.5;
  double width_px = 0.0;   // > 0
  double height_px = 0.0;  // > 0
};

// OpenGL matrices (column-major, as glUniformMatrix4fv(..., GL_FALSE, m.data()) expects) for
// drawing laser-frame geometry over the camera image: clip = projection * view * p_laser.
// view = gl_camera_from_laser (OpenGL eye frame: x right, y up, looking along -z).
struct GlMatrices {
  Eigen::Matrix4f projection = Eigen::Matrix4f::Identity();
  Eigen::Matrix4f view = Eigen::Matrix4f::Identity();
};

// A pinhole + distortion camera placed by a LaserCameraCalibration for one eye. Immutable.
class CameraModel {
 public:
  // Points closer than this to the camera plane (camera z, metres) are "behind" the camera.
  static constexpr double kMinDepthM = 1e-3;

  // `calibration` must satisfy IsValid() (checked with an assertion); use Create() for
  // calibrations that come from outside (files, the UI).
  CameraModel(const LaserCameraCalibration& calibration, RigCamera camera);
  // Returns nullopt and sets `error` when the calibration is invalid.
  static std::optional<CameraModel> Create(const LaserCameraCalibration& calibration,
                                           RigCamera camera, std::string* error);

  const LaserCameraCalibration& calibration() const { return calibration_; }
  RigCamera eye() const { return eye_; }
  int width_px() const { return calibration_.image_width_px; }
  int height_px() const { return calibration_.image_height_px; }
  const Eigen::Isometry3d& camera_from_laser() const { return camera_from_laser_; }
  const Eigen::Isometry3d& laser_from_camera() const { return laser_from_camera_; }
  // Camera centre in the laser frame, metres.
  Eigen::Vector3d CameraCenterInLaser() const { return laser_from_camera_.translation(); }
  // Intrinsic matrix K (pixels), as OpenCV's cameraMatrix.
  Eigen::Matrix3d IntrinsicMatrix() const;

  // Pixel of a laser-frame point, with distortion. nullopt when the point is behind the camera
  // (camera z < kMinDepthM), not finite, or so far off-axis that the distortion polynomial
  // folds back (there the lens model is not one-to-one; such points are never in the image).
  // The pixel may lie outside the image: check with IsInImage().
  std::optional<Eigen::Vector2d> Project(const Eigen::Vector3d& point_laser) const;
  // Same for a camera-frame point.
  std::optional<Eigen::Vector2d> ProjectCameraPoint(const Eigen::Vector3d& point_camera) const;
  // Pinhole projection without distortion (what the GL matrices draw).
  std::optional<Eigen::Vector2d> ProjectUndistorted(const Eigen::Vector3d& point_laser) const;

  // True when `pixel` lies in [-0.5, width - 0.5] x [-0.5, height - 0.5].
  bool IsInImage(const Eigen::Vector2d& pixel) const;

  // Unit direction (laser frame) of the viewing ray through `pixel`, distortion removed. The ray
  // starts at CameraCenterInLaser().
  Eigen::Vector3d PixelRayInLaser(const Eigen::Vector2d& pixel) const;
  // Laser-frame point where the viewing ray through `pixel` meets the horizontal plane
  // z_laser = plane_z_m; nullopt when the ray does not go towards the plane (e.g. a pixel above
  // the horizon for the floor) or meets it farther than max_range_m from the camera.
  std::optional<Eigen::Vector3d> UnprojectToHeight(const Eigen::Vector2d& pixel, double plane_z_m,
                                                   double max_range_m = 1e3) const;
  // UnprojectToHeight(pixel, -laser_height_m): the floor point seen at `pixel`.
  std::optional<Eigen::Vector3d> UnprojectToFloor(const Eigen::Vector2d& pixel,
                                                  double max_range_m = 1e3) const;

  // Visible part of the 3D segment origin + t * direction, t in [0, length_m] (direction need
  // not be unit; it is normalised): clipped to points in front of the camera (camera z >=
  // kMinDepthM) whose projection is inside the image (assumed one interval). nullopt when
  // nothing is visible. Used to find the image segment of a virtual ray (thesis 8.2): scan
  // pixels between start_px and end_px, or sample t and Project() (with distortion the image of
  // a line is slightly curved). The ends are exact up to rounding, and both project inside.
  std::optional<ImageRay> ProjectRayToImage(const Eigen::Vector3d& origin_laser,
                                            const Eigen::Vector3d& direction_laser,
                                            double length_m) const;

  // Normalised image coordinates (x/z, y/z) <-> distorted normalised coordinates.
  Eigen::Vector2d Distort(const Eigen::Vector2d& undistorted) const;
  // Inverse of Distort(), iterative (Newton, to ~1e-12). Exact identity without distortion.
  Eigen::Vector2d Undistort(const Eigen::Vector2d& distorted) const;

  // OpenGL matrices drawing exactly what ProjectUndistorted() computes, for a viewport showing
  // `region` of the camera image (default: the whole image). near_m/far_m: clip distances along
  // the optical axis, 0 < near_m < far_m.
  GlMatrices OpenGlMatrices(double near_m, double far_m) const;
  GlMatrices OpenGlMatrices(double near_m, double far_m, const ImageRegion& region) const;
  // The whole image as an ImageRegion.
  ImageRegion FullImage() const;

 private:
  bool InsideUndistortedBounds(const Eigen::Vector3d& point_camera) const;

  LaserCameraCalibration calibration_;
  RigCamera eye_;
  Eigen::Isometry3d camera_from_laser_;
  Eigen::Isometry3d laser_from_camera_;
  // Largest squared normalised radius where the radial distortion is still increasing.
  double max_radius2_;
  // Bounding box of the image in undistorted normalised coordinates (covers the whole image).
  Eigen::Vector2d undistorted_min_;
  Eigen::Vector2d undistorted_max_;
};

// Maps an OpenGL normalised-device coordinate (x, y in [-1, 1], y up) of a viewport showing
// `region` back to image pixels. For tests and picking.
Eigen::Vector2d NdcToPixel(const Eigen::Vector2d& ndc, const ImageRegion& region);

}  // namespace mostar::math
