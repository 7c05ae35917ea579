#include "operator_client/web/web_messages.h"

#include <cmath>
#include <cstdio>
#include <cstring>

#include "common/check/check.h"

namespace mostar::web {
namespace {

void PutU16(uint16_t v, std::string* out) {
  out->push_back(static_cast<char>(v & 0xff));
  out->push_back(static_cast<char>(v >> 8));
}
void PutU32(uint32_t v, std::string* out) {
  for (int i = 0; i < 4; ++i) out->push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void PutU64(uint64_t v, std::string* out) {
  for (int i = 0; i < 8; ++i) out->push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void PutF32(float v, std::string* out) {
  uint32_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  PutU32(bits, out);
}
void PutF64(double v, std::string* out) {
  uint64_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  PutU64(bits, out);
}
void Pad4(std::string* out) {
  while (out->size() % 4 != 0) out->push_back('\0');
}
uint32_t Count(size_t n) {
  MOSTAR_CHECK(n <= UINT32_MAX) << n;
  return static_cast<uint32_t>(n);
}

void PutVertices(const std::vector<PixelVertex>& v, std::string* out) {
  for (const PixelVertex& p : v) {
    PutF32(p.u_px, out);
    PutF32(p.v_px, out);
  }
  for (const PixelVertex& p : v) out->append(reinterpret_cast<const char*>(p.rgba), 4);
}

void PutMapVertices(const std::vector<MapPoint>& v, std::string* out) {
  for (const MapPoint& p : v) {
    PutF32(p.x_m, out);
    PutF32(p.y_m, out);
  }
  for (const MapPoint& p : v) out->append(reinterpret_cast<const char*>(p.rgba), 4);
}

std::string Hex(const uint8_t rgba[4]) {
  char buffer[8];
  std::snprintf(buffer, sizeof buffer, "#%02x%02x%02x", rgba[0], rgba[1], rgba[2]);
  return buffer;
}

std::string Number(double v) {
  if (!std::isfinite(v)) return "-1";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f", v);
  return buffer;
}

std::string LabelsJson(const std::vector<PixelLabel>& labels) {
  std::string json = "[";
  for (size_t i = 0; i < labels.size(); ++i) {
    const PixelLabel& l = labels[i];
    if (i > 0) json += ",";
    json += "{\"u\":" + Number(l.u_px) + ",\"v\":" + Number(l.v_px) + ",\"c\":\"" + Hex(l.rgba) +
            "\",\"t\":" + JsonString(l.text) + "}";
  }
  return json + "]";
}

// Length of the valid UTF-8 sequence starting at s[i], 0 when invalid.
size_t Utf8Length(const std::string& s, size_t i) {
  const auto b = [&s](size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = b(i);
  size_t n = 0;
  if (c < 0x80) return 1;
  if (c >= 0xc2 && c <= 0xdf)
    n = 2;
  else if (c >= 0xe0 && c <= 0xef)
    n = 3;
  else if (c >= 0xf0 && c <= 0xf4)
    n = 4;
  else
    return 0;
  if (i + n > s.size()) return 0;
  for (size_t k = 1; k < n; ++k) {
    if ((b(i + k) & 0xc0) != 0x80) return 0;
  }
  if (n == 3 && c == 0xe0 && b(i + 1) < 0xa0) return 0;   // overlong
  if (n == 3 && c == 0xed && b(i + 1) >= 0xa0) return 0;  // surrogates
  if (n == 4 && c == 0xf0 && b(i + 1) < 0x90) return 0;   // overlong
  if (n == 4 && c == 0xf4 && b(i + 1) >= 0x90) return 0;  // beyond U+10FFFF
  return n;
}

}  // namespace

std::vector<MapPoint> MapPoints(const fusion::ArFeatures& features) {
  std::vector<MapPoint> out;
  out.reserve(features.points.size());
  for (const fusion::ScanPointLabel& p : features.points) {
    if (!p.valid) continue;
    MapPoint m;
    m.x_m = p.x_m;
    m.y_m = p.y_m;
    ToRgba8(p.color, m.rgba);
    out.push_back(m);
  }
  return out;
}

std::vector<MapPoint> MapVertices(const fusion::VertexArray& array) {
  std::vector<MapPoint> out(array.vertex_count());
  for (size_t i = 0; i < out.size(); ++i) {
    out[i].x_m = array.positions[3 * i];
    out[i].y_m = array.positions[3 * i + 1];
    const float* c = &array.colors[4 * i];
    ToRgba8({c[0], c[1], c[2], c[3]}, out[i].rgba);
  }
  return out;
}

std::string EncodeFrame(const FrameContent& frame) {
  MOSTAR_CHECK(frame.left_jpeg != nullptr);
  MOSTAR_CHECK(frame.width_px >= 0 && frame.width_px <= 65535 && frame.height_px >= 0 &&
               frame.height_px <= 65535)
      << frame.width_px << "x" << frame.height_px;
  static const ImageOverlay kNoOverlay;
  static const std::vector<MapPoint> kNoMap;
  static const std::vector<uint8_t> kNoImage;
  const ImageOverlay& overlay = frame.overlay ? *frame.overlay : kNoOverlay;
  const std::vector<MapPoint>& map = frame.map ? *frame.map : kNoMap;
  const ImageOverlay& sonar = frame.sonar ? *frame.sonar : kNoOverlay;
  const std::vector<MapPoint>& sonar_map_triangles =
      frame.sonar_map_triangles ? *frame.sonar_map_triangles : kNoMap;
  const std::vector<MapPoint>& sonar_map_lines =
      frame.sonar_map_lines ? *frame.sonar_map_lines : kNoMap;
  MOSTAR_CHECK(frame.sonar_echoes >= 0 && frame.sonar_echoes <= 65535 && frame.sonar_unseen >= 0 &&
               frame.sonar_unseen <= frame.sonar_echoes)
      << frame.sonar_echoes << " " << frame.sonar_unseen;
  const std::vector<uint8_t>& left = *frame.left_jpeg;
  const std::vector<uint8_t>& right = frame.right_jpeg ? *frame.right_jpeg : kNoImage;
  const std::string labels = LabelsJson(overlay.labels);

  std::string out;
  const size_t vertices = overlay.triangles.size() + overlay.lines.size() + overlay.points.size() +
                          map.size() + sonar.triangles.size() + sonar.lines.size() +
                          sonar_map_triangles.size() + sonar_map_lines.size();
  out.reserve(kFrameHeaderBytes + 12 * vertices + labels.size() + left.size() + right.size() + 12);
  out.append("MWF2", 4);
  PutU32(kFrameHeaderBytes, &out);
  PutU32(frame.sequence, &out);
  PutU16(static_cast<uint16_t>(frame.width_px), &out);
  PutU16(static_cast<uint16_t>(frame.height_px), &out);
  PutF64(static_cast<double>(ToUnixNanos(frame.stamp)) * 1e-9, &out);
  PutF64(static_cast<double>(ToUnixNanos(frame.scan_stamp)) * 1e-9, &out);
  PutU32(Count(overlay.triangles.size()), &out);
  PutU32(Count(overlay.lines.size()), &out);
  PutU32(Count(overlay.points.size()), &out);
  PutU32(Count(map.size()), &out);
  PutU32(Count(labels.size()), &out);
  PutU32(Count(left.size()), &out);
  PutU32(Count(right.size()), &out);
  PutF32(overlay.point_size_px, &out);
  PutU32(Count(sonar.triangles.size()), &out);
  PutU32(Count(sonar.lines.size()), &out);
  PutU32(Count(sonar_map_triangles.size()), &out);
  PutU32(Count(sonar_map_lines.size()), &out);
  PutU16(static_cast<uint16_t>(frame.sonar_echoes), &out);
  PutU16(static_cast<uint16_t>(frame.sonar_unseen), &out);
  PutU32(Count(frame.possible_obstacles), &out);
  PutU32(frame.flags, &out);
  PutU32(0, &out);
  MOSTAR_CHECK(out.size() == kFrameHeaderBytes);
  PutVertices(overlay.triangles, &out);
  PutVertices(overlay.lines, &out);
  PutVertices(overlay.points, &out);
  PutMapVertices(map, &out);
  PutVertices(sonar.triangles, &out);
  PutVertices(sonar.lines, &out);
  PutMapVertices(sonar_map_triangles, &out);
  PutMapVertices(sonar_map_lines, &out);
  out += labels;
  Pad4(&out);
  out.append(reinterpret_cast<const char*>(left.data()), left.size());
  Pad4(&out);
  out.append(reinterpret_cast<const char*>(right.data()), right.size());
  Pad4(&out);
  return out;
}

std::string JsonString(const std::string& text) {
  std::string out = "\"";
  for (size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    const size_t n = Utf8Length(text, i);
    if (n == 0) {
      out += "\\ufffd";
      ++i;
      continue;
    }
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20 || c == 0x7f) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
      out += buffer;
    } else {
      out.append(text, i, n);
    }
    i += n;
  }
  return out + "\"";
}

std::string EncodeHud(const HudState& hud) {
  std::string json = "{\"type\":\"hud\",\"seq\":" + std::to_string(hud.sequence);
  json += ",\"frame_age_ms\":" + Number(hud.frame_age_ms);
  json += ",\"scan_age_ms\":" + Number(hud.scan_age_ms);
  json += ",\"health_age_ms\":" + Number(hud.health_age_ms);
  json += ",\"video_fps\":" + Number(hud.video_fps);
  json += ",\"scan_hz\":" + Number(hud.scan_rate_hz);
  json += ",\"link\":" + JsonString(hud.link);
  json += ",\"robot\":" + JsonString(hud.robot_id);
  json += ",\"pilot\":" + JsonString(hud.pilot);
  json += ",\"watchdog\":" + JsonString(hud.watchdog);
  json += std::string(",\"estop\":") + (hud.estop_engaged ? "true" : "false");
  json += std::string(",\"dds_security_off\":") + (hud.dds_security_off ? "true" : "false");
  json += ",\"browsers\":" + std::to_string(hud.browsers);
  json += ",\"warnings\":[";
  for (size_t i = 0; i < hud.warnings.size(); ++i) {
    if (i > 0) json += ",";
    json += JsonString(hud.warnings[i]);
  }
  json += "],\"bumpers\":{\"segments\":[";
  for (size_t i = 0; i < hud.bumper_segments.size(); ++i) {
    if (i > 0) json += ",";
    json += JsonString(hud.bumper_segments[i]);
  }
  json += std::string("],\"alert\":") + (hud.bumper_alert ? "true" : "false");
  json += std::string(",\"stale\":") + (hud.bumper_stale ? "true" : "false");
  json += ",\"status\":" + JsonString(hud.bumper_status);
  char radius[32];
  std::snprintf(radius, sizeof radius, "%.3f", hud.footprint_radius_m);
  json += ",\"radius_m\":" + std::string(std::isfinite(hud.footprint_radius_m) ? radius : "0");
  return json + "}}";
}

}  // namespace mostar::web
