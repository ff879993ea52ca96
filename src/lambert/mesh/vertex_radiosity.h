#pragma once
// Radiosity at mesh vertices from radiosity per patch, for Gouraud shading and vertex export.
// Each patch counts with the radiosity of its open part, B / openFraction, and its open area
// (geometry/coverage.h), so the dark floor under a block does not darken the floor around it.
//
// Interior vertices take the area-weighted average of the patches around them (the usual
// Gouraud averaging), which is second-order accurate there. At a vertex on a surface's border
// every patch lies on one side, so the average is biased toward the inside: a wall's top edge
// looks as lit as its patches' centres although no direct light reaches the very corner. There,
// as Cohen & Wallace recommend (Radiosity and Realistic Image Synthesis, §9.2), the value is
// extrapolated: a linear function of position is fitted by area-weighted least squares to the
// centroids of the patches within two rings of the vertex and evaluated at it, limited to the
// range those patches span widened by that range on each side (and never below zero), so a
// sharp shadow cannot throw it far off. Vertices are never shared across surfaces, so nothing is
// ever mixed across a crease.
#include <cstdint>
#include <array>
#include <span>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/mesh/mesh.h"

namespace lambert {

// The interpolation above for one mesh, with everything that depends on the geometry alone (the
// patches around each vertex, their weights, the border fits' weights) computed once, so that
// a mesh whose values change every frame (a moving light) interpolates in O(vertices).
class VertexInterpolation {
 public:
  explicit VertexInterpolation(const Mesh& mesh);
  // B at every vertex from B per patch (one per patch of the mesh it was made for).
  std::vector<Rgb> apply(const std::vector<Rgb>& patchRadiosity) const;

 private:
  struct Term {
    std::uint32_t patch;
    double weight;
  };
  struct Fit {
    std::uint32_t vertex, begin, end;  // its terms in fitTerms_; the same patches bound the clamp
  };
  std::size_t numPatches_ = 0;
  std::vector<double> patchScale_;           // 1 / openFraction (0 for a covered patch)
  std::vector<std::uint32_t> averageStart_;  // per vertex, into averageTerms_
  std::vector<Term> averageTerms_;
  std::vector<Term> fitTerms_;
  std::vector<Fit> fits_;
};

// VertexInterpolation(mesh).apply(patchRadiosity), for a mesh interpolated once.
std::vector<Rgb> vertexRadiosity(const Mesh& mesh, const std::vector<Rgb>& patchRadiosity);

// Where a quantity is evaluated "at" a vertex (the path tracer's reference and the hierarchical
// final gather): the vertex moved `nudge` scene units (at most half way) toward the centroid of
// one of its patches (vertexSitePatches), so as not to sit exactly on an edge shared with a
// perpendicular surface, where the irradiance jumps, with the area-weighted mean normal of its
// patches (zero for a vertex no patch uses). The point stays in that patch's plane: moved toward
// the mean of all its patches' centroids, a vertex of a convex curved surface went inside it (a
// UV sphere's, under every face round it), where every shadow ray meets the back of a face, and
// a lit sphere's vertices were all black. The patch is the most open one (geometry/coverage.h),
// so that a vertex on a contact line (a block's foot on the floor) is evaluated on the open
// side, whose light it shows (vertexRadiosity weighs the patches by their open part too): under
// the block the reference is black and the final gather is not, and that one Cornell-box vertex
// made a quarter of the default solve's squared error.
struct VertexSite {
  Vec3 point;
  Vec3 normal;
};
inline constexpr std::uint32_t kNoSitePatch = 0xffffffffu;
// Per vertex, the patch its site lies on: of the patches using it, the largest open fraction, then
// the smallest area (the hierarchical method's finest leaf, whose links are the finest), then the
// first; kNoSitePatch where none uses it.
std::vector<std::uint32_t> vertexSitePatches(const Mesh& mesh);
std::vector<VertexSite> vertexSites(const Mesh& mesh, double nudge);

// A per-vertex quantity looked up at ray hits: at(patch, x) is the patch's corner values
// interpolated over the fan triangle (0, j, j + 1) that holds x, as the rasterizer's Gouraud
// shading draws it (x is a hit, on the patch up to rounding: barycentrics are clamped). Each
// patch's corners and values are packed together in floats (two cache lines), since hemisphere
// rays land on patches in no order: gathered from the mesh's patch, position and value arrays, one
// lookup cost up to nine cache misses, 9% of a point-illuminance run (perf, illuminance_bench).
// An optional per-patch factor scales the patch's values (the meter folds in ρ).
class PatchInterpolation {
 public:
  PatchInterpolation(const Mesh& mesh, std::span<const Rgb> vertexValues, std::span<const Rgb> patchFactor = {});
  Rgb at(std::uint32_t patch, const Vec3& x) const;

 private:
  struct Record {
    std::array<float, 12> corners{};  // x, y, z of up to four corners
    std::array<float, 12> values{};   // r, g, b at each
    std::uint32_t numCorners = 0;
  };
  std::vector<Record> records_;
};

}  // namespace lambert
