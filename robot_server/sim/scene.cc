#include "robot_server/sim/scene.h"

#include <cmath>
#include <sstream>

#include "common/config/config_loader.h"

namespace mostar::sim {
namespace {

std::string Key(const char* field, int index, const char* sub) {
  std::ostringstream out;
  out << field << '[' << index << "]." << sub;
  return out.str();
}

bool Fail(const std::string& name, const std::string& key, const std::string& reason,
          std::string* error) {
  *error = name + ": " + key + ": " + reason;
  return false;
}

bool CheckMaterial(const proto::Material& m, const std::string& name, const std::string& key,
                   std::string* error) {
  if (m.texture() != proto::Material::SOLID && !m.has_colour2()) {
    return Fail(name, key + ".colour2", "a textured material needs a second colour", error);
  }
  if (m.laser() == proto::ABSORB_DARK && m.texture() == proto::Material::SOLID) {
    return Fail(name, key + ".laser", "ABSORB_DARK needs a CHECKERBOARD or STRIPES texture", error);
  }
  return true;
}

}  // namespace

bool LoadScene(const std::string& path, proto::Scene* scene, std::string* error) {
  if (!LoadTextConfig(path, scene, error)) return false;
  return ValidateScene(*scene, path, error);
}

bool ParseScene(const std::string& text, const std::string& name, proto::Scene* scene,
                std::string* error) {
  if (!ParseTextConfig(text, name, scene, error)) return false;
  return ValidateScene(*scene, name, error);
}

bool ValidateScene(const proto::Scene& scene, const std::string& name, std::string* error) {
  if (!ValidateRanges(scene, name, error)) return false;
  const auto& f = scene.floor();
  if (!(f.max_x_m() > f.min_x_m())) return Fail(name, "floor.max_x_m", "must be > min_x_m", error);
  if (!(f.max_y_m() > f.min_y_m())) return Fail(name, "floor.max_y_m", "must be > min_y_m", error);
  if (f.black_squares_absorb() && f.pattern() != proto::Floor::CHECKERBOARD) {
    return Fail(name, "floor.black_squares_absorb", "needs pattern: CHECKERBOARD", error);
  }
  for (int i = 0; i < scene.tape_size(); ++i) {
    const auto& t = scene.tape(i);
    if (std::hypot(t.x1_m() - t.x0_m(), t.y1_m() - t.y0_m()) < 1e-3) {
      return Fail(name, Key("tape", i, "x1_m"), "tape has zero length", error);
    }
  }
  for (int i = 0; i < scene.wall_size(); ++i) {
    const auto& w = scene.wall(i);
    if (std::hypot(w.x1_m() - w.x0_m(), w.y1_m() - w.y0_m()) < 1e-3) {
      return Fail(name, Key("wall", i, "x1_m"), "wall has zero length", error);
    }
    if (!CheckMaterial(w.material(), name, Key("wall", i, "material"), error)) return false;
  }
  for (int i = 0; i < scene.box_size(); ++i) {
    const auto& b = scene.box(i);
    if (!b.has_size_x_m()) return Fail(name, Key("box", i, "size_x_m"), "must be set", error);
    if (!b.has_size_y_m()) return Fail(name, Key("box", i, "size_y_m"), "must be set", error);
    if (!b.has_height_m()) return Fail(name, Key("box", i, "height_m"), "must be set", error);
    if (!CheckMaterial(b.material(), name, Key("box", i, "material"), error)) return false;
  }
  for (int i = 0; i < scene.cylinder_size(); ++i) {
    const auto& c = scene.cylinder(i);
    if (!c.has_radius_m()) {
      return Fail(name, Key("cylinder", i, "radius_m"), "must be set", error);
    }
    if (!c.has_height_m()) {
      return Fail(name, Key("cylinder", i, "height_m"), "must be set", error);
    }
    if (!CheckMaterial(c.material(), name, Key("cylinder", i, "material"), error)) return false;
  }
  const auto& s = scene.start();
  if (s.x_m() < f.min_x_m() || s.x_m() > f.max_x_m() || s.y_m() < f.min_y_m() ||
      s.y_m() > f.max_y_m()) {
    return Fail(name, "start", "start pose is outside the floor", error);
  }
  return true;
}

}  // namespace mostar::sim
