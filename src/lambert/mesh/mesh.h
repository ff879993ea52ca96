#pragma once
// Patches: the finite elements radiosity is solved on, each a planar convex polygon of three or
// four corners. subdivideScene splits every surface into a triangle fan and bisects each triangle
// across its longest edge until no edge is longer than a limit; the adaptive quad-tree
// (flat/quadtree.h) makes quads. Vertices are shared between the patches of one surface, never
// across surfaces, so per-vertex averaging never blurs across a crease.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "lambert/core/vec3.h"
#include "lambert/scene/scene.h"

namespace lambert {

// A patch's corner positions, in order.
struct PatchCorners {
  std::array<Vec3, 4> points;
  std::size_t count = 3;

  const Vec3& operator[](std::size_t k) const { return points[k]; }
  std::size_t size() const { return count; }
  const Vec3* begin() const { return points.data(); }
  const Vec3* end() const { return points.data() + count; }
  operator std::span<const Vec3>() const { return {points.data(), count}; }
};

struct Patch {
  std::array<std::uint32_t, 4> vertices{};  // indices into Mesh::positions, counter-clockwise
  std::uint32_t numCorners = 3;             // 3 (triangle) or 4 (quad)
  std::uint32_t surface = 0;                // index into Scene::surfaces
  std::uint32_t face = 0;                   // index into the surface's faces (uniform meshing)
  // Its surface has a twin lying back to back (Surface::twin): a ray or a camera that meets this
  // patch's back meets the twin's front there instead, so the back is never what is seen.
  bool twinned = false;
  Vec3 normal;                            // unit, front side
  Vec3 centroid;
  double area = 0;                        // scene units²
  // Share of the patch not covered by other geometry (the floor under a block, the ceiling above
  // a light panel): its light falls on this part only. 1 until measured (geometry/coverage.h).
  double openFraction = 1;
};

struct Mesh {
  std::vector<Vec3> positions;
  std::vector<std::uint32_t> vertexSurface;  // the surface each vertex belongs to
  std::vector<Patch> patches;

  std::size_t numPatches() const { return patches.size(); }
  std::size_t numVertices() const { return positions.size(); }
  std::span<const std::uint32_t> cornerIndices(std::size_t patch) const {
    return {patches[patch].vertices.data(), patches[patch].numCorners};
  }
  PatchCorners corners(std::size_t patch) const {
    PatchCorners c;
    c.count = patches[patch].numCorners;
    for (std::size_t k = 0; k < c.count; ++k) c.points[k] = positions[patches[patch].vertices[k]];
    return c;
  }
};

// A patch over the given vertices (3 or 4, counter-clockwise), with its area, unit normal and
// area centroid computed from their positions.
Patch makePatch(const std::vector<Vec3>& positions, std::span<const std::uint32_t> vertices, std::uint32_t surface);

// Subdivides every surface until no patch edge is longer than maxEdgeLength (scene units).
Mesh subdivideScene(const Scene& scene, double maxEdgeLength);

// The edge length limit whose mesh has the fewest patches that are still at least targetPatches
// (the counts come in steps, so the result may have somewhat more).
double edgeLengthForPatchCount(const Scene& scene, std::size_t targetPatches);

// The scene's axis-aligned bounding box diagonal, in scene units.
double sceneDiagonal(const Scene& scene);

}  // namespace lambert
