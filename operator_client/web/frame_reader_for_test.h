// A reader of EncodeFrame's layout for the tests (the page has its own, in app.js). Test-only.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "operator_client/web/web_messages.h"

namespace mostar::web::testing {

struct ReadFrame {
  uint32_t sequence = 0;
  int width_px = 0, height_px = 0;
  double stamp_s = 0, scan_stamp_s = 0;
  std::vector<PixelVertex> triangles, lines, points;
  std::vector<MapPoint> map;
  std::vector<PixelVertex> sonar_triangles, sonar_lines;
  std::vector<MapPoint> sonar_map_triangles, sonar_map_lines;
  int sonar_echoes = 0, sonar_unseen = 0;
  uint32_t possible_obstacles = 0, flags = 0;
  std::string labels_json, left_jpeg, right_jpeg;
  float point_size_px = 0;
};

inline uint32_t U32(const std::string& b, size_t o) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<uint8_t>(b[o + i]);
  return v;
}
inline float F32(const std::string& b, size_t o) {
  const uint32_t bits = U32(b, o);
  float v;
  std::memcpy(&v, &bits, 4);
  return v;
}
inline double F64(const std::string& b, size_t o) {
  const uint64_t bits = U32(b, o) | (static_cast<uint64_t>(U32(b, o + 4)) << 32);
  double v;
  std::memcpy(&v, &bits, 8);
  return v;
}
inline size_t Pad4(size_t n) { return (n + 3) & ~size_t{3}; }

// False when the bytes do not hold a complete frame. Overwrites every field of `f`.
inline bool Read(const std::string& b, ReadFrame* f) {
  *f = ReadFrame();
  if (b.size() < kFrameHeaderBytes || b.compare(0, 4, "MWF2") != 0) return false;
  f->sequence = U32(b, 8);
  f->width_px = static_cast<int>(U32(b, 12) & 0xffff);
  f->height_px = static_cast<int>(U32(b, 12) >> 16);
  f->stamp_s = F64(b, 16);
  f->scan_stamp_s = F64(b, 24);
  f->point_size_px = F32(b, 60);
  f->sonar_echoes = static_cast<int>(U32(b, 80) & 0xffff);
  f->sonar_unseen = static_cast<int>(U32(b, 80) >> 16);
  f->possible_obstacles = U32(b, 84);
  f->flags = U32(b, 88);
  size_t o = U32(b, 4);
  auto vertices = [&](uint32_t n, std::vector<PixelVertex>* out) {
    if (o + 12 * size_t{n} > b.size()) return false;
    out->resize(n);
    for (uint32_t i = 0; i < n; ++i) {
      (*out)[i].u_px = F32(b, o + 8 * i);
      (*out)[i].v_px = F32(b, o + 8 * i + 4);
      std::memcpy((*out)[i].rgba, b.data() + o + 8 * n + 4 * i, 4);
    }
    o += 12 * size_t{n};
    return true;
  };
  auto map_vertices = [&](uint32_t n, std::vector<MapPoint>* out) {
    std::vector<PixelVertex> v;
    if (!vertices(n, &v)) return false;
    for (const PixelVertex& p : v) {
      MapPoint m;
      m.x_m = p.u_px;
      m.y_m = p.v_px;
      std::memcpy(m.rgba, p.rgba, 4);
      out->push_back(m);
    }
    return true;
  };
  if (!vertices(U32(b, 32), &f->triangles) || !vertices(U32(b, 36), &f->lines) ||
      !vertices(U32(b, 40), &f->points) || !map_vertices(U32(b, 44), &f->map) ||
      !vertices(U32(b, 64), &f->sonar_triangles) || !vertices(U32(b, 68), &f->sonar_lines) ||
      !map_vertices(U32(b, 72), &f->sonar_map_triangles) ||
      !map_vertices(U32(b, 76), &f->sonar_map_lines)) {
    return false;
  }
  auto bytes = [&](uint32_t n, std::string* out) {
    if (o + n > b.size()) return false;
    *out = b.substr(o, n);
    o = Pad4(o + n);
    return true;
  };
  return bytes(U32(b, 48), &f->labels_json) && bytes(U32(b, 52), &f->left_jpeg) &&
         bytes(U32(b, 56), &f->right_jpeg) && o == b.size();
}

}  // namespace mostar::web::testing
