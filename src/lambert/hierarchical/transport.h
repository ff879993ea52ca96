#pragma once
// Gathering over the links of hierarchical radiosity (Hanrahan, Salzman & Aupperle 1991, §4):
// pull the leaves' radiosity up the hierarchy as area-weighted means, gather over every node's
// links, push what each node gathered down to the leaves under it. One gather costs
// O(nodes + links), against O(n²) for the dense matrix. hierarchical/refiner.h makes the links;
// hierarchical/distributed_transport.h spreads the sweeps over ranks.
#include <array>
#include <memory>
#include <span>
#include <vector>

#include "lambert/hierarchical/element_hierarchy.h"
#include "lambert/hierarchical/links.h"
#include "lambert/solve/transport.h"

namespace lambert {

class HierarchicalTransport : public Transport {
 public:
  // Copies what it needs of the hierarchy (which may be refined further afterwards).
  // leafOpenFraction: per leaf, the share not covered by other geometry (Patch::openFraction);
  // leafAlbedo: per leaf, the ρ it will be solved with (for the bound below).
  HierarchicalTransport(const ElementHierarchy& hierarchy, std::shared_ptr<const Links> links,
                        std::span<const double> leafOpenFraction, std::span<const Rgb> leafAlbedo);

  std::size_t size() const override { return nodeOfLeaf_.size(); }
  void gather(const std::vector<Rgb>& radiosity, std::vector<Rgb>& irradiance) const override;
  // Jacobi: one gather from the previous iterate. Gauss–Seidel: nodes depth first (parents
  // first, each subtree whole), each gathering from the current means: a node's mean takes the
  // change of the leaves under it when its subtree is finished, once, so a sweep costs
  // O(nodes + links) rather than O(leaves × depth), and every node outside the subtree being
  // swept reads its mean with every change made so far, as if each new leaf value had raised
  // its ancestors' means at once. Only a link from a node to its own ancestor would read that
  // ancestor's mean as of the sweep's start.
  SweepChange sweep(const std::vector<Rgb>& emitted, const std::vector<Rgb>& albedo, std::vector<Rgb>& radiosity,
                    bool inPlace) const override;

  const Links& links() const { return *links_; }

  // The bound on ρ·Σ K above which a leaf's Σ K is scaled to 1 (leafGain_ below): the flat
  // methods' rowContractionBound(ρ) (flat/table.h), 0.95 or (1 + ρ)/2 where that is higher.
  // The largest Σ K a leaf gathers over its own links and its ancestors' before the bound, and
  // how many leaves the bound scaled down.
  double largestRowSum() const { return largestRowSum_; }
  std::size_t rowsScaled() const { return rowsScaled_; }
  // The radiosity every node shows to what its links reach, HSA'91's pull: the power of the
  // leaves under an element over their open area (where the floor runs under a block, the
  // covered part is dark, and the links' visibility rays already leave it out; a mean over the
  // whole area would count it out twice and dim everything the element lights); a cluster's
  // over all its area.
  void pull(const std::vector<Rgb>& radiosity, std::vector<Rgb>& mean) const;

 protected:
  // What the sweeps spread over ranks (hierarchical/distributed_transport.h) read of this transport.
  Rgb gatherNode(std::uint32_t node, const std::vector<Rgb>& mean) const;
  // A sweep's change at one leaf: the largest over the channels.
  static double largestChange(const Rgb& a, const Rgb& b);

  std::vector<std::uint32_t> parent_;
  std::vector<double> area_;
  std::vector<double> openArea_;  // of the leaves under each element; a cluster's whole area
  // A link's K is the irradiance of its receiver's open part (hierarchical/links.h): a leaf takes
  // its open share f of what it and its ancestors gather, E = f·ΣK·B̄_s, a mean over its area.
  // The bound. Where the K of the links at a leaf and at its ancestors sum to S with ρS above
  // rowContractionBound(ρ) (ρ: the leaf albedo's largest channel; 0.95, or (1 + ρ)/2 for ρ above
  // 0.9), the estimate is far above the truth (at most 1: a receiver gathers at most its whole
  // hemisphere) and the leaf gathers exactly its hemisphere, its own links first: they are kept
  // whole (scaled to 1 if they alone sum above it) and what its ancestors hand down fills the
  // rest, 1 − S_own. An ancestor's K is a mean over a larger receiver, and the leaf may be where
  // that mean is wrong: a ceiling leaf over a lamp panel hung 10 cm under it sees the panel
  // through its own links (K ≈ 0.94) and, through the whole ceiling element's, the room as the
  // open part of that element sees it (K ≈ 0.6). Scaling both by 1/S took 40% of the panel's
  // light from the ceiling over it (docs/hierarchical.md, "Narrow cavities"). Below the bound, S
  // is left as measured. Every leaf then has ρ·S ≤ max(0.95, (1 + ρ_max)/2) < 1, every pulled
  // mean is at most its leaves' largest value, and so one sweep shrinks the largest open
  // radiosity's distance to the solution by that factor: B = E + ρKB is a contraction and no
  // sweep can diverge (docs/hierarchical.md, "The bound"). Rows above 1 by less are estimation
  // noise around a true sum of at most 1 (different quadrature points and rays at each level; a
  // receiving cluster handing every face the mean of what its faces gather), balanced by rows
  // below 1: scaling them too let the closed Cornell box lose 5.8% of its power and made the
  // clustered box 11% dark.
  // What a leaf gathers is own · leafOwnGain_ + ancestors · leafAncestorGain_ (f folded in).

  // The nodes depth first from the root (Gauss–Seidel's order), each with its depth (the root's 0)
  // and its place in that order (what per-step arrays are indexed by).
  struct SweepStep {
    std::uint32_t node, depth, step;
  };

  // The directional push of a receiving cluster (Sillion 1995's non-isotropic clusters, on the
  // receiving side): a link K·B̄_s into a cluster is the mean irradiance over all the cluster's
  // faces, those facing the source and those facing away. Handing every face that mean gave a
  // desk's top half of the luminaires' light and its underside the other half (RenderPark's
  // classroom: desk tops 30% dark in the solve, the room's reflected light 11% short). A cluster
  // holds what its links gather in bins, one per axis direction: each link puts its light into
  // them as its own sample pairs found it falling on the cluster's faces (Links::facing); a
  // link whose pairs found nothing open goes into a seventh bin, handed out by area alike. A
  // child takes of each axis bin its own open projected area's share of its siblings', over its
  // open area (foldWeight_; K is the irradiance of the receiver's open part, links.h): a face
  // takes what fell on faces facing its way, a cluster keeps the bins for its children, and a
  // child as oriented as its parent takes the parent's mean as before. Every bin's power is
  // handed out whole: Σ_c fold · A_open,c = A_open,p. By all area, an enclosed inner twin
  // (geometry/enclosures.h) counted in the parent's area but not among the faces facing the
  // light's way, and a two-sided box's bottom got 3% too much.
  static constexpr int kBins = 7;
  using Bins = std::array<Rgb, kBins>;
  // What a node on the path from the root holds while the push passes it: an element, what it
  // and its ancestors gathered (as a scalar); a cluster, the same in bins.
  struct Handed {
    Rgb total;
    Bins bins;
    std::uint8_t binMask = 0;  // the bins that hold light (the others are not read)
  };
  // Node at.node's state from its own links (own: an element's gatherNode, or nullptr to compute it) and
  // what its parent's state hands down; for a leaf, also what it gathers in all (its own links by
  // leafOwnGain_, the rest by leafAncestorGain_).
  void handDown(const SweepStep& at, const Handed* parent, const std::vector<Rgb>& mean, const Rgb* own, Handed& state,
                Rgb* leafGathered) const;
  // A cluster's own links into its bins (clearing them first); returns the bins it filled.
  std::uint8_t gatherBins(std::uint32_t cluster, const std::vector<Rgb>& mean, Bins& bins) const;
  std::vector<std::array<float, kBins>> foldWeight_;  // per sweep step, for a node under a cluster: its factor on each bin of the parent's
  std::vector<std::uint8_t> foldMask_;  // per sweep step: the bins whose factor is not 0 (a face's: those it faces)
  // Per link into a cluster, its K in each bin (K × its share there) and which bins those are:
  // read by every sweep, so worked out once. At clusterLinkStart_[r] + (k − links.start[r]).
  struct ClusterLinkWeights {
    std::array<float, kBins> weight;
    std::uint8_t mask;
  };
  std::vector<ClusterLinkWeights> clusterLinkWeights_;
  std::vector<std::uint32_t> clusterLinkStart_;  // per node
  std::vector<std::uint8_t> isCluster_;
  // Which nodes are clusters, and each cluster child's foldWeight_, from the hierarchy and the
  // leaves' open fractions.
  void shareBins(const ElementHierarchy& hierarchy, std::span<const double> leafOpenFraction);
  // A link's Links::facing as shares of its K over the bins (the seventh where it is unknown).
  static std::array<double, kBins> binShares(const std::array<std::uint8_t, 6>& facing);
  // The weighted push and pull (docs/hierarchical.md, "Weighted push and pull"): per element, its
  // share of what its parent gathers (pushWeight_) and the weight its light has in its parent's
  // mean (pullWeight_); each averages to 1 over the siblings by open area, so a pulled mean is
  // still a convex combination of its children's. The sweeps pull with pullWeight_; pull(), the
  // plain means (no weights), is what the outputs' final gathers read.
  std::vector<double> pushWeight_;
  std::vector<double> pullWeight_;
  void pullWeighted(const std::vector<Rgb>& radiosity, std::vector<Rgb>& mean, std::span<const double> weight) const;
  // Per node, the weight that hands an element's share to its element children by what the
  // links at and below each leave unclaimed of it (claimedShare per node; the others 1), or, where
  // `above` is given, by how much of what the links above claim fits in that.
  // above: per node, what its ancestors claim (handedFromAbove of claimedShare).
  std::vector<double> unclaimedWeights(const ElementHierarchy& hierarchy, std::span<const double> claimedShare,
                                       std::span<const double> leafOpenFraction, std::span<const double> above) const;
  // The push's and the pull's weights and the leaves' gains, from each node's Σ K over its links
  // (gathers) and Σ K · A_r over the links from it (sends), the whole hierarchy's.
  // clusterGathers: per node, a cluster's Σ K split into its bins (binShares), what the push hands
  // down of it.
  void weigh(const ElementHierarchy& hierarchy, std::span<const double> gathers, std::span<const std::array<double, kBins>> clusterGathers,
             std::span<const double> sends, std::span<const double> leafOpenFraction, std::span<const Rgb> leafAlbedo);
  // Per node, what reaches it of its ancestors' values (per node of `own`, clusters' in bins), before its own
  // and before pushWeight_, as the push hands them down: a scalar per node.
  std::vector<double> handedFromAbove(std::span<const double> own, std::span<const std::array<double, kBins>> ownBins,
                                      bool weighted) const;
  std::vector<double> leafOwnGain_;
  std::vector<double> leafAncestorGain_;
  std::vector<double> leafRowSum_;       // S per leaf
  std::vector<std::uint8_t> leafScaled_;  // whether the bound scaled it
  double largestRowSum_ = 0;
  std::size_t rowsScaled_ = 0;
  std::vector<std::uint32_t> leafOfNode_;  // kNoNode for inner nodes
  std::vector<std::uint32_t> nodeOfLeaf_;
  std::shared_ptr<const Links> links_;

  std::vector<SweepStep> sweepOrder_;
  std::size_t sweepDepth_ = 0;  // the deepest node's depth + 1
  // The push over `order` (depth first, every node's ancestors before it): each leaf's gathered
  // irradiance into leafGathered (indexed by leaf), from each element's own gather (ownGathered, per
  // node) and the clusters' bins gathered on the way.
  void pushAlong(std::span<const SweepStep> order, const std::vector<Rgb>& mean, const std::vector<Rgb>& ownGathered,
                 std::vector<Rgb>& leafGathered) const;
};

}  // namespace lambert
