#include "lambert/design/calculation_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lambert {
namespace {

// Cells along two sides of lu × lv metres: EN 12464-1's rule from its largest cell p, or a given
// spacing on both sides.
std::pair<int, int> cellCounts(double lu, double lv, double spacingMetres) {
  auto count = [](double length, double cell) { return std::max(1, static_cast<int>(std::lround(length / cell))); };
  if (spacingMetres > 0) return {count(lu, spacingMetres), count(lv, spacingMetres)};
  const double p = en12464GridSpacing(lu, lv);
  const bool uLonger = lu >= lv;
  const double longer = uLonger ? lu : lv, shorter = uLonger ? lv : lu;
  // The relevant side d is the longer, or the shorter where the longer is at least twice it.
  const bool relevantIsLonger = longer < 2 * shorter;
  const double d = relevantIsLonger ? longer : shorter, other = relevantIsLonger ? shorter : longer;
  const int nd = count(d, p);
  const int nother = count(other, d / nd);
  const bool relevantIsU = relevantIsLonger == uLonger;
  return relevantIsU ? std::pair{nd, nother} : std::pair{nother, nd};
}

// Whether (u, v) lies inside the 2-D polygon (crossing number; either winding).
bool inside2d(const std::vector<std::pair<double, double>>& polygon, double u, double v) {
  bool in = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const auto [ui, vi] = polygon[i];
    const auto [uj, vj] = polygon[j];
    if ((vi > v) != (vj > v) && u < (uj - ui) * (v - vi) / (vj - vi) + ui) in = !in;
  }
  return in;
}

}  // namespace

double en12464GridSpacing(double aMetres, double bMetres) {
  const double longer = std::max(aMetres, bMetres), shorter = std::min(aMetres, bMetres);
  const double d = longer >= 2 * shorter ? shorter : longer;
  if (!(d > 0)) return 0;
  return std::min(10.0, 0.2 * std::pow(5.0, std::log10(d)));
}

Result<CalculationGrid> workPlaneGrid(const Scene& scene, const WorkPlaneSpec& spec) {
  if (scene.surfaces.empty()) return Error{"work plane \"" + spec.name + "\": the scene has no surfaces"};
  const Bounds bounds = sceneBounds(scene);
  const double unitsPerMetre = 1 / scene.metresPerUnit;
  const double elevation = bounds.lo.y + spec.heightMetres * unitsPerMetre;
  if (!(spec.heightMetres >= 0) || !(elevation < bounds.hi.y))
    return Error{"work plane \"" + spec.name + "\": a height of " + std::to_string(spec.heightMetres) +
                 " m above the floor is outside the scene, which is " +
                 std::to_string((bounds.hi.y - bounds.lo.y) * scene.metresPerUnit) + " m tall"};
  std::array<double, 4> area = spec.area.value_or(std::array<double, 4>{bounds.lo.x, bounds.lo.z, bounds.hi.x, bounds.hi.z});
  if (!spec.area) {
    const double margin = spec.marginMetres * unitsPerMetre;
    area = {area[0] + margin, area[1] + margin, area[2] - margin, area[3] - margin};
  }
  if (!(area[2] > area[0] && area[3] > area[1]))
    return Error{"work plane \"" + spec.name + "\": its area is empty (x " + std::to_string(area[0]) + " to " + std::to_string(area[2]) +
                 ", z " + std::to_string(area[1]) + " to " + std::to_string(area[3]) + " scene units); give a smaller margin or an area"};
  CalculationGrid grid;
  grid.name = spec.name;
  grid.origin = {area[0], elevation, area[1]};
  grid.axisU = {1, 0, 0};
  grid.axisV = {0, 0, 1};
  const double lu = area[2] - area[0], lv = area[3] - area[1];
  std::tie(grid.nu, grid.nv) = cellCounts(lu * scene.metresPerUnit, lv * scene.metresPerUnit, spec.spacingMetres);
  grid.spacingU = lu / grid.nu;
  grid.spacingV = lv / grid.nv;
  grid.pointOfCell.assign(static_cast<std::size_t>(grid.nu) * grid.nv, -1);
  for (int j = 0; j < grid.nv; ++j)
    for (int i = 0; i < grid.nu; ++i) {
      grid.pointOfCell[static_cast<std::size_t>(j) * grid.nu + i] = static_cast<int>(grid.points.size());
      grid.points.push_back({grid.origin + grid.axisU * ((i + 0.5) * grid.spacingU) + grid.axisV * ((j + 0.5) * grid.spacingV), {0, 1, 0}});
    }
  return grid;
}

Result<CalculationGrid> surfaceGrid(const Scene& scene, const SurfaceGridSpec& spec) {
  struct Face {
    std::vector<Vec3> polygon;
    Vec3 normal;
    std::vector<std::pair<double, double>> projected;
    double lo[2], hi[2];
  };
  std::vector<Face> faces;
  Vec3 areaVector;
  for (const Surface& surface : scene.surfaces) {
    const bool named = surface.name == spec.surface;
    const bool ofMaterial = surface.material >= 0 && static_cast<std::size_t>(surface.material) < scene.materials.size() &&
                            scene.materials[surface.material].name == spec.surface;
    const bool twin = surface.name.size() > 7 && surface.name.ends_with(" (back)");
    if (!named && !(ofMaterial && !twin)) continue;
    for (const std::vector<std::uint32_t>& f : surfaceFaces(surface)) {
      Face face;
      face.polygon = facePositions(surface, f);
      const Vec3 a = polygonAreaVector(face.polygon);
      if (!(length(a) > 0)) continue;
      face.normal = normalize(a);
      areaVector += a;
      faces.push_back(std::move(face));
    }
  }
  if (faces.empty()) {
    std::string names;
    for (std::size_t s = 0; s < scene.surfaces.size() && s < 8; ++s) names += (s ? ", \"" : "\"") + scene.surfaces[s].name + "\"";
    return Error{"grid on \"" + spec.surface + "\": no surface or material of that name (surfaces: " + names +
                 (scene.surfaces.size() > 8 ? ", …" : "") + "; `lambert info` lists them)"};
  }
  if (!(length(areaVector) > 0)) return Error{"grid on \"" + spec.surface + "\": its faces face every way (a closed object); choose one flat surface"};
  const Vec3 n = normalize(areaVector);
  Vec3 u, v;
  orthonormalBasis(n, u, v);
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, height = 0, weight = 0;
  for (Face& face : faces) {
    face.lo[0] = face.lo[1] = INFINITY;
    face.hi[0] = face.hi[1] = -INFINITY;
    for (const Vec3& p : face.polygon) {
      const double pu = dot(p, u), pv = dot(p, v);
      face.projected.emplace_back(pu, pv);
      face.lo[0] = std::min(face.lo[0], pu), face.hi[0] = std::max(face.hi[0], pu);
      face.lo[1] = std::min(face.lo[1], pv), face.hi[1] = std::max(face.hi[1], pv);
      height += dot(p, n);
      weight += 1;
    }
    for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], face.lo[k]), hi[k] = std::max(hi[k], face.hi[k]);
  }
  CalculationGrid grid;
  grid.name = spec.surface;
  grid.axisU = u;
  grid.axisV = v;
  grid.origin = u * lo[0] + v * lo[1] + n * (height / weight);
  const double lu = hi[0] - lo[0], lv = hi[1] - lo[1];
  if (!(lu > 0 && lv > 0)) return Error{"grid on \"" + spec.surface + "\": its faces have no extent across their normal"};
  std::tie(grid.nu, grid.nv) = cellCounts(lu * scene.metresPerUnit, lv * scene.metresPerUnit, spec.spacingMetres);
  grid.spacingU = lu / grid.nu;
  grid.spacingV = lv / grid.nv;
  grid.pointOfCell.assign(static_cast<std::size_t>(grid.nu) * grid.nv, -1);
  const double lift = spec.offsetMetres / scene.metresPerUnit;
  for (int j = 0; j < grid.nv; ++j)
    for (int i = 0; i < grid.nu; ++i) {
      const double cu = lo[0] + (i + 0.5) * grid.spacingU, cv = lo[1] + (j + 0.5) * grid.spacingV;
      for (const Face& face : faces) {
        if (cu < face.lo[0] || cu > face.hi[0] || cv < face.lo[1] || cv > face.hi[1] || !inside2d(face.projected, cu, cv)) continue;
        // Onto the face's own plane along the mean normal.
        const Vec3 c = u * cu + v * cv + n * (height / weight);
        const double along = dot(n, face.normal);
        if (!(std::fabs(along) > 1e-6)) continue;
        const Vec3 onFace = c + n * (dot(face.polygon[0] - c, face.normal) / along);
        grid.pointOfCell[static_cast<std::size_t>(j) * grid.nu + i] = static_cast<int>(grid.points.size());
        grid.points.push_back({onFace + face.normal * lift, face.normal});
        break;
      }
    }
  if (grid.points.empty()) return Error{"grid on \"" + spec.surface + "\": no cell centre lies on its faces; give a smaller spacing"};
  return grid;
}

GridStatistics gridStatistics(std::span<const double> values) {
  GridStatistics s;
  s.points = values.size();
  if (values.empty()) return s;
  double sum = 0;
  s.minimum = INFINITY;
  s.maximum = -INFINITY;
  for (double x : values) {
    sum += x;
    s.minimum = std::min(s.minimum, x);
    s.maximum = std::max(s.maximum, x);
  }
  s.average = sum / static_cast<double>(values.size());
  s.uniformity = s.average > 0 ? s.minimum / s.average : 0;
  s.minOverMax = s.maximum > 0 ? s.minimum / s.maximum : 0;
  return s;
}

}  // namespace lambert
