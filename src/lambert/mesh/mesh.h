#pragma once
// Patches: the finite elements radiosity is solved on. Each scene surface is split into a
// triangle fan and every triangle is bisected across its longest edge (seed 000) until no edge is
// longer than a limit. Vertices are shared between the patches of one surface, never across
// surfaces, so per-vertex averaging never blurs across a crease.
#include <array>
#include <cstdint>
#include <vector>

#include "lambert/core/vec3.h"
#include "lambert/scene/scene.h"

namespace lambert {

struct Patch {
  std::array<std::uint32_t, 3> vertices;  // indices into Mesh::positions, counter-clockwise
  std::uint32_t surface = 0;              // index into Scene::surfaces
  Vec3 normal;                            // unit, front side
  Vec3 centroid;
  double area = 0;                        // scene units²
};

struct Mesh {
  std::vector<Vec3> positions;
  std::vector<std::uint32_t> vertexSurface;  // the surface each vertex belongs to
  std::vector<Patch> patches;

  std::size_t numPatches() const { return patches.size(); }
  std::size_t numVertices() const { return positions.size(); }
  std::array<Vec3, 3> corners(std::size_t patch) const {
    const auto& v = patches[patch].vertices;
    return {positions[v[0]], positions[v[1]], positions[v[2]]};
  }
};

// Subdivides every surface until no patch edge is longer than maxEdgeLength (scene units).
Mesh subdivideScene(const Scene& scene, double maxEdgeLength);

// The edge length limit whose mesh has the fewest patches that are still at least targetPatches
// (the counts come in steps, so the result may have somewhat more).
double edgeLengthForPatchCount(const Scene& scene, std::size_t targetPatches);

// The scene's axis-aligned bounding box diagonal, in scene units.
double sceneDiagonal(const Scene& scene);

}  // namespace lambert
