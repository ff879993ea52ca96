#include "lambert/mesh/mesh.h"

#include <cmath>
#include <unordered_map>

#include "lambert/core/error.h"

namespace lambert {
namespace {

// Splits the triangles of one surface, sharing each edge midpoint between the two triangles on
// either side of the edge, so the result has no T-junctions.
class SurfaceSubdivider {
 public:
  SurfaceSubdivider(Mesh& mesh, std::uint32_t surface, bool twinned, double maxEdgeLength)
      : mesh_(mesh), surface_(surface), twinned_(twinned), maxEdgeSquared_(maxEdgeLength * maxEdgeLength) {}

  std::uint32_t addVertex(const Vec3& p) {
    mesh_.positions.push_back(p);
    mesh_.vertexSurface.push_back(surface_);
    return static_cast<std::uint32_t>(mesh_.positions.size() - 1);
  }

  void setFace(std::uint32_t face) { face_ = face; }

  void split(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const Vec3 pa = mesh_.positions[a], pb = mesh_.positions[b], pc = mesh_.positions[c];
    double ab = lengthSquared(pb - pa), bc = lengthSquared(pc - pb), ca = lengthSquared(pa - pc);
    double longest = std::fmax(ab, std::fmax(bc, ca));
    if (longest <= maxEdgeSquared_) {
      emit(a, b, c);
      return;
    }
    // Rotate so the longest edge is (a, b), then bisect it; winding is kept.
    if (bc == longest) return splitLongest(b, c, a);
    if (ca == longest) return splitLongest(c, a, b);
    splitLongest(a, b, c);
  }

 private:
  void splitLongest(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    std::uint32_t m = midpoint(a, b);
    split(a, m, c);
    split(m, b, c);
  }

  std::uint32_t midpoint(std::uint32_t a, std::uint32_t b) {
    std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
    auto [it, inserted] = midpoints_.try_emplace(key, 0);
    if (inserted) it->second = addVertex((mesh_.positions[a] + mesh_.positions[b]) * 0.5);
    return it->second;
  }

  void emit(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const std::uint32_t corners[3] = {a, b, c};
    mesh_.patches.push_back(makePatch(mesh_.positions, corners, surface_));
    mesh_.patches.back().face = face_;
    mesh_.patches.back().twinned = twinned_;
  }

  Mesh& mesh_;
  std::uint32_t surface_;
  bool twinned_;
  std::uint32_t face_ = 0;
  double maxEdgeSquared_;
  std::unordered_map<std::uint64_t, std::uint32_t> midpoints_;
};

}  // namespace

Patch makePatch(const std::vector<Vec3>& positions, std::span<const std::uint32_t> vertices, std::uint32_t surface) {
  LAMBERT_CHECK(vertices.size() == 3 || vertices.size() == 4);
  Patch patch;
  patch.numCorners = static_cast<std::uint32_t>(vertices.size());
  for (std::size_t k = 0; k < 4; ++k) patch.vertices[k] = vertices[std::min(k, vertices.size() - 1)];
  patch.surface = surface;
  const Vec3& origin = positions[vertices[0]];
  Vec3 normalSum, weightedCentroid;
  for (std::size_t k = 1; k + 1 < vertices.size(); ++k) {
    const Vec3& b = positions[vertices[k]];
    const Vec3& c = positions[vertices[k + 1]];
    Vec3 n = cross(b - origin, c - origin);
    double area = 0.5 * length(n);
    normalSum += n;
    patch.area += area;
    weightedCentroid += (origin + b + c) * (area / 3.0);
  }
  patch.normal = normalize(normalSum);
  patch.centroid = weightedCentroid / patch.area;
  return patch;
}

Mesh subdivideScene(const Scene& scene, double maxEdgeLength) {
  LAMBERT_CHECK(maxEdgeLength > 0);
  Mesh mesh;
  for (std::uint32_t s = 0; s < scene.surfaces.size(); ++s) {
    const Surface& surface = scene.surfaces[s];
    LAMBERT_CHECK(surface.vertices.size() >= 3);
    // One subdivider for all the surface's faces: an edge two faces share is split at the same
    // midpoint vertex for both, so the region's mesh is conforming across it.
    SurfaceSubdivider subdivider(mesh, s, surface.twin >= 0, maxEdgeLength);
    const auto first = static_cast<std::uint32_t>(mesh.positions.size());
    for (const Vec3& v : surface.vertices) subdivider.addVertex(v);
    const auto faces = surfaceFaces(surface);
    for (std::uint32_t f = 0; f < faces.size(); ++f) {
      const std::vector<std::uint32_t>& face = faces[f];
      LAMBERT_CHECK(face.size() >= 3);
      subdivider.setFace(f);
      for (std::size_t i = 1; i + 1 < face.size(); ++i) subdivider.split(first + face[0], first + face[i], first + face[i + 1]);
    }
  }
  return mesh;
}

double sceneDiagonal(const Scene& scene) {
  const Bounds bounds = sceneBounds(scene);
  return length(bounds.hi - bounds.lo);
}

double edgeLengthForPatchCount(const Scene& scene, std::size_t targetPatches) {
  // Patch count falls as the limit grows (in steps). Halve until the target is reached, then
  // bisect between the last two limits.
  double hi = sceneDiagonal(scene);
  double lo = hi;
  while (subdivideScene(scene, lo).numPatches() < targetPatches) {
    hi = lo;
    lo *= 0.5;
  }
  for (int iteration = 0; iteration < 40 && lo < hi; ++iteration) {
    double mid = 0.5 * (lo + hi);
    if (subdivideScene(scene, mid).numPatches() >= targetPatches)
      lo = mid;
    else
      hi = mid;
  }
  return lo;
}

}  // namespace lambert
