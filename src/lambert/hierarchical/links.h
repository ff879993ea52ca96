#pragma once
// The links of hierarchical radiosity (Hanrahan, Salzman & Aupperle 1991), from clusters down to
// elements (Smits, Arvo & Greenberg 1994; Sillion 1995): what a link is, and the kernels that
// estimate one (links.cpp, behind hierarchical/link_estimator.h). hierarchical/refiner.h decides
// which links there are.
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
#include <array>
#include <cstdint>
#include <vector>

#include "lambert/hierarchical/element_hierarchy.h"
#include "lambert/method/hierarchical_options.h"

namespace lambert {

// Links grouped by receiver node (compressed rows over the hierarchy's nodes), sources in
// increasing order within each receiver.
struct Links {
  std::vector<std::uint32_t> start;   // per node, and one past the last: links of node i are [start[i], start[i+1])
  std::vector<std::uint32_t> source;
  std::vector<float> formFactor;      // K_rs, with visibility (0: an element pair whose rays were all blocked)
  std::vector<float> uncertainty;     // ΔK: what the oracle multiplies by B_s A_r (hierarchical/refiner.h); for a cluster link, its unoccluded K
  std::vector<std::uint8_t> receiverSide;  // ΔK is K's spread over the receiver (every ray got through): refining splits the receiver
  // Into a cluster: how the light K brings divides over the cluster's faces by the way they face,
  // in 255ths over the six axis directions (+x, −x, +y, −y, +z, −z; a face's share split by its
  // normal's components), from the link's own sample pairs; all 0 where unknown (an element
  // receiver, no open pair). The push hands each bin to the faces that face its way
  // (hierarchical/transport.h, "directional push").
  std::vector<std::array<std::uint8_t, 6>> facing;

  std::size_t size() const { return source.size(); }
  std::size_t bytes() const;
};

// The minimum element area the options give for this hierarchy.
double minimumElementArea(const ElementHierarchy& hierarchy, const LinkOptions& options);

}  // namespace lambert
