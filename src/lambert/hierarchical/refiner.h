#pragma once
// The refinement of hierarchical radiosity (Hanrahan, Salzman & Aupperle 1991): which links
// there are (hierarchical/links.h says what one is), and which elements are split for them. Its
// own file because it is the method's one decision loop (waves of candidates judged by the
// oracle); the kernels that estimate a candidate are links.cpp's (hierarchical/link_estimator.h).
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
// Cost: one estimate per candidate (a few visibility rays; estimated in parallel, judged in
// order). It fails only for memory: a refinement whose links and nodes would not fit in
// LinkOptions::memoryLimitBytes stops at the wave that finds so (RefinementReport::memoryNeeded).
#include <cstdint>
#include <span>

#include "lambert/geometry/ray_caster.h"
#include "lambert/hierarchical/element_hierarchy.h"
#include "lambert/hierarchical/links.h"
#include "lambert/method/hierarchical_options.h"

namespace lambert {

class LinkShare;  // hierarchical/distributed_links.h

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
// only the candidate links into its own nodes (LinkShare::holds) and keeps those, and the ranks hand
// each other the elements they split, so that every rank holds the same hierarchy and the union
// of their links is the links one process makes; null: this process alone.
Links refineLinks(ElementHierarchy& hierarchy, const RayCaster& caster, double rayEpsilon,
                  std::span<const std::uint64_t> casterFace, const Links* previous,
                  std::span<const double> leafRadiosity, std::span<const double> leafOpenFraction, const LinkOptions& options,
                  RefinementReport& report, LinkShare* share = nullptr);

}  // namespace lambert
