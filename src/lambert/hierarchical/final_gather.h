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
//   cluster source   I_s(−ω) max(0, n·ω) / (π d²) × the link's visibility, with ω and d toward
//                    the power-weighted centroid of its leaves and I_s(−ω) = Σ_axis |ω_axis| × the
//                    power its leaves send toward that side of the axis (B̄_s P_s(−ω) where its
//                    radiosity is uniform: a luminaire shows the floor its emitting face); where
//                    some of the link's rays were blocked, the share of rays from the site to
//                    points on the faces inside s, picked by area, that get through (a point
//                    beside an occluder sees past it where the receiver's mean did not): at
//                    points for every such source, at vertices for the largest, until those left
//                    could bring 2% of the vertex's light together.
// A vertex is evaluated where the path tracer's reference evaluates it (vertexSites: nudged
// into its own surface) and gathers through the adjacent leaf with the largest open fraction,
// then the smallest (whose links are the finest).
//
// Its files: final_gather.cpp (the traversal, site by site), gather_visibility.cpp (the rays from
// a site to a source), near_field.cpp (the close sources' corners), final_gather_outputs.h (what
// a gather hands back beside the irradiance).
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/method/point_gather.h"
#include "lambert/hierarchical/links.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/hierarchical/element_hierarchy.h"
#include "lambert/mesh/vertex_radiosity.h"

namespace lambert {

// The visibility values a final gather computed: each is fixed by a vertex, a link, a source
// node and whether penumbra rays were added, over one hierarchy, its links and its leaf mesh's
// vertices; the light never enters. A later gather over the same ones (the link cache's key,
// hierarchical/link_cache.h) reads them instead of casting their rays again, and gets the same bits.
// Entries are grouped by vertex, and within a vertex ordered by (link, source, penumbra).
struct GatherVisibility {
  static constexpr std::uint32_t kPenumbra = 0x80000000u;  // flag in `source`'s top bit
  std::vector<std::uint32_t> start;   // per vertex and one more: vertex v's entries are [start[v], start[v + 1])
  std::vector<std::uint32_t> link;    // per entry: the link (an index into Links)
  std::vector<std::uint32_t> source;  // per entry: the source node, | kPenumbra with penumbra rays
  std::vector<double> seen;           // per entry: FinalGather's visibility (a share of rays, 0 to 1)
  std::size_t numVertices() const { return start.empty() ? 0 : start.size() - 1; }
  std::size_t size() const { return seen.size(); }
  // The value for a vertex, link and flagged source, or nullptr.
  const double* find(std::uint32_t vertex, std::uint32_t link, std::uint32_t flaggedSource) const;
};

// What FinalGather::coupleNearField did: its BiCGSTAB iterations, whether they converged (if not,
// the uncoupled gather was returned) and the rows its contraction bound scaled.
inline constexpr int kNearFieldMaxIterations = 1000;
inline constexpr double kNearFieldTolerance = 1e-6;
struct NearFieldCoupling {
  int iterations = 0;
  bool converged = true;
  std::size_t rowsScaled = 0;
};

// What one final gather did, summed over the vertices (and the most at any one vertex).
struct FinalGatherCounts {
  std::uint64_t vertices = 0;         // vertices gathered (those with a leaf)
  std::uint64_t sourcesGathered = 0;  // source nodes whose factor was evaluated at a vertex
  std::uint64_t sourcesOpened = 0;    // source nodes taken through their children instead
  std::uint64_t visibilityRays = 0;   // rays cast from the vertices to sources
  std::uint64_t visibilityKnown = 0;  // visibility values read from a GatherVisibility instead
  std::uint64_t maxSourcesGathered = 0, maxVisibilityRays = 0;  // at one vertex
  // Another gather's, at other vertices, added.
  void add(const FinalGatherCounts& other) {
    vertices += other.vertices;
    sourcesGathered += other.sourcesGathered;
    sourcesOpened += other.sourcesOpened;
    visibilityRays += other.visibilityRays;
    visibilityKnown += other.visibilityKnown;
    maxSourcesGathered = std::max(maxSourcesGathered, other.maxSourcesGathered);
    maxVisibilityRays = std::max(maxVisibilityRays, other.maxVisibilityRays);
  }
};

class FinalGather {
 public:
  // The references must outlive this object and stay unchanged while it is used.
  // At the leaf mesh's vertices (vertexSites, nudged by `nudge`), each through gatheringLeaves'.
  FinalGather(const ElementHierarchy& hierarchy, const ElementHierarchy::LeafMesh& leaves, const Links& links,
              const RayCaster& caster, double rayEpsilon, double nudge, int visibilityRays, std::uint64_t seed);
  // At any points on the leaves (a lightmap's texels), each through the leaf (its patch index in
  // the leaf mesh) that holds it. Visibility rays are drawn per site index. resolveClusterVisibility:
  // a cluster source whose link's rays were partly blocked is seen through rays from each site
  // (points, whose values are shown one by one), else with the link's visibility (vertices, as the
  // constructor above gathers them).
  FinalGather(const ElementHierarchy& hierarchy, const ElementHierarchy::LeafMesh& leaves, const Links& links,
              const RayCaster& caster, double rayEpsilon, std::vector<VertexSite> sites, std::vector<std::uint32_t> leafOfSite,
              int visibilityRays, std::uint64_t seed, bool resolveClusterVisibility);
  // Per vertex: the adjacent leaf it gathers through, the one its site lies on (mesh/
  // vertex_radiosity.h vertexSitePatches: the largest open fraction, then the smallest, whose
  // links are the finest); kNoNode for a vertex no leaf uses.
  static std::vector<std::uint32_t> gatheringLeaves(const Mesh& mesh);
  // The same gather (sites, links, rays) through other leaves, one per site (kNoNode: the site is
  // not gathered): a distributed rank gathers its own sites alone.
  FinalGather throughLeaves(std::vector<std::uint32_t> leafOfSite) const;

  // Per vertex of the leaf mesh: the irradiance Σ K(x, s) B̄_s the links bring (W/m²), from the
  // radiosity every node shows (HierarchicalTransport::pull, W/m²).
  // counts, if given, receives what the gather did. known, if given, holds visibility values of an
  // earlier gather over the same hierarchy, links and vertices, read instead of cast again; record,
  // if given, receives every visibility value this gather used (those read included).
  // near, if given, receives the close leaf sources' weights (their F × B̄_s stays in the result).
  // weights, if given, receives the result's weights on the node means (without the close leaf
  // sources where near is given).
  std::vector<Rgb> irradiance(const std::vector<Rgb>& nodeMeanRadiosity, FinalGatherCounts* counts = nullptr,
                              const GatherVisibility* known = nullptr, GatherVisibility* record = nullptr,
                              NearFieldWeights* near = nullptr, GatherWeights* weights = nullptr) const;
  // The irradiance at sites whose close sources' corners have known radiosities (a lightmap's
  // texels, the vertices solved): gathered − meanPart + Σ weight × cornerRadiosity[corner].
  static std::vector<Rgb> withCorners(const std::vector<Rgb>& gathered, const NearFieldWeights& near,
                                      const std::vector<Rgb>& cornerRadiosity);
  // The irradiance at every vertex with each close leaf source's light taken from its corners'
  // radiosities, B_u = emitted_u + ρ_u (E_u + direct_u) (per vertex, W/m²), solved by BiCGSTAB
  // (Eigen, matrix-free) from `gathered` (the gather's result with B̄_s) until the residual is
  // kNearFieldTolerance of the right-hand side's. Rows whose ρ Σ w exceed the solve's contraction
  // bound are scaled to it, so that the system has one solution; should the solver still not
  // converge within kNearFieldMaxIterations, `gathered` itself is returned (each close source at
  // its mean) and report says so. Returns the irradiance from the surfaces (direct light from
  // the lights not included); report, if given, receives what the coupling did.
  static std::vector<Rgb> coupleNearField(const std::vector<Rgb>& gathered, const NearFieldWeights& near,
                                          std::span<const Rgb> emitted, std::span<const Rgb> albedo,
                                          std::span<const Rgb> direct, NearFieldCoupling* report = nullptr);

  const std::vector<VertexSite>& sites() const { return sites_; }
  // The leaf each vertex gathers through (its patch index in the leaf mesh); kNoNode if none.
  const std::vector<std::uint32_t>& gatheringLeaf() const { return leaf_; }

 private:
  class SiteGather;  // one site's gather, step by step (final_gather.cpp)

  // The share of rays from the vertex to stratified points on the source that get through, each
  // weighted by the point-to-point kernel; with penumbraRays, more where the first ones disagree.
  // Adds the rays cast to raysCast.
  double visibility(std::uint32_t vertex, std::uint32_t link, std::uint32_t source, std::uint32_t& raysCast,
                    bool penumbraRays = false) const;

  // Source s's mean radiosity as the vertex weighs it: its descendants' means, each by its
  // point kernel × area, kShapeDepth levels down (final_gather.cpp).
  Rgb shapedMean(const VertexSite& site, std::uint32_t s, const std::vector<Rgb>& mean, int depth = 0) const;
  // The same mean as weights on those descendants, `scale` times each, appended to `out`.
  void shapedWeights(const VertexSite& site, std::uint32_t s, double scale, std::vector<std::pair<std::uint32_t, double>>& out,
                     int depth = 0) const;
  const ElementHierarchy& hierarchy_;
  const Links& links_;
  const RayCaster& caster_;
  double epsilon_;
  int rays_;
  std::uint64_t seed_;
  bool resolveClusterVisibility_;
  const Mesh& mesh_;
  std::vector<VertexSite> sites_;
  std::vector<std::uint32_t> leaf_;
};

}  // namespace lambert
