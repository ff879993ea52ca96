#pragma once
// The light the surfaces bring to points on the scene's faces (lightmap texels), as the final
// gather brings it to the vertices (hierarchical/final_gather.h); the types that the engine's
// internal gathers return (engine/solution_internals.h), and optionally the weights that give it
// again from a later solution of the same hierarchy (a moved light's warm re-solve) as one sparse
// product: Σ weight × B̄_node over the node means (nodeMeanRadiosity) plus Σ weight × B_vertex
// over the close leaf sources' corners (vertexMesh()'s vertex radiosities).
#include <cstdint>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/mesh/vertex_radiosity.h"

namespace lambert {

// The leaf sources a final gather saw from close by (the vertex nearer than twice their bounding
// sphere's radius, as the gather opens nodes), as weights on their corner vertices: a vertex's irradiance from such a source is
// ∫ k(x, y) B(y) dA_y with B interpolated (bilinearly on a quad, linearly on a triangle) from the
// source's corner vertices' radiosities, instead of F(x → s) × B̄_s. The light across a leaf
// varies most where it meets another surface (the strip of wall under the ceiling is far darker
// than the wall leaf's mean) and a vertex beside that surface sees the strip nearest it with
// about half its hemisphere: with B̄_s, the Cornell box's room edges were 8–10% too bright.
// The corner radiosities are the gather's own results, so FinalGather::coupleNearField solves
// for them together.
struct NearFieldWeights {
  std::vector<std::uint32_t> start;   // per vertex and one more: vertex v's entries are [start[v], start[v + 1])
  std::vector<std::uint32_t> corner;  // per entry: a source's corner vertex
  std::vector<float> weight;          // per entry: ∫ k φ_corner dA × the source's visibility (dimensionless)
  std::vector<Rgb> meanPart;          // per vertex: Σ F × visibility × B̄_s over these sources (W/m²), in the gather
  std::size_t size() const { return weight.size(); }
};

// A gather's result as fixed weights on the node mean radiosities it read: per site, Σ weight ×
// B̄_node is what the gather returned (before its clamp at zero), less the close leaf sources that
// NearFieldWeights carries instead where those were asked for. The decisions the gather took from
// the radiosity (which sources to open, whose visibility to resolve, the shaped means' children)
// are frozen in the weights: after the light changes, the product is the gather the old decisions
// would give, the basis of lightmap updates without a new gather (bake/lightmap_updates.h).
struct GatherWeights {
  std::vector<std::uint32_t> start;  // per site and one more: site v's entries are [start[v], start[v + 1])
  std::vector<std::uint32_t> node;   // per entry: a hierarchy node, each at most once per site
  std::vector<float> weight;         // per entry: F × visibility (× the shaped mean's share), dimensionless
  std::size_t size() const { return weight.size(); }
  std::size_t bytes() const { return start.size() * sizeof(std::uint32_t) + node.size() * sizeof(std::uint32_t) + weight.size() * sizeof(float); }
};

// What pointGather (engine/solution_internals.h) computes: the sites alone (where a lightmap's
// texels are lit from), the surfaces' light there too, that and its weights, or the weights alone
// (no vertex final gather for the close sources' corners: only the light needs their radiosity).
enum class PointGatherRequest { Sites, Light, LightAndWeights, Weights };

struct PointGather {
  // The leaf of a site that no leaf holds (the hierarchy's kNoNode).
  static constexpr std::uint32_t kNoLeaf = 0xffffffffu;
  // Each point as it was gathered: on its leaf's plane, nudged off the leaf's edges toward its
  // centre (as vertex sites are), with the leaf's normal. Shadow rays to the lights start here.
  std::vector<VertexSite> sites;
  // Per site: the leaf it gathers through (an element of SolutionView::mesh()); kNoLeaf for a
  // vertex no leaf uses.
  std::vector<std::uint32_t> leaf;
  // Per point: the irradiance from the surfaces (links), W/m²; the lights' direct light not
  // included (empty for PointGatherRequest::Sites and Weights).
  std::vector<Rgb> fromSurfaces;
  // The offset shadow rays start above a site, along its normal (scene units).
  double rayEpsilon = 0;
  // With weights asked for: fromSurfaces = max(0, Σ nodes × node means + Σ near × corner radiosities).
  GatherWeights nodes;
  NearFieldWeights near;
};

}  // namespace lambert
