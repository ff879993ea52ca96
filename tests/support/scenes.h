#pragma once
// Small analytic scenes shared by the tests.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "lambert/flat/form_factors.h"
#include "lambert/formfactor/kernels.h"
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

// Unit squares one apart (parallelSquares): the top one black and emitting L_e = 1 W/(m²·sr)
// (E = π W/m² in each channel), the bottom one grey, ρ = `albedo`. Light goes from the top to the
// bottom, which reflects ρ of it; the black top absorbs what comes back, and nothing else returns.
// In closed form, with F(x) the exact point-to-square factor at a point x of the bottom square:
//   absorbed = π [(1 − ρ) ∫ F(x) dA + ρ ∫ F(x)² dA],   escaped = π − absorbed,
// the first term the bottom's share, the second the top's (B_bottom(x) = ρ π F(x), and the top
// receives ∫ B_bottom(x) F(x) dA of it). The integrals by the midpoint rule on a 128 × 128 grid
// (F is smooth on the square: exact to ~1e-6).
struct EnergyBalanceWatts {
  double emitted = 0, absorbed = 0, escaped = 0;
};
inline Scene emitterOverPlate(double albedo) {
  Scene scene = sceneOf({{"plate", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, 0, {}},
                         {"emitter", {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}}, 1, Rgb::gray(1)}},
                        Rgb::gray(albedo));
  scene.materials.push_back({"black", Rgb::gray(0)});
  return scene;
}
inline EnergyBalanceWatts emitterOverPlateBalance(double albedo) {
  const Vec3 top[] = {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}};
  const int n = 128;
  double first = 0, second = 0;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const double f = pointToPolygonFormFactor({(a + 0.5) / n, (b + 0.5) / n, 0}, {0, 0, 1}, top, {0, 0, -1});
      first += f / (n * n);
      second += f * f / (n * n);
    }
  EnergyBalanceWatts watts;
  watts.emitted = kPi;  // L_e = 1 in each channel: white, π W of luminance
  watts.absorbed = kPi * ((1 - albedo) * first + albedo * second);
  watts.escaped = watts.emitted - watts.absorbed;
  return watts;
}

// The solid angle a planar convex polygon subtends at a point, fanned into triangles, each by
// Van Oosterom & Strackee's formula (1983): tan(Ω/2) = |a·(b×c)| / (abc + (a·b)c + (a·c)b + (b·c)a).
// An isotropic point light of intensity I gives a polygon facing it the mean irradiance I·Ω/A
// (dΩ = cosθ dA / r²), whatever the polygon's size.
inline double solidAngle(const Vec3& point, const std::vector<Vec3>& polygon) {
  double omega = 0;
  for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
    const Vec3 a = polygon[0] - point, b = polygon[k] - point, c = polygon[k + 1] - point;
    const double la = length(a), lb = length(b), lc = length(c);
    const double numerator = std::fabs(dot(a, cross(b, c)));
    const double denominator = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
    omega += 2 * std::atan2(numerator, denominator);
  }
  return omega;
}

inline double relativeError(double value, double expected) { return std::fabs(value - expected) / std::fabs(expected); }

}  // namespace lambert::testing
