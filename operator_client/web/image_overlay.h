// The console's AR overlay (render::OverlayGeometry, laser frame, metres) as the browser draws it:
// 2D vertices in pixels of the camera image the page shows, so the page needs no camera model.
// Pure: no DDS, no sockets.
//
// The page shows the left camera image as the robot sent it (not undistorted), so every vertex
// is placed with the eye's image model, lens distortion included (math::CameraModel::Project, the
// model NED and NESC use): vertices land exactly where their 3D point is in the picture; the
// straight segments between them ignore the slight curvature distortion gives a 3D line (the
// console draws on the undistorted image, where lines stay straight).
//
// Primitives are clipped in the camera frame against the plane z = kNearM (as the GL near plane
// clips them in the console): a triangle crossing it becomes one or two triangles, a line is
// shortened, a point behind it is dropped. A primitive with a vertex the lens model cannot
// project (far off-axis, where the distortion polynomial folds back) is dropped and counted.
// Primitives entirely beyond one side of the image are left out (not counted).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/math/camera_model.h"
#include "operator_client/fusion/ar_features.h"
#include "operator_client/render/overlay_geometry.h"

namespace mostar::web {

// A vertex in image pixels (OpenCV: u right, v down, (0, 0) the centre of the top-left pixel)
// with its colour as 8-bit RGBA (alpha 255 = opaque).
struct PixelVertex {
  float u_px = 0.f;
  float v_px = 0.f;
  uint8_t rgba[4] = {0, 0, 0, 255};
};

// A distance label at the projection of its anchor; only labels whose anchor is in the image.
struct PixelLabel {
  float u_px = 0.f;
  float v_px = 0.f;
  uint8_t rgba[4] = {0, 0, 0, 255};
  std::string text;
};

struct ImageOverlay {
  std::vector<PixelVertex> triangles;  // 3 vertices per triangle (walls)
  std::vector<PixelVertex> lines;      // 2 vertices per segment (rays, circles, path)
  std::vector<PixelVertex> points;     // laser points, NEP dots; only those in the image
  std::vector<PixelLabel> labels;
  float point_size_px = 5.f;
  size_t unprojectable = 0;  // primitives dropped because a vertex could not be projected
};

// Camera-frame depth of the clipping plane, metres (the console's GL near plane).
constexpr double kNearM = 0.05;

// Projects `overlay` and `labels` with `image_model` (the left eye's image model).
ImageOverlay ProjectOverlay(const render::OverlayGeometry& overlay,
                            const std::vector<fusion::DistanceLabel>& labels,
                            const math::CameraModel& image_model);

// 8-bit RGBA of a colour with components in [0, 1] (clamped).
void ToRgba8(const fusion::Rgba& color, uint8_t out[4]);

}  // namespace mostar::web
