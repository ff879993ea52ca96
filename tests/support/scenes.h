#pragma once
// Small analytic scenes shared by the tests.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "lambert/formfactor/form_factors.h"
#include "lambert/mesh/mesh.h"
#include "lambert/scene/builtin.h"
#include "lambert/scene/scene.h"

namespace lambert::testing {

inline Scene sceneOf(std::vector<Surface> surfaces, Rgb albedo = Rgb::gray(0.5)) {
  Scene scene;
  scene.name = "test";
  scene.materials = {{"grey", albedo}};
  scene.surfaces = std::move(surfaces);
  return scene;
}

// Unit squares one apart, facing each other (Howell's catalogue: F = 0.19982).
inline Scene parallelSquares() {
  return sceneOf({{"bottom", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, 0, {}},
                  {"top", {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}}, 0, {}}});
}

// Unit squares sharing an edge at 90° (Howell: F = 0.20004).
inline Scene perpendicularSquares() {
  return sceneOf({{"floor", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, 0, {}},
                  {"wall", {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}, 0, {}}});
}

// The six faces of a cube of side `side`, normals inward; every face emits `emittedRadiance`.
inline Scene closedCube(double side = 1, Rgb emittedRadiance = {}, Rgb albedo = Rgb::gray(0.5)) {
  const double s = side;
  Scene scene = sceneOf({{"z0", {{0, 0, 0}, {s, 0, 0}, {s, s, 0}, {0, s, 0}}, 0, emittedRadiance},
                         {"z1", {{0, 0, s}, {s, 0, s}, {s, s, s}, {0, s, s}}, 0, emittedRadiance},
                         {"x0", {{0, 0, 0}, {0, 0, s}, {0, s, s}, {0, s, 0}}, 0, emittedRadiance},
                         {"x1", {{s, 0, 0}, {s, 0, s}, {s, s, s}, {s, s, 0}}, 0, emittedRadiance},
                         {"y0", {{0, 0, 0}, {s, 0, 0}, {s, 0, s}, {0, 0, s}}, 0, emittedRadiance},
                         {"y1", {{0, s, 0}, {s, s, 0}, {s, s, s}, {0, s, s}}, 0, emittedRadiance}},
                        albedo);
  const Vec3 centre{s / 2, s / 2, s / 2};
  for (Surface& face : scene.surfaces)
    if (dot(surfaceNormal(face), centre - face.vertices[0]) < 0) std::reverse(face.vertices.begin(), face.vertices.end());
  return scene;
}

// The Cornell box with its open front closed by a black, non-emitting portal: everything that
// would escape is absorbed there, so the box is a closed environment.
inline Scene closedCornellBox() {
  Scene scene = cornellBox();
  scene.materials.push_back({"black", {0, 0, 0}});
  scene.surfaces.push_back({"front portal", {{552.8, 0, 0}, {556, 548.8, 0}, {0, 548.8, 0}, {0, 0, 0}},
                            static_cast<int>(scene.materials.size() - 1), {}});
  return scene;
}

// Form factor between the patch groups of two surfaces: F_ab = Σ_{i∈a} A_i Σ_{j∈b} F_ij / A_a.
inline double surfaceFormFactor(const Mesh& mesh, const FormFactorMatrix& F, std::uint32_t from, std::uint32_t to) {
  double weighted = 0, area = 0;
  for (std::size_t i = 0; i < mesh.numPatches(); ++i) {
    if (mesh.patches[i].surface != from) continue;
    area += mesh.patches[i].area;
    for (std::size_t j = 0; j < mesh.numPatches(); ++j)
      if (mesh.patches[j].surface == to) weighted += mesh.patches[i].area * F(i, j);
  }
  return weighted / area;
}

inline double relativeError(double value, double expected) { return std::fabs(value - expected) / std::fabs(expected); }

}  // namespace lambert::testing
