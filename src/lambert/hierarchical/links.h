#pragma once
// The links of hierarchical radiosity and the refinement that makes them (Hanrahan, Salzman &
// Aupperle 1991), from clusters down to elements (Smits, Arvo & Greenberg 1994; Sillion 1995).
//
// A link (r ← s) lets node r gather from node s: r's irradiance-like sum gains K_rs·B̄_s, where
// B̄_s is the area-weighted mean radiosity of the leaves under s (pull) and r passes what it
// gathered down to every leaf under it (push).
//   element ← element   K = the unoccluded form factor from r to polygon s, the exact point-
//                       to-polygon factor averaged over r at degree-2 quadrature points
//                       (formfactor/kernels.h, exact at any distance) × the share of unoccluded
//                       rays between stratified points of the two;
//   with a cluster      K = 1/A_r ∫_r Σ_f F(x→f) V B_f / B̄_s over the faces f of the source,
//                       by Monte Carlo over the link's own sample pairs: a receiving face and a
//                       source face chosen by the area they show each other (the source's also
//                       by its radiosity), a point on the receiving face, the exact point-to-
//                       polygon factor to the source face, and one visibility ray. Far apart it
//                       is the point-to-point transfer P_s(−ω) P_r(ω) / (π d² A_r) of Sillion
//                       1995's non-isotropic clusters (P: the area a node shows toward a
//                       direction); close by, where that kernel is 15–20% high, it stays exact
//                       on average, so links need only the nodes' boxes apart and neither
//                       cutting through the other's element plane. A receiver cluster passes its
//                       mean to every face inside it.
// Visibility is the share of unoccluded rays between stratified points on the two nodes,
// leaving out receiving points that are covered (the floor under a block): K is the irradiance
// of the receiver's open part. A ray is open where the first face it meets, run to just behind
// the source point, is the source's own face: of faces lying on one another (a two-sided face's
// back twin under a drawer front, a binder cover's lining), each point shows one.
//
// Refinement is breadth-first and deterministic: starting from the root cluster's link to itself
// (or, unclustered, from every pair of faces, HSA'91's O(n²) start), each candidate link is
// estimated (in parallel) and then judged in order by the BF oracle: B_s·ΔK·A_r, the power the
// link may move wrongly (not weighted by the receiver's albedo, so that what black surfaces
// absorb is counted as well as the rest), against linkError × the scene's total power, where ΔK is what K is
// uncertain by: between elements, the spread of the point factors over the receiver (what a
// parent's link hands its children alike; Lischinski, Tampieri & Greenberg 1994 bound the same
// variation), or the whole unoccluded K where visibility is partial (a shadow edge crosses);
// with a cluster, the whole point-to-point transfer between the centres (HSA'91's magnitude
// oracle; not the Monte Carlo K, whose noise would keep the links it underestimates). A link above it is replaced by the
// links of the larger node's children, or the receiver's where ΔK is its spread (a cluster
// opens, an element splits four ways while above the minimum area), until it is below or
// neither node can be split. Cluster links that see nothing are dropped; element links whose
// rays were all blocked are kept with K = 0, for the final gather to resolve at the vertices. receiverSide marks the links
// whose rays all got through (ΔK is the spread), which the final gather
// (hierarchical/final_gather.h) takes as unoccluded.
#include <cstdint>
#include <span>
#include <vector>

#include "lambert/core/communicator.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/hierarchical/element_hierarchy.h"
#include "lambert/hierarchical/options.h"

namespace lambert {


// Links grouped by receiver node (compressed rows over the hierarchy's nodes), sources in
// increasing order within each receiver.
struct Links {
  std::vector<std::uint32_t> start;   // per node, and one past the last: links of node i are [start[i], start[i+1])
  std::vector<std::uint32_t> source;
  std::vector<float> formFactor;      // K_rs, with visibility (0: an element pair whose rays were all blocked)
  std::vector<float> uncertainty;     // ΔK: what the oracle multiplies by B_s A_r (see above); for a cluster link, its unoccluded K
  std::vector<std::uint8_t> receiverSide;  // ΔK is K's spread over the receiver (every ray got through): refining splits the receiver

  std::size_t size() const { return source.size(); }
  std::size_t bytes() const;
};

// A distributed refinement's share of the hierarchy: the ranks meet through the communicator,
// and this rank refines and keeps the links into the nodes marked mine (per node of the
// hierarchy: those over its leaves, and under them). The refinement marks the nodes it adds as
// their parents are.
struct LinkShare {
  Communicator* communicator = nullptr;
  std::vector<std::uint8_t> mine;
};

struct RefinementReport {
  std::uint64_t initialLinks = 0;   // the candidates the refinement started from
  std::uint64_t estimated = 0;      // candidate links estimated
  std::uint64_t rays = 0;           // visibility rays
  std::uint64_t elementsSplit = 0;
  std::uint64_t clusterLinks = 0;   // kept links with a cluster at either end
  double seconds = 0;
  // Non-zero when refinement stopped because its links and nodes would need more memory than
  // LinkOptions::memoryLimitBytes allows: the estimate, in bytes. The links returned then are
  // incomplete.
  double memoryNeeded = 0;
};

// Refines links over `hierarchy` (splitting its elements as needed) for leaf radiosities given
// as their largest channel (W/m²), one per current leaf, and the leaves' open fractions
// (Patch::openFraction): only the points of a leaf partly covered, and of its descendants, are
// asked whether they are covered.
// With `previous` (links of the same hierarchy before more splits), those links are judged again
// with the new radiosities and refined further where they now carry too much; without, the
// refinement starts afresh. Numbers the new leaves before returning.
// casterFace: per patch of the mesh `caster` was built from, its face as surface << 32 | face:
// a visibility ray counts as open only where the first face it meets at the source point is the
// source's own, so of faces lying on one another only the one a ray meets first is seen.
// share: a distributed solve's (docs/distributed.md): every rank calls this alike; each refines
// only the candidate links into its own nodes (share->mine) and keeps those, and the ranks hand
// each other the elements they split, so that every rank holds the same hierarchy and the union
// of their links is the links one process makes; null: this process alone.
Links refineLinks(ElementHierarchy& hierarchy, const RayCaster& caster, double rayEpsilon,
                  std::span<const std::uint64_t> casterFace, const Links* previous,
                  std::span<const double> leafRadiosity, std::span<const double> leafOpenFraction, const LinkOptions& options,
                  RefinementReport& report, LinkShare* share = nullptr);

// The minimum element area the options give for this hierarchy.
double minimumElementArea(const ElementHierarchy& hierarchy, const LinkOptions& options);

}  // namespace lambert
