#pragma once
// The final gather of hierarchical radiosity: the irradiance at each vertex of the leaf mesh,
// gathered over the links of a leaf the vertex bounds and of that leaf's ancestors, with every
// link's kernel evaluated at the vertex itself instead of averaged over the receiver (Smits,
// Arvo & Greenberg 1994, §6; Lischinski, Tampieri & Greenberg 1993 gather the same way at
// their final mesh's points).
//
// A link hands every leaf under its receiver the same irradiance K·B̄_s, so without this the
// leaves' values are constant across whatever a coarse link covers, and interpolating them at
// the vertices (mesh/vertex_radiosity.h) cannot show how the light varies there: the dark rim of
// a wall below the ceiling, a floor's corners, a block's contact shadow. Here the sources are
// the nodes the oracle chose (their mean radiosity B̄_s), opened to their children (whose means
// are pulled too) where a node's bounding sphere is wider than half its distance from the
// vertex: a cluster always, an element only where its children can change the vertex's
// irradiance by more than 10⁻³ of what the unopened sources give, F(x → s) × (the spread of the
// leaf radiosities under s, or its brightest leaf where the rays to s disagree). The polygon
// factor is additive, so a uniform, uniformly visible element gives the same whole; long thin
// ones (lamp strips, whose spheres are as long as they are) are not opened to their leaves by
// every vertex nearby. The receiver is the point:
//   element source   the exact point-to-polygon factor from the vertex to s (formfactor/kernels.h)
//                    × visibility: the share of unoccluded rays from the vertex to stratified
//                    points on s (the link's own rays start elsewhere on the receiver: a vertex
//                    on its rim may be in a penumbra they all missed, or lit where they were all
//                    blocked; refinement keeps element links whose rays were all blocked, with
//                    K = 0, for this);
//   cluster source   P_s(−ω) max(0, n·ω) / (π d²) × the link's visibility.
// A vertex is evaluated where the path tracer's reference evaluates it (vertexSites: nudged
// into its own surface) and gathers through the adjacent leaf with the largest open fraction,
// then the smallest (whose links are the finest).
#include <cstdint>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/formfactor/links.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/mesh/element_hierarchy.h"
#include "lambert/mesh/vertex_radiosity.h"

namespace lambert {

// What one final gather did, summed over the vertices (and the most at any one vertex).
struct FinalGatherCounts {
  std::uint64_t vertices = 0;         // vertices gathered (those with a leaf)
  std::uint64_t sourcesGathered = 0;  // source nodes whose factor was evaluated at a vertex
  std::uint64_t sourcesOpened = 0;    // source nodes taken through their children instead
  std::uint64_t visibilityRays = 0;   // rays cast from the vertices to sources
  std::uint64_t maxSourcesGathered = 0, maxVisibilityRays = 0;  // at one vertex
};

class FinalGather {
 public:
  // The references must outlive this object and stay unchanged while it is used.
  FinalGather(const ElementHierarchy& hierarchy, const ElementHierarchy::LeafMesh& leaves, const Links& links,
              const RayCaster& caster, double rayEpsilon, double nudge, int visibilityRays, std::uint64_t seed);

  // Per vertex of the leaf mesh: the irradiance Σ K(x, s) B̄_s the links bring (W/m²), from the
  // radiosity every node shows (HierarchicalTransport::pull, W/m²).
  // counts, if given, receives what the gather did.
  std::vector<Rgb> irradiance(const std::vector<Rgb>& nodeMeanRadiosity, FinalGatherCounts* counts = nullptr) const;

  const std::vector<VertexSite>& sites() const { return sites_; }
  // The leaf each vertex gathers through (its patch index in the leaf mesh); kNoNode if none.
  const std::vector<std::uint32_t>& gatheringLeaf() const { return leaf_; }

 private:
  // The share of rays from the vertex to stratified points on the source that get through, each
  // weighted by the point-to-point kernel; with penumbraRays, more where the first ones disagree.
  // Adds the rays cast to raysCast.
  double visibility(std::uint32_t vertex, std::uint32_t link, const HierarchyNode& source, std::uint32_t& raysCast,
                    bool penumbraRays = false) const;

  const ElementHierarchy& hierarchy_;
  const Links& links_;
  const RayCaster& caster_;
  double epsilon_;
  int rays_;
  std::uint64_t seed_;
  std::vector<VertexSite> sites_;
  std::vector<std::uint32_t> leaf_;
};

}  // namespace lambert
