#include "robot_server/sim/world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

namespace mostar::sim {
namespace {

constexpr double kEps = 1e-9;

Surface ToSurface(const proto::Material& m) {
  Surface s;
  s.colour = ToRgb(m.colour());
  s.colour2 = m.has_colour2() ? ToRgb(m.colour2()) : Rgb{30.f, 30.f, 30.f};
  s.texture = m.texture();
  s.square_m = m.square_m();
  s.laser = m.laser();
  s.spurious_probability = m.spurious_probability();
  return s;
}

Rgb Scale(const Rgb& c, double k) {
  const auto f = static_cast<float>(k);
  return {c.r * f, c.g * f, c.b * f};
}

bool Odd(double a, double b) {
  const auto ia = static_cast<int64_t>(std::floor(a));
  const auto ib = static_cast<int64_t>(std::floor(b));
  return ((ia + ib) & 1) != 0;
}

// A small deterministic hash of a tile index to 0..1.
double TileHash(int64_t i, int64_t j) {
  uint64_t h = static_cast<uint64_t>(i) * 0x9E3779B97F4A7C15ull ^
               (static_cast<uint64_t>(j) + 0x632BE59BD9B4E019ull) * 0xC2B2AE3D27D4EB4Full;
  h ^= h >> 31;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 29;
  return static_cast<double>(h & 0xFFFF) / 65535.0;
}

void AddCylinder(std::vector<Obstacle>* out, const std::string& name, double x, double y, double r,
                 double z0, double z1, const Surface& surface) {
  Obstacle o;
  o.name = name;
  o.kind = ShapeKind::kCylinder;
  o.x0_m = x;
  o.y0_m = y;
  o.radius_m = r;
  o.z_min_m = z0;
  o.z_max_m = z1;
  o.surface = surface;
  out->push_back(o);
}

}  // namespace

Rgb ToRgb(const proto::Colour& c) {
  return {static_cast<float>(c.r()), static_cast<float>(c.g()), static_cast<float>(c.b())};
}

bool IntersectFootprint(const Obstacle& ob, double ox, double oy, double dx, double dy,
                        FootprintHit* hit) {
  switch (ob.kind) {
    case ShapeKind::kWall: {
      const double ex = ob.x1_m - ob.x0_m, ey = ob.y1_m - ob.y0_m;
      const double denom = dx * ey - dy * ex;
      if (std::abs(denom) < kEps) return false;
      const double wx = ob.x0_m - ox, wy = ob.y0_m - oy;
      const double h = (wx * ey - wy * ex) / denom;
      const double s = (wx * dy - wy * dx) / denom;
      if (h <= kEps || s < 0.0 || s > 1.0) return false;
      const double len = std::hypot(ex, ey);
      double nx = -ey / len, ny = ex / len;
      if (nx * dx + ny * dy > 0) {
        nx = -nx;
        ny = -ny;
      }
      *hit = {h, h, nx, ny, s * len};
      return true;
    }
    case ShapeKind::kBox: {
      const double c = std::cos(ob.yaw_rad), s = std::sin(ob.yaw_rad);
      const double px = ox - ob.x0_m, py = oy - ob.y0_m;
      const double lx = c * px + s * py, ly = -s * px + c * py;
      const double ldx = c * dx + s * dy, ldy = -s * dx + c * dy;
      double t_min = -std::numeric_limits<double>::infinity();
      double t_max = std::numeric_limits<double>::infinity();
      int axis = -1;
      const double o[2] = {lx, ly}, d[2] = {ldx, ldy}, half[2] = {ob.half_x_m, ob.half_y_m};
      for (int a = 0; a < 2; ++a) {
        if (std::abs(d[a]) < kEps) {
          if (std::abs(o[a]) > half[a]) return false;
          continue;
        }
        double t1 = (-half[a] - o[a]) / d[a], t2 = (half[a] - o[a]) / d[a];
        if (t1 > t2) std::swap(t1, t2);
        if (t1 > t_min) {
          t_min = t1;
          axis = a;
        }
        t_max = std::min(t_max, t2);
      }
      if (axis < 0 || t_min > t_max || t_min <= kEps) return false;
      // Entry face normal in the box frame, then in the world.
      double lnx = 0, lny = 0, u = 0;
      if (axis == 0) {
        lnx = d[0] > 0 ? -1 : 1;
        u = o[1] + t_min * d[1] + half[1];
      } else {
        lny = d[1] > 0 ? -1 : 1;
        u = o[0] + t_min * d[0] + half[0];
      }
      *hit = {t_min, t_max, c * lnx - s * lny, s * lnx + c * lny, u};
      return true;
    }
    case ShapeKind::kCylinder: {
      const double px = ox - ob.x0_m, py = oy - ob.y0_m;
      const double b = px * dx + py * dy;
      const double cc = px * px + py * py - ob.radius_m * ob.radius_m;
      const double disc = b * b - cc;
      if (disc < 0) return false;
      const double sq = std::sqrt(disc);
      const double h_in = -b - sq;
      if (h_in <= kEps) return false;
      const double nx = (px + h_in * dx) / ob.radius_m, ny = (py + h_in * dy) / ob.radius_m;
      *hit = {h_in, -b + sq, nx, ny, ob.radius_m * std::atan2(ny, nx)};
      return true;
    }
  }
  return false;
}

bool ResolveVertical(const Obstacle& ob, const FootprintHit& fp, double oz, double tan_el,
                     double* h_m, Face* face) {
  const double z_in = oz + fp.h_in_m * tan_el;
  if (z_in >= ob.z_min_m && z_in <= ob.z_max_m) {
    *h_m = fp.h_in_m;
    *face = Face::kSide;
    return true;
  }
  if (ob.kind == ShapeKind::kWall) return false;
  if (z_in > ob.z_max_m && tan_el < 0) {
    const double h = (ob.z_max_m - oz) / tan_el;
    if (h <= fp.h_out_m) {
      *h_m = h;
      *face = Face::kTop;
      return true;
    }
  } else if (z_in < ob.z_min_m && tan_el > 0) {
    const double h = (ob.z_min_m - oz) / tan_el;
    if (h <= fp.h_out_m) {
      *h_m = h;
      *face = Face::kBottom;
      return true;
    }
  }
  return false;
}

World::World(const proto::Scene& scene) : scene_(scene) {
  for (const auto& w : scene.wall()) {
    Obstacle o;
    o.name = "wall";
    o.kind = ShapeKind::kWall;
    o.x0_m = w.x0_m();
    o.y0_m = w.y0_m();
    o.x1_m = w.x1_m();
    o.y1_m = w.y1_m();
    o.z_max_m = w.height_m();
    o.surface = ToSurface(w.material());
    o.baseboard_height_m = w.baseboard_height_m();
    o.baseboard =
        w.has_baseboard_colour() ? ToRgb(w.baseboard_colour()) : Scale(o.surface.colour, 0.55);
    obstacles_.push_back(o);
  }
  for (const auto& b : scene.box()) {
    Obstacle o;
    o.name = b.name().empty() ? "box" : b.name();
    o.kind = ShapeKind::kBox;
    o.x0_m = b.x_m();
    o.y0_m = b.y_m();
    o.yaw_rad = b.yaw_rad();
    o.half_x_m = b.size_x_m() / 2;
    o.half_y_m = b.size_y_m() / 2;
    o.z_min_m = b.elevation_m();
    o.z_max_m = b.elevation_m() + b.height_m();
    o.surface = ToSurface(b.material());
    obstacles_.push_back(o);
  }
  for (const auto& c : scene.cylinder()) {
    AddCylinder(&obstacles_, c.name().empty() ? "cylinder" : c.name(), c.x_m(), c.y_m(),
                c.radius_m(), c.elevation_m(), c.elevation_m() + c.height_m(),
                ToSurface(c.material()));
  }
  for (const auto& p : scene.person()) {
    const std::string name = p.name().empty() ? "person" : p.name();
    const double lx = -std::sin(p.yaw_rad()), ly = std::cos(p.yaw_rad());  // person's left
    Surface legs;
    legs.colour = p.has_trousers() ? ToRgb(p.trousers()) : Rgb{50, 55, 80};
    legs.laser = p.legs_laser();
    Surface shirt;
    shirt.colour = p.has_shirt() ? ToRgb(p.shirt()) : Rgb{170, 60, 50};
    Surface skin;
    skin.colour = {200, 160, 135};
    AddCylinder(&obstacles_, name + ".left_leg", p.x_m() + 0.1 * lx, p.y_m() + 0.1 * ly, 0.065, 0,
                0.86, legs);
    AddCylinder(&obstacles_, name + ".right_leg", p.x_m() - 0.1 * lx, p.y_m() - 0.1 * ly, 0.065, 0,
                0.86, legs);
    AddCylinder(&obstacles_, name + ".torso", p.x_m(), p.y_m(), 0.19, 0.86, 1.47, shirt);
    AddCylinder(&obstacles_, name + ".head", p.x_m(), p.y_m(), 0.1, 1.5, 1.74, skin);
  }
  for (size_t i = 0; i < obstacles_.size(); ++i) obstacles_[i].id = static_cast<int>(i) + 1;

  const auto& l = scene.lighting();
  lighting_.brightness = l.brightness();
  lighting_.ambient = l.ambient();
  lighting_.lx = std::cos(l.elevation_rad()) * std::cos(l.azimuth_rad());
  lighting_.ly = std::cos(l.elevation_rad()) * std::sin(l.azimuth_rad());
  lighting_.lz = std::sin(l.elevation_rad());
  ceiling_height_m_ = scene.ceiling_height_m();
  ceiling_colour_ = scene.has_ceiling_colour() ? ToRgb(scene.ceiling_colour()) : Rgb{215, 215, 210};

  const auto& fl = scene.floor();
  floor_.min_x_m = fl.min_x_m();
  floor_.min_y_m = fl.min_y_m();
  floor_.max_x_m = fl.max_x_m();
  floor_.max_y_m = fl.max_y_m();
  floor_.square_m = fl.square_m();
  floor_.pattern = fl.pattern();
  floor_.colour = fl.has_colour() ? ToRgb(fl.colour()) : Rgb{150, 140, 125};
  floor_.colour2 = fl.has_colour2() ? ToRgb(fl.colour2()) : Rgb{25, 25, 25};
  floor_.joint_colour = Scale(floor_.colour, 0.86);
  floor_.per_square_m = 1.0 / floor_.square_m;
  floor_.joint =
      (fl.pattern() == proto::Floor::TILES ? 0.5 * fl.joint_m() : 0.006) / floor_.square_m;
  floor_.tile_variation = fl.tile_variation();
  for (const auto& t : scene.tape()) {
    const double dx = t.x1_m() - t.x0_m(), dy = t.y1_m() - t.y0_m();
    const double length_m = std::hypot(dx, dy);
    tapes_.push_back({t.x0_m(), t.y0_m(), dx / length_m, dy / length_m, length_m, 0.5 * t.width_m(),
                      t.has_colour() ? ToRgb(t.colour()) : Rgb{225, 190, 40}});
  }
  floor_.light = lighting_.ambient + (1 - lighting_.ambient) * 0.5 * (1.0 + lighting_.lz);

  // Floor occlusion: distance from each floor cell to the nearest footprint standing on it.
  const auto& f = scene.floor();
  const double area = (f.max_x_m() - f.min_x_m()) * (f.max_y_m() - f.min_y_m());
  occlusion_res_m_ = std::max(0.02, std::sqrt(area / 2e6));
  per_occlusion_res_m_ = 1.0 / occlusion_res_m_;
  const int cols = static_cast<int>(std::ceil((f.max_x_m() - f.min_x_m()) / occlusion_res_m_));
  const int rows = static_cast<int>(std::ceil((f.max_y_m() - f.min_y_m()) / occlusion_res_m_));
  cv::Mat free_mask(rows, cols, CV_8U, cv::Scalar(255));
  const int kShift = 4;  // sub-cell precision of the rasterisation
  auto to_cell = [&](double x, double y) {
    return cv::Point(static_cast<int>((x - f.min_x_m()) / occlusion_res_m_ * (1 << kShift)),
                     static_cast<int>((y - f.min_y_m()) / occlusion_res_m_ * (1 << kShift)));
  };
  for (const auto& o : obstacles_) {
    if (o.z_min_m > 0.05) continue;
    if (o.kind == ShapeKind::kWall) {
      cv::line(free_mask, to_cell(o.x0_m, o.y0_m), to_cell(o.x1_m, o.y1_m), cv::Scalar(0), 1,
               cv::LINE_8, kShift);
    } else if (o.kind == ShapeKind::kBox) {
      const double c = std::cos(o.yaw_rad), s = std::sin(o.yaw_rad);
      std::vector<cv::Point> corners;
      for (const auto& [sx, sy] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
        const double lx = sx * o.half_x_m, ly = sy * o.half_y_m;
        corners.push_back(to_cell(o.x0_m + c * lx - s * ly, o.y0_m + s * lx + c * ly));
      }
      cv::fillConvexPoly(free_mask, corners, cv::Scalar(0), cv::LINE_8, kShift);
    } else {
      cv::circle(free_mask, to_cell(o.x0_m, o.y0_m),
                 static_cast<int>(o.radius_m / occlusion_res_m_ * (1 << kShift)), cv::Scalar(0),
                 cv::FILLED, cv::LINE_8, kShift);
    }
  }
  cv::Mat dist;
  cv::distanceTransform(free_mask, dist, cv::DIST_L2, 3);
  // occlusion = 1 - 0.45 exp(-d / 4.5 cm)
  cv::Mat decay;
  cv::exp(dist * (-occlusion_res_m_ / 0.045), decay);
  occlusion_ = 1.0 - 0.45 * decay;
}

RayHit World::Trace(double ox, double oy, double oz, double azimuth_rad, double tan_el,
                    double max_h_m, bool skip_transparent) const {
  const double dx = std::cos(azimuth_rad), dy = std::sin(azimuth_rad);
  RayHit best;
  double best_h = max_h_m;
  FootprintHit fp, best_fp;
  for (const auto& ob : obstacles_) {
    if (skip_transparent && ob.surface.laser == proto::TRANSPARENT) continue;
    if (!IntersectFootprint(ob, ox, oy, dx, dy, &fp) || fp.h_in_m >= best_h) continue;
    double h;
    Face face;
    if (!ResolveVertical(ob, fp, oz, tan_el, &h, &face) || h >= best_h) continue;
    best_h = h;
    best.kind = RayHit::kObstacle;
    best.obstacle = &ob;
    best.face = face;
    best_fp = fp;
  }
  if (tan_el < 0) {
    const double h_floor = oz / -tan_el;
    if (h_floor < best_h) {
      best_h = h_floor;
      best.kind = RayHit::kFloor;
    }
  } else if (tan_el > 0 && ceiling_height_m_ > oz) {
    const double h_ceiling = (ceiling_height_m_ - oz) / tan_el;
    if (h_ceiling < best_h) {
      best_h = h_ceiling;
      best.kind = RayHit::kCeiling;
    }
  }
  if (best.kind == RayHit::kNothing) return best;
  best.h_m = best_h;
  best.x_m = ox + best_h * dx;
  best.y_m = oy + best_h * dy;
  best.z_m = oz + best_h * tan_el;
  if (best.kind == RayHit::kFloor) {
    const FloorCache& f = floor_;
    if (best.x_m < f.min_x_m || best.x_m > f.max_x_m || best.y_m < f.min_y_m ||
        best.y_m > f.max_y_m) {
      best.kind = RayHit::kNothing;
      return best;
    }
    best.nz = 1;
  } else if (best.kind == RayHit::kCeiling) {
    best.nz = -1;
  } else if (best.face == Face::kSide) {
    best.nx = best_fp.nx;
    best.ny = best_fp.ny;
    best.u_m = best_fp.u_m;
  } else {
    best.nz = best.face == Face::kTop ? 1 : -1;
  }
  return best;
}

bool World::CircleCollides(double x, double y, double r) const {
  for (const auto& o : obstacles_) {
    switch (o.kind) {
      case ShapeKind::kWall: {
        const double ex = o.x1_m - o.x0_m, ey = o.y1_m - o.y0_m;
        const double len2 = ex * ex + ey * ey;
        double t = len2 > 0 ? ((x - o.x0_m) * ex + (y - o.y0_m) * ey) / len2 : 0.0;
        t = std::clamp(t, 0.0, 1.0);
        if (std::hypot(x - (o.x0_m + t * ex), y - (o.y0_m + t * ey)) < r) return true;
        break;
      }
      case ShapeKind::kBox: {
        const double c = std::cos(o.yaw_rad), s = std::sin(o.yaw_rad);
        const double px = x - o.x0_m, py = y - o.y0_m;
        const double lx = c * px + s * py, ly = -s * px + c * py;
        const double qx = std::clamp(lx, -o.half_x_m, o.half_x_m);
        const double qy = std::clamp(ly, -o.half_y_m, o.half_y_m);
        if (std::hypot(lx - qx, ly - qy) < r) return true;
        break;
      }
      case ShapeKind::kCylinder:
        if (std::hypot(x - o.x0_m, y - o.y0_m) < r + o.radius_m) return true;
        break;
    }
  }
  return false;
}

Rgb World::FloorAlbedo(double x, double y, bool* inside, bool* dark_square) const {
  *inside = OnFloor(x, y);
  double factor;
  const Rgb& colour = FloorAlbedoAt(x, y, dark_square, &factor);
  return factor == 1.0 ? colour : Scale(colour, factor);
}

inline const Rgb& World::FloorAlbedoAt(double x, double y, bool* dark_square,
                                       double* factor) const {
  const FloorCache& f = floor_;
  *dark_square = false;
  *factor = 1.0;
  for (const TapeStrip& tape : tapes_) {
    const double rx = x - tape.x0_m, ry = y - tape.y0_m;
    const double along = rx * tape.ux + ry * tape.uy;
    if (along >= 0 && along <= tape.length_m &&
        std::abs(rx * tape.uy - ry * tape.ux) <= tape.half_width_m) {
      return tape.colour;
    }
  }
  switch (f.pattern) {
    case proto::Floor::PLAIN:
      return f.colour;
    case proto::Floor::FAINT_PATTERN:
    case proto::Floor::TILES: {
      // Joints centred on the tile borders, half on each side.
      const double ux = x * f.per_square_m, uy = y * f.per_square_m;
      const double ix = std::floor(ux), iy = std::floor(uy);
      const double fx = ux - ix, fy = uy - iy;
      const bool tiles = f.pattern == proto::Floor::TILES;
      if (fx < f.joint || fx > 1 - f.joint || fy < f.joint || fy > 1 - f.joint) {
        return tiles ? f.colour2 : f.joint_colour;
      }
      const double hash = TileHash(static_cast<int64_t>(ix), static_cast<int64_t>(iy));
      *factor = tiles ? 1.0 + f.tile_variation * (hash - 0.5) : 0.96 + 0.08 * hash;
      return f.colour;
    }
    case proto::Floor::CHECKERBOARD:
      if (Odd(x * f.per_square_m, y * f.per_square_m)) {
        *dark_square = true;
        return f.colour2;
      }
      return f.colour;
  }
  return f.colour;
}

Rgb World::ObstacleAlbedo(const RayHit& hit, bool* dark) const {
  const Obstacle& o = *hit.obstacle;
  const Surface& s = o.surface;
  *dark = false;
  if (o.kind == ShapeKind::kWall && hit.z_m < o.baseboard_height_m) return o.baseboard;
  switch (s.texture) {
    case proto::Material::SOLID:
      return s.colour;
    case proto::Material::CHECKERBOARD:
      *dark = hit.face == Face::kSide ? Odd(hit.u_m / s.square_m, hit.z_m / s.square_m)
                                      : Odd(hit.x_m / s.square_m, hit.y_m / s.square_m);
      return *dark ? s.colour2 : s.colour;
    case proto::Material::STRIPES:
      *dark = Odd(hit.z_m / s.square_m, 0.0);
      return *dark ? s.colour2 : s.colour;
  }
  return s.colour;
}

float World::FloorOcclusion(double x, double y) const {
  const int c = static_cast<int>((x - floor_.min_x_m) * per_occlusion_res_m_);
  const int r = static_cast<int>((y - floor_.min_y_m) * per_occlusion_res_m_);
  if (r < 0 || c < 0 || r >= occlusion_.rows || c >= occlusion_.cols) return 1.f;
  return occlusion_.at<float>(r, c);
}

Rgb World::ShadeFloor(double x, double y, bool contact_shadows) const {
  bool dark;
  double k;
  const Rgb& albedo = FloorAlbedoAt(x, y, &dark, &k);
  k *= floor_.light;
  if (contact_shadows) k *= FloorOcclusion(x, y);
  return Scale(albedo, k * lighting_.brightness);
}

double World::Light(double nx, double ny, double nz) const {
  // Half-Lambert: indoor light comes from many lamps and bounces, so surfaces facing away
  // from the main light are dimmer but not dark.
  const double cos_l = nx * lighting_.lx + ny * lighting_.ly + nz * lighting_.lz;
  const double diffuse = 0.5 * (1.0 + cos_l);
  return lighting_.ambient + (1 - lighting_.ambient) * diffuse;
}

Rgb World::ShadePlainSide(const Obstacle& o, double nx, double ny, bool contact_shadows,
                          double* plain_from_z_m) const {
  *plain_from_z_m = std::numeric_limits<double>::infinity();
  if (o.surface.texture != proto::Material::SOLID) return {};
  double from_z_m = -std::numeric_limits<double>::infinity();
  if (o.kind == ShapeKind::kWall) from_z_m = o.baseboard_height_m;  // see ObstacleAlbedo
  if (contact_shadows && o.z_min_m < 0.05) from_z_m = std::max(from_z_m, o.z_min_m + 0.25);
  *plain_from_z_m = from_z_m;
  return Scale(o.surface.colour, Light(nx, ny, 0) * lighting_.brightness);
}

Rgb World::Shade(const RayHit& hit, bool contact_shadows) const {
  const double bright = lighting_.brightness;
  switch (hit.kind) {
    case RayHit::kNothing:
      return Scale({22, 22, 26}, bright);
    case RayHit::kCeiling:
      return Scale(ceiling_colour_, bright);
    case RayHit::kFloor:
      return ShadeFloor(hit.x_m, hit.y_m, contact_shadows);
    case RayHit::kObstacle: {
      bool dark;
      const Rgb albedo = ObstacleAlbedo(hit, &dark);
      double k = Light(hit.nx, hit.ny, hit.nz);
      if (contact_shadows && hit.face == Face::kSide && hit.obstacle->z_min_m < 0.05 &&
          hit.z_m - hit.obstacle->z_min_m < 0.25) {
        k *= 1.0 - 0.25 * std::exp(-(hit.z_m - hit.obstacle->z_min_m) / 0.04);
      }
      return Scale(albedo, k * bright);
    }
  }
  return {};
}

}  // namespace mostar::sim
