#pragma once
// Whether triangles in the plane overlap one another (lightmap charts, a file's coordinates):
// triangles inserted one by one into a uniform grid of buckets over a box; a query tests only the
// triangles in the buckets its bounding box touches (each once), by a separating-axis test over
// the six edge normals. Linear in the triangles for triangles of similar size, instead of all
// pairs; triangles of very different sizes fill many buckets each (the grid has at most 1024
// cells a side). Internal to mesh/lightmap_uvs.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "lambert/core/vec2.h"

namespace lambert {

class OverlapGrid {
 public:
  // A grid over the box [lo, hi] for about expectedTriangles triangles. Interiors that overlap by
  // no more than `tolerance` (touching along an edge or at a corner) do not count.
  OverlapGrid(Vec2 lo, Vec2 hi, std::size_t expectedTriangles, double tolerance);
  // The owner of a triangle already inserted that `t` (three corners, either winding) overlaps,
  // or -1.
  long overlapping(const Vec2* t);
  void insert(const Vec2* t, long owner);

 private:
  template <class F>
  void forCells(const Vec2* t, F&& f);

  Vec2 lo_;
  double tolerance_;
  int nx_ = 1, ny_ = 1;
  double sx_ = 1, sy_ = 1;
  std::vector<std::vector<std::uint32_t>> buckets_;
  std::vector<Vec2> triangles_;
  std::vector<long> owners_;
  std::vector<std::uint64_t> stamp_;
  std::uint64_t query_ = 0;
};

}  // namespace lambert
