#include "operator_client/web/image_overlay.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace mostar::web {
namespace {

// A vertex in the camera frame with its colour, for clipping.
struct CameraVertex {
  Eigen::Vector3d p;  // camera frame, metres
  Eigen::Vector4d rgba;
};

CameraVertex Vertex(const fusion::VertexArray& array, size_t i, const Eigen::Isometry3d& T) {
  const float* p = &array.positions[3 * i];
  const float* c = &array.colors[4 * i];
  return {T * Eigen::Vector3d(p[0], p[1], p[2]), Eigen::Vector4d(c[0], c[1], c[2], c[3])};
}

CameraVertex OnNearPlane(const CameraVertex& a, const CameraVertex& b) {
  const double t = (kNearM - a.p.z()) / (b.p.z() - a.p.z());
  return {a.p + t * (b.p - a.p), a.rgba + t * (b.rgba - a.rgba)};
}

// Sutherland-Hodgman against z >= kNearM for a convex polygon.
std::vector<CameraVertex> ClipPolygon(const std::vector<CameraVertex>& in) {
  std::vector<CameraVertex> out;
  for (size_t i = 0; i < in.size(); ++i) {
    const CameraVertex& a = in[i];
    const CameraVertex& b = in[(i + 1) % in.size()];
    const bool a_in = a.p.z() >= kNearM;
    const bool b_in = b.p.z() >= kNearM;
    if (a_in) out.push_back(a);
    if (a_in != b_in) out.push_back(OnNearPlane(a, b));
  }
  return out;
}

std::optional<PixelVertex> ToPixel(const CameraVertex& v, const math::CameraModel& model) {
  const std::optional<Eigen::Vector2d> px = model.ProjectCameraPoint(v.p);
  if (!px) return std::nullopt;
  PixelVertex out;
  out.u_px = static_cast<float>(px->x());
  out.v_px = static_cast<float>(px->y());
  ToRgba8({static_cast<float>(v.rgba[0]), static_cast<float>(v.rgba[1]),
           static_cast<float>(v.rgba[2]), static_cast<float>(v.rgba[3])},
          out.rgba);
  return out;
}

// Projects a clipped primitive; false (nothing appended) when a vertex is unprojectable or the
// primitive lies entirely beyond one side of the image.
bool Append(const std::vector<CameraVertex>& vertices, const math::CameraModel& model,
            std::vector<PixelVertex>* out) {
  std::vector<PixelVertex> px;
  px.reserve(vertices.size());
  for (const CameraVertex& v : vertices) {
    const std::optional<PixelVertex> p = ToPixel(v, model);
    if (!p) return false;
    px.push_back(*p);
  }
  const float w = static_cast<float>(model.width_px()) - 0.5f;
  const float h = static_cast<float>(model.height_px()) - 0.5f;
  auto all = [&px](auto outside) { return std::all_of(px.begin(), px.end(), outside); };
  if (all([](const PixelVertex& p) { return p.u_px < -0.5f; }) ||
      all([w](const PixelVertex& p) { return p.u_px > w; }) ||
      all([](const PixelVertex& p) { return p.v_px < -0.5f; }) ||
      all([h](const PixelVertex& p) { return p.v_px > h; })) {
    return true;  // off-screen: nothing to draw, nothing wrong
  }
  out->insert(out->end(), px.begin(), px.end());
  return true;
}

}  // namespace

void ToRgba8(const fusion::Rgba& color, uint8_t out[4]) {
  const float c[4] = {color.r, color.g, color.b, color.a};
  for (int i = 0; i < 4; ++i) {
    const float v = std::isfinite(c[i]) ? std::clamp(c[i], 0.f, 1.f) : 0.f;
    out[i] = static_cast<uint8_t>(std::lround(v * 255.f));
  }
}

ImageOverlay ProjectOverlay(const render::OverlayGeometry& overlay,
                            const std::vector<fusion::DistanceLabel>& labels,
                            const math::CameraModel& image_model) {
  ImageOverlay out;
  out.point_size_px = overlay.point_size_px;
  const Eigen::Isometry3d& camera_from_laser = image_model.camera_from_laser();

  const fusion::VertexArray& tri = overlay.triangles;
  for (size_t i = 0; i + 2 < tri.vertex_count(); i += 3) {
    const std::vector<CameraVertex> clipped =
        ClipPolygon({Vertex(tri, i, camera_from_laser), Vertex(tri, i + 1, camera_from_laser),
                     Vertex(tri, i + 2, camera_from_laser)});
    if (clipped.size() < 3) continue;  // behind the camera
    // A convex polygon of 3 or 4 vertices as a fan of triangles.
    std::vector<CameraVertex> fan;
    for (size_t k = 1; k + 1 < clipped.size(); ++k) {
      fan.insert(fan.end(), {clipped[0], clipped[k], clipped[k + 1]});
    }
    if (!Append(fan, image_model, &out.triangles)) ++out.unprojectable;
  }

  const fusion::VertexArray& lines = overlay.lines;
  for (size_t i = 0; i + 1 < lines.vertex_count(); i += 2) {
    CameraVertex a = Vertex(lines, i, camera_from_laser);
    CameraVertex b = Vertex(lines, i + 1, camera_from_laser);
    const bool a_in = a.p.z() >= kNearM;
    const bool b_in = b.p.z() >= kNearM;
    if (!a_in && !b_in) continue;
    if (!a_in) a = OnNearPlane(a, b);
    if (!b_in) b = OnNearPlane(a, b);
    if (!Append({a, b}, image_model, &out.lines)) ++out.unprojectable;
  }

  const fusion::VertexArray& points = overlay.points;
  for (size_t i = 0; i < points.vertex_count(); ++i) {
    const CameraVertex v = Vertex(points, i, camera_from_laser);
    if (v.p.z() < kNearM) continue;
    const std::optional<PixelVertex> p = ToPixel(v, image_model);
    if (!p) {
      ++out.unprojectable;
      continue;
    }
    if (image_model.IsInImage(Eigen::Vector2d(p->u_px, p->v_px))) out.points.push_back(*p);
  }

  for (const fusion::DistanceLabel& label : labels) {
    const Eigen::Vector3d anchor(label.anchor_x_m, label.anchor_y_m, label.anchor_z_m);
    const std::optional<Eigen::Vector2d> px = image_model.Project(anchor);
    if (!px || !image_model.IsInImage(*px)) continue;
    PixelLabel l;
    l.u_px = static_cast<float>(px->x());
    l.v_px = static_cast<float>(px->y());
    ToRgba8(label.color, l.rgba);
    l.text = label.text;
    out.labels.push_back(std::move(l));
  }
  return out;
}

}  // namespace mostar::web
