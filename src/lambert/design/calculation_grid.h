#pragma once
// Calculation surfaces, where lighting design reads illuminance: a work plane (a horizontal plane
// at a height above the floor, over the room's footprint or an area given) and a grid on a chosen
// surface of the scene (a floor, a desk top, a wall), each a regular lattice of points at the
// centres of square-ish cells. Their statistics are the figures a lighting standard asks for:
// E_avg, E_min, E_max, the uniformity U₀ = E_min/E_avg, and E_min/E_max.
//
// Spacing. Unless given, the grid of EN 12464-1:2011 §4.4 (2021: §5.2.2, its annex): the largest
// cell p = 0.2 × 5^log10(d) m, d the area's longer side in metres (its shorter side where the
// longer is at least twice it), p at most 10 m; the number of cells along d is the whole number
// nearest d/p (at least one), the cells then d/n wide, and the other side gets the whole number
// of cells nearest its length over that width. A 4 m room: p = 0.2 × 5^0.602 = 0.53 m, 8 cells.
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/design/illuminance.h"
#include "lambert/scene/scene.h"

namespace lambert {

// EN 12464-1's largest grid cell, in metres, for an area of sides a and b metres.
double en12464GridSpacing(double aMetres, double bMetres);

struct CalculationGrid {
  std::string name;
  // Cell (i, j) of nu × nv has its centre at origin + axisU·(i + ½)·spacingU + axisV·(j + ½)·spacingV
  // (scene units; axisU, axisV unit and perpendicular) when that centre lies on the surface.
  Vec3 origin, axisU, axisV;
  double spacingU = 0, spacingV = 0;
  int nu = 0, nv = 0;
  std::vector<int> pointOfCell;           // nu·nv, row by row (j major): an index into points, or −1
  std::vector<CalculationPoint> points;   // the cells' points on the surface, facing its light
};

struct WorkPlaneSpec {
  std::string name = "work plane";
  double heightMetres = 0.8;  // above the floor: the scene's lowest point (EN 12464-1: 0.75 m for desks; 0.8 common)
  // The area, scene units, in the horizontal plane (scene x and z): lo, hi corners. None: the
  // scene's footprint (its bounding box), less marginMetres all round.
  std::optional<std::array<double, 4>> area;  // x0, z0, x1, z1
  double marginMetres = 0;   // border left out (EN 12464-1's 0.5 m band by walls, where asked)
  double spacingMetres = 0;  // 0: EN 12464-1's
};

// The work plane's lattice, facing up (+y, the scene's up).
Result<CalculationGrid> workPlaneGrid(const Scene& scene, const WorkPlaneSpec& spec);

struct SurfaceGridSpec {
  std::string surface;       // a surface's name, or a material's (every surface of that material)
  double spacingMetres = 0;  // 0: EN 12464-1's
  double offsetMetres = 0;   // the points lifted this far off the surface along its normal
};

// A lattice over the surfaces' bounding rectangle in the plane of their mean normal, keeping the
// cells whose centre projects into one of their faces; each point lies on that face (lifted by
// offsetMetres) with its normal. The faces should be roughly coplanar (a floor, a desk top); an
// Error names what to do when none is found.
Result<CalculationGrid> surfaceGrid(const Scene& scene, const SurfaceGridSpec& spec);

struct GridStatistics {
  std::size_t points = 0;
  double average = 0, minimum = 0, maximum = 0;  // lux (or whatever the values are)
  double uniformity = 0;                          // U₀ = E_min / E_avg (0 when E_avg is 0)
  double minOverMax = 0;                          // E_min / E_max (0 when E_max is 0)
};
GridStatistics gridStatistics(std::span<const double> values);

}  // namespace lambert
