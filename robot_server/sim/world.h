// The simulated world as geometry: a scene file compiled into vertical prisms over a floor.
//
// World frame: x, y on the floor, z up; metres, radians. Every obstacle is the vertical
// extrusion of a 2D footprint (a segment, a rotated rectangle or a circle) between z_min_m and
// z_max_m. A ray is described by its 2D origin, its azimuth (counter-clockwise from world x)
// and the tangent of its elevation; distances along it are *horizontal* distances `h_m`, the
// height of the ray at h is `origin_z + h * tan_elevation`. The laser beams and the camera
// pixel rays share this tracer, so what the laser misses (an object below its plane) and what
// the cameras see come from the same geometry.
//
// A World is immutable after construction and safe to read from many threads.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "robot_server/sim/scene.pb.h"

namespace mostar::sim {

// Linear 0..255 colour channels.
struct Rgb {
  float r = 0.f;
  float g = 0.f;
  float b = 0.f;
};

Rgb ToRgb(const proto::Colour& colour);

struct Surface {
  Rgb colour;
  Rgb colour2;
  proto::Material::Texture texture = proto::Material::SOLID;
  double square_m = 0.25;
  proto::LaserResponse laser = proto::NORMAL;
  double spurious_probability = 0.5;
};

enum class ShapeKind { kWall, kBox, kCylinder };

struct Obstacle {
  int id = 0;  // 1..N, index + 1 into World::obstacles(); 0 is reserved for the floor
  std::string name;
  ShapeKind kind = ShapeKind::kWall;
  // kWall: the segment (x0, y0)-(x1, y1). kBox: centre (x0, y0), yaw, half sizes. kCylinder:
  // centre (x0, y0), radius.
  double x0_m = 0, y0_m = 0, x1_m = 0, y1_m = 0;
  double yaw_rad = 0, half_x_m = 0, half_y_m = 0;
  double radius_m = 0;
  double z_min_m = 0, z_max_m = 0;
  Surface surface;
  double baseboard_height_m = 0;  // walls only
  Rgb baseboard;
};

// Which part of an obstacle a ray met.
enum class Face { kSide, kTop, kBottom };

// Where a 2D ray crosses an obstacle's footprint. For walls h_in == h_out.
struct FootprintHit {
  double h_in_m = 0;      // horizontal distance where the ray enters the footprint (>= 0)
  double h_out_m = 0;     // where it leaves
  double nx = 0, ny = 0;  // outward unit normal of the side crossed at h_in (world frame)
  double u_m = 0;         // texture coordinate along that side at h_in
};

// Crosses the 2D ray (ox, oy) + h (cos az, sin az) with the footprint. False when missed or
// when the footprint lies behind the origin (an origin inside a box/cylinder sees nothing of it).
bool IntersectFootprint(const Obstacle& obstacle, double ox_m, double oy_m, double dir_x,
                        double dir_y, FootprintHit* hit);

// Given a footprint crossing and a ray of height oz + h * tan_el, the face hit and its distance.
// False when the ray passes above or below the obstacle.
bool ResolveVertical(const Obstacle& obstacle, const FootprintHit& fp, double oz_m, double tan_el,
                     double* h_m, Face* face);

// What a traced ray hit.
struct RayHit {
  enum Kind { kNothing, kFloor, kCeiling, kObstacle };
  Kind kind = kNothing;
  const Obstacle* obstacle = nullptr;  // for kObstacle
  Face face = Face::kSide;
  double h_m = 0;                    // horizontal distance from the origin
  double x_m = 0, y_m = 0, z_m = 0;  // hit point, world frame
  double nx = 0, ny = 0, nz = 0;     // surface normal, world frame
  double u_m = 0;                    // texture coordinate along a side face
};

struct Lighting {
  double brightness = 1.0;
  double ambient = 0.55;
  double lx = 0, ly = 0, lz = 1;  // unit vector towards the light
};

// The compiled scene.
class World {
 public:
  // `scene` must have passed ValidateScene (scene.h).
  explicit World(const proto::Scene& scene);

  const std::vector<Obstacle>& obstacles() const { return obstacles_; }
  const proto::Scene& scene() const { return scene_; }
  const Lighting& lighting() const { return lighting_; }
  double ceiling_height_m() const { return ceiling_height_m_; }  // 0 = none

  // Traces a ray up to max_h_m (horizontal). With `skip_transparent`, obstacles whose laser
  // response is TRANSPARENT are passed through (the laser); the cameras see them.
  RayHit Trace(double ox_m, double oy_m, double oz_m, double azimuth_rad, double tan_el,
               double max_h_m, bool skip_transparent) const;

  // True when a circle on the floor overlaps any obstacle footprint (all heights collide).
  bool CircleCollides(double x_m, double y_m, double radius_m) const;

  // Floor appearance at a world point, before lighting: colour and whether it is a dark
  // checkerboard square. Outside the floor extent `inside` is false.
  Rgb FloorAlbedo(double x_m, double y_m, bool* inside, bool* dark_square) const;
  // Appearance of an obstacle surface at a hit, before lighting; `dark` tells a colour2 cell.
  Rgb ObstacleAlbedo(const RayHit& hit, bool* dark) const;
  // True when (x, y) lies within the floor extent.
  bool OnFloor(double x_m, double y_m) const {
    return x_m >= floor_.min_x_m && x_m <= floor_.max_x_m && y_m >= floor_.min_y_m &&
           y_m <= floor_.max_y_m;
  }
  // Ambient occlusion of the floor near obstacle bases, 0..1 (1 = open floor).
  float FloorOcclusion(double x_m, double y_m) const;
  // Shade() of a floor hit at (x, y), which must lie within the floor extent (the per-pixel
  // path of the cameras).
  Rgb ShadeFloor(double x_m, double y_m, bool contact_shadows) const;
  // Where the side of `obstacle` with outward normal (nx, ny) is plain (no texture, skirting
  // board or contact shadow), Shade() of any hit on it at a height z_m >= *plain_from_z_m is
  // the colour returned. *plain_from_z_m is +inf when the side is textured.
  Rgb ShadePlainSide(const Obstacle& obstacle, double nx, double ny, bool contact_shadows,
                     double* plain_from_z_m) const;

  // Lit colour of a hit (kNothing gives the dark void colour). Distance fall-off excluded.
  // `contact_shadows`: apply FloorOcclusion and the darkening of obstacle sides near the floor.
  Rgb Shade(const RayHit& hit, bool contact_shadows = true) const;

 private:
  // Floor albedo as a colour times a factor.
  const Rgb& FloorAlbedoAt(double x_m, double y_m, bool* dark_square, double* factor) const;
  // Half-Lambert light factor of a surface with unit normal n, before brightness.
  double Light(double nx, double ny, double nz) const;

  proto::Scene scene_;
  std::vector<Obstacle> obstacles_;
  Lighting lighting_;
  double ceiling_height_m_ = 0;
  Rgb ceiling_colour_;
  // Floor, copied out of the proto for the per-pixel paths.
  struct FloorCache {
    double min_x_m, min_y_m, max_x_m, max_y_m, square_m;
    double per_square_m;    // 1 / square_m
    double joint;           // joint width in squares (FAINT_PATTERN, TILES)
    double tile_variation;  // TILES: albedo spread between tiles
    proto::Floor::Pattern pattern;
    Rgb colour, colour2, joint_colour;
    double light;  // Lambert factor of the horizontal floor, before brightness
  } floor_;
  // Tape on the floor: from (x0, y0) along the unit vector (ux, uy) for length_m.
  struct TapeStrip {
    double x0_m, y0_m, ux, uy, length_m, half_width_m;
    Rgb colour;
  };
  std::vector<TapeStrip> tapes_;
  // Floor occlusion map: cell (row, col) covers [min_x + col*res, ...] x [min_y + row*res, ...].
  cv::Mat occlusion_;  // CV_32F
  double occlusion_res_m_ = 0.02;
  double per_occlusion_res_m_ = 50;  // 1 / occlusion_res_m_
};

}  // namespace mostar::sim
