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

// False when the bytes do not hold a complete frame.
inline bool Read(const std::string& b, ReadFrame* f) {
  if (b.size() < kFrameHeaderBytes || b.compare(0, 4, "MWF1") != 0) return false;
  f->sequence = U32(b, 8);
  f->width_px = static_cast<int>(U32(b, 12) & 0xffff);
  f->height_px = static_cast<int>(U32(b, 12) >> 16);
  f->stamp_s = F64(b, 16);
  f->scan_stamp_s = F64(b, 24);
  f->point_size_px = F32(b, 60);
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
  std::vector<PixelVertex> map;
  if (!vertices(U32(b, 32), &f->triangles) || !vertices(U32(b, 36), &f->lines) ||
      !vertices(U32(b, 40), &f->points) || !vertices(U32(b, 44), &map)) {
    return false;
  }
  for (const PixelVertex& v : map) {
    MapPoint m;
    m.x_m = v.u_px;
    m.y_m = v.v_px;
    std::memcpy(m.rgba, v.rgba, 4);
    f->map.push_back(m);
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
