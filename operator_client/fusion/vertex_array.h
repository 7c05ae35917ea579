// Plain vertex data for the overlay renderer: positions in the laser frame, colours as RGBA.
#pragma once

#include <cstddef>
#include <vector>

namespace mostar::fusion {

// Colour with components in [0, 1]; alpha 1 = opaque.
struct Rgba {
  float r = 0.f;
  float g = 0.f;
  float b = 0.f;
  float a = 1.f;

  Rgba WithAlpha(float alpha) const { return Rgba{r, g, b, alpha}; }
};

// A point in the scan plane (laser frame, which is the base frame raised to the laser; x
// forward, y left; metres).
struct PlanarPoint {
  float x_m = 0.f;
  float y_m = 0.f;
};

// Interleaving-free vertex arrays, ready for glBufferData: `positions` holds x, y, z per vertex
// (laser frame, metres) and `colors` r, g, b, a per vertex. The primitive type (points, lines,
// triangles) is stated where the array is produced.
struct VertexArray {
  std::vector<float> positions;  // 3 floats per vertex
  std::vector<float> colors;     // 4 floats per vertex

  size_t vertex_count() const { return positions.size() / 3; }
  bool empty() const { return positions.empty(); }
  // Keeps the capacity, so a reused array does not allocate in steady state.
  void Clear() {
    positions.clear();
    colors.clear();
  }
  void Reserve(size_t vertices) {
    positions.reserve(3 * vertices);
    colors.reserve(4 * vertices);
  }
  void Add(float x, float y, float z, const Rgba& color) {
    positions.insert(positions.end(), {x, y, z});
    colors.insert(colors.end(), {color.r, color.g, color.b, color.a});
  }
};

}  // namespace mostar::fusion
