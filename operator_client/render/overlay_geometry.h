// What the eye renderer draws over the image: plain vertex data, no GL.
#pragma once

#include "operator_client/fusion/vertex_array.h"

namespace mostar::render {

// The AR geometry of one frame (laser frame, metres).
struct OverlayGeometry {
  fusion::VertexArray triangles;  // GL_TRIANGLES: virtual walls
  fusion::VertexArray lines;      // GL_LINES: rays, circles, vertical lines, predicted path
  fusion::VertexArray points;     // GL_POINTS: laser points, NEP dots
  float point_size_px = 5.f;
};

}  // namespace mostar::render
