// The messages mostar_web sends to browsers over the WebSocket, as bytes. Pure: no sockets.
//
// Frame (binary message), every field little-endian, every section starting at a multiple of 4
// bytes so that the page reads the vertex arrays through typed-array views without copying:
//   offset  type      field
//    0      char[4]   "MWF2"
//    4      u32       header bytes (96)
//    8      u32       frame sequence (pairs composed by this mostar_web, from 1)
//   12      u16, u16  image width, height (px)
//   16      f64       capture stamp, seconds since the Unix epoch (robot clock)
//   24      f64       stamp of the scan the overlay was built from (0: no scan)
//   32      u32 x 4   vertex counts: triangles (walls), lines, points, map points
//   48      u32 x 3   bytes: labels (UTF-8 JSON), left JPEG, right JPEG (0: left eye only)
//   60      f32       point size (px)
//   64      u32 x 4   vertex counts: sonar triangles, sonar lines (image), sonar triangles,
//                     sonar lines (map)
//   80      u16, u16  sonar sensors with an echo, of them not seen by the laser
//   84      u32       possible obstacles of the edge result (before projection; 0: none or no
//                     result)
//   88      u32       flags: kFrameEdges (the overlay holds this pair's edge result: NEP dots
//                     and the NEP-corrected scan), kFrameSonar (a fresh sonar cycle is drawn)
//   92      u32       0 (reserved)
//   96      sections, each padded with zeros to a multiple of 4 bytes:
//           triangles, lines, points: n x (f32 u, f32 v) pixels, then n x RGBA8;
//           map points: n x (f32 x, f32 y) laser frame metres, then n x RGBA8;
//           sonar triangles, sonar lines: pixels as above; sonar map triangles, lines: metres;
//           labels JSON: [{"u":..,"v":..,"c":"#rrggbb","t":"1.35 m"}, ...];
//           left JPEG; right JPEG.
// HUD (text message): a JSON object, see EncodeHud.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/time/time.h"
#include "operator_client/fusion/ar_features.h"
#include "operator_client/web/image_overlay.h"

namespace mostar::web {

constexpr uint32_t kFrameHeaderBytes = 96;
constexpr uint32_t kFrameEdges = 1u << 0;
constexpr uint32_t kFrameSonar = 1u << 1;

// A scan point on the bird's-eye map: laser frame (x forward, y left), metres.
struct MapPoint {
  float x_m = 0.f;
  float y_m = 0.f;
  uint8_t rgba[4] = {0, 0, 0, 255};
};

// The valid points of `features` for the map.
std::vector<MapPoint> MapPoints(const fusion::ArFeatures& features);

// The x, y of every vertex of `array` (laser frame, metres; z dropped) with its colour: the sonar
// fans and outlines on the map.
std::vector<MapPoint> MapVertices(const fusion::VertexArray& array);

struct FrameContent {
  uint32_t sequence = 0;
  int width_px = 0;  // of the image (and of the overlay's pixels); [0, 65535]
  int height_px = 0;
  Time stamp;                             // capture stamp of the pair
  Time scan_stamp;                        // epoch: no scan
  const ImageOverlay* overlay = nullptr;  // not owned; null: no overlay
  const std::vector<MapPoint>* map = nullptr;
  const ImageOverlay* sonar = nullptr;  // fans (triangles), outlines (lines)
  const std::vector<MapPoint>* sonar_map_triangles = nullptr;
  const std::vector<MapPoint>* sonar_map_lines = nullptr;
  int sonar_echoes = 0;  // [0, 65535]
  int sonar_unseen = 0;
  size_t possible_obstacles = 0;
  uint32_t flags = 0;                                // kFrameEdges | kFrameSonar
  const std::vector<uint8_t>* left_jpeg = nullptr;   // must be set
  const std::vector<uint8_t>* right_jpeg = nullptr;  // null: left eye only
};

std::string EncodeFrame(const FrameContent& frame);

// What the page's HUD shows. Ages in milliseconds, -1 when there is nothing to measure.
struct HudState {
  uint64_t sequence = 0;      // HUD messages composed, from 1
  double frame_age_ms = -1;   // now (this machine) minus the newest pair's capture stamp
  double scan_age_ms = -1;    // since the newest scan arrived here
  double health_age_ms = -1;  // since the newest health arrived here
  double video_fps = 0;       // pairs per second arriving from the robot
  double scan_rate_hz = 0;
  std::string link;  // "ok", "no video", "no scans", "no contact"
  std::string robot_id;
  std::string pilot;     // lease holder, empty: nobody
  std::string watchdog;  // WatchdogStateName, empty before the first health
  bool estop_engaged = false;
  bool dds_security_off = false;      // --insecure on a network profile
  std::vector<std::string> warnings;  // devices not OK: "laser warn: ..."
  uint64_t browsers = 0;              // connected observers
  // The bumper belt as the console shows it (ui::ViewBumpers): one look per segment, "idle",
  // "pressed" or "latched" (segment i centred i x 360/N degrees counter-clockwise from ahead);
  // empty when the robot has no belt or sent no state yet.
  std::vector<std::string> bumper_segments;
  bool bumper_alert = false;      // a segment pressed or latched, or the belt unreadable
  bool bumper_stale = false;      // no bumper state for ui::kBumperStaleAfter: the last known looks
  std::string bumper_status;      // the console's HUD line; empty: nothing to say
  double footprint_radius_m = 0;  // of the robot outline on the map (the console's)
};

std::string EncodeHud(const HudState& hud);

// `text` as a JSON string literal (quotes, escapes, control characters as \u00XX; bytes that
// are not valid UTF-8 replaced by U+FFFD).
std::string JsonString(const std::string& text);

}  // namespace mostar::web
