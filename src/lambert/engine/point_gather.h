#pragma once
// The light the surfaces bring to points on the scene's faces (lightmap texels), as the final
// gather brings it to the vertices (engine/final_gather.h), and optionally the weights that give
// it again from a later solution of the same hierarchy (a moved light's warm re-solve) as one
// sparse product: Σ weight × B̄_node over the node means (SolutionView::nodeMeanRadiosity) plus
// Σ weight × B_vertex over the close leaf sources' corners (vertexMesh()'s vertex radiosities).
#include <cstdint>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/engine/final_gather.h"
#include "lambert/mesh/vertex_radiosity.h"

namespace lambert {

// What SolutionView::pointGather computes: the sites alone (where a lightmap's texels are lit
// from), the surfaces' light there too, that and its weights, or the weights alone (no vertex
// final gather for the close sources' corners: only the light needs their radiosity).
enum class PointGatherPart { Sites, Light, LightAndWeights, Weights };

struct PointGather {
  // Each point as it was gathered: on its leaf's plane, nudged off the leaf's edges toward its
  // centre (as vertex sites are), with the leaf's normal. Shadow rays to the lights start here.
  std::vector<VertexSite> sites;
  // Per site: the leaf it gathers through (an element of SolutionView::mesh()); kNoNode for a
  // vertex no leaf uses.
  std::vector<std::uint32_t> leaf;
  // Per point: the irradiance from the surfaces (links), W/m²; the lights' direct light not
  // included (empty for PointGatherPart::Sites and Weights).
  std::vector<Rgb> fromSurfaces;
  // The offset shadow rays start above a site, along its normal (scene units).
  double rayEpsilon = 0;
  // With weights asked for: fromSurfaces = max(0, Σ nodes × node means + Σ near × corner radiosities).
  GatherWeights nodes;
  NearFieldWeights near;
};

}  // namespace lambert
