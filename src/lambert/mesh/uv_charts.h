#pragma once
// The charts of lightmap_uvs (mesh/lightmap_uvs.h): each surface's faces cut into pieces that lie
// flat in the plane without overlapping themselves, each turned to its minimum-area bounding
// rectangle. mesh/uv_charts.cpp says how; internal to mesh/lightmap_uvs.
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "lambert/core/vec2.h"
#include "lambert/core/vec3.h"
#include "lambert/scene/scene.h"

namespace lambert {

// Per-surface geometry: faces, their normals, areas, centroids and edge neighbours.
struct SurfaceGeometry {
  const Surface* surface = nullptr;
  std::vector<std::vector<std::uint32_t>> faces;
  std::vector<Vec3> normal, centroid;
  std::vector<double> area;
  // Neighbours across edges shared by exactly two faces: face f's are neighbours[start[f] .. start[f + 1]).
  std::vector<std::uint32_t> start;
  std::vector<std::pair<std::uint32_t, double>> neighbours;  // (face, shared edge length)
  std::vector<double> perimeter;

  explicit SurfaceGeometry(const Surface& s);
  double sharedEdgeLength(std::uint32_t f, std::uint32_t g) const;
};

// Faces of one surface laid flat: their corners in scene units, turned to the chart's
// minimum-area bounding rectangle (wider than tall) at the origin.
struct Chart {
  std::uint32_t surface = 0;
  std::vector<std::uint32_t> faces;      // into surfaceFaces(surface)
  std::vector<std::uint32_t> cornerStart;  // face k's corners are corners[cornerStart[k] ..)
  std::vector<Vec2> corners;               // scene units; bounding box [0, width] × [0, height]
  double width = 0, height = 0;
  double area = 0;                       // the faces' area, scene units²
  bool conformal = false;
};

// Charts made, by kind, and the splits of maps that failed.
struct ChartStats {
  std::size_t planar = 0, conformal = 0, splits = 0;
};

// Every surface's charts, in surface order; `stats` counts them and the splits.
std::vector<Chart> buildCharts(const Scene& scene, ChartStats& stats);

}  // namespace lambert
