#pragma once
// Gathering over the links of hierarchical radiosity (Hanrahan, Salzman & Aupperle 1991, §4):
// pull the leaves' radiosity up the hierarchy as area-weighted means, gather over every node's
// links, push what each node gathered down to the leaves under it. One gather costs
// O(nodes + links), against O(n²) for the dense matrix. hierarchical/links.h makes the links.
#include <memory>
#include <span>
#include <vector>

#include "lambert/core/communicator.h"
#include "lambert/core/timer.h"
#include "lambert/hierarchical/links.h"
#include "lambert/hierarchical/element_hierarchy.h"
#include "lambert/solve/transport.h"

namespace lambert {

class HierarchicalTransport final : public Transport {
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
  void completeSweeps(std::vector<Rgb>& radiosity) const override;
  // Distributed: the records a sweep's exchange hands this rank (the others' nodes' power, 24 B each).
  std::size_t receivedPerSweep() const { return receivedNodes_.size() - sentNodes_.size(); }

  const Links& links() const { return *links_; }

  // Spreads the Jacobi sweep over the communicator's ranks (docs/distributed.md): rank
  // nodeRank[i] is the rank whose leaves alone lie under node i, or kSharedNode where several
  // ranks' do. A rank sweeps its leaves, and holds the links into them and their ancestors (a distributed
  // refinement's share, hierarchical/links.h: the links here are this rank's alone). A sweep then
  // gathers, on each rank, the nodes on the paths to its own leaves only and updates those leaves,
  // reading the means of its own nodes, of the shared nodes above the ranks' subtrees and of the
  // others' nodes its links read; one collective per sweep hands every rank the power of each
  // rank's subtree tops and of its nodes that others read (what crosses the cut, planned here
  // with one more collective). The sweep's change is the largest over the ranks. Each leaf ends a
  // sweep, on its rank, with the radiosity a single process's Jacobi sweep over the union of the
  // ranks' links gives, to the bit; the others' leaves are stale until completeSweeps() hands
  // every rank the whole. gather() is then collective too. The in-place (Gauss–Seidel) sweep
  // cannot be spread so: sweep() refuses it once distributed. Every rank must call this, and
  // then every sweep and gather, alike. The row-sum figures below become this rank's leaves'.
  static constexpr int kSharedNode = -1;
  void distribute(std::shared_ptr<Communicator> communicator, std::span<const int> nodeRank);
  // This rank's leaves, and the values a sweep sends from each rank (empty before distribute()).
  std::span<const std::uint32_t> ownLeaves() const;
  const std::vector<int>& leavesPerRank() const { return leavesPerRank_; }
  // Seconds this rank's sweeps spent in their exchange (waiting for the other ranks included).
  double sweepCommunicationSeconds() const { return sweepCommunicationSeconds_; }
  // The rank that sweeps a leaf (0 before distribute()).
  int rankOfLeaf(std::uint32_t leaf) const { return communicator_ ? nodeOwner_[nodeOfLeaf_[leaf]] : 0; }
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

 private:
  Rgb gatherNode(std::uint32_t node, const std::vector<Rgb>& mean) const;
  // Distributed: what this rank's leaves gather (in ownLeaves() order).
  std::vector<Rgb> gatherOwn(const std::vector<Rgb>& radiosity) const;
  // Distributed: the node means this rank's links read, from its own leaves' radiosity (the
  // others' may be stale) and one collective: what crosses the cut (planExchange).
  std::vector<Rgb> exchangeMeans(const std::vector<Rgb>& radiosity) const;
  void planExchange();
  // Every rank's values of its own leaves (in ownLeaves() order), placed at their leaves.
  std::vector<Rgb> exchangeOwn(const std::vector<Rgb>& mine) const;

  std::vector<std::uint32_t> parent_;
  std::vector<double> area_;
  std::vector<double> openArea_;  // of the leaves under each element; a cluster's whole area
  // A link's K is the irradiance of its receiver's open part (hierarchical/links.h): a leaf takes
  // its open share f of what it and its ancestors gather, E = f·ΣK·B̄_s, a mean over its area.
  // The bound. Where the K of the links at a leaf and at its ancestors sum to S with ρS above
  // rowContractionBound(ρ) (ρ: the leaf albedo's largest channel; 0.95, or (1 + ρ)/2 for ρ above
  // 0.9), the estimate is far above the truth (at most 1: a receiver gathers at most its whole
  // hemisphere) and what the leaf gathers is scaled by 1/S; below, S is left as measured. Every
  // leaf then has ρ·S ≤ max(0.95, (1 + ρ_max)/2) < 1, every pulled mean is at most its leaves' largest value, and so one sweep
  // shrinks the largest open radiosity's distance to the solution by that factor: B = E + ρKB is
  // a contraction and no sweep can diverge (docs/hierarchical.md, "The bound"). Rows above 1 by
  // less are estimation noise around a true sum of at most 1 (different quadrature points and
  // rays at each level; a receiving cluster handing every face the mean of what its faces
  // gather), balanced by rows below 1: scaling them too let the closed Cornell box lose 5.8% of
  // its power and made the clustered box 11% dark.
  // leafGain_ = f · (scaled ? 1/S : 1).
  std::vector<double> leafGain_;
  std::vector<double> leafRowSum_;       // S per leaf
  std::vector<std::uint8_t> leafScaled_;  // whether the bound scaled it
  double largestRowSum_ = 0;
  std::size_t rowsScaled_ = 0;
  std::vector<std::uint32_t> leafOfNode_;  // kNoNode for inner nodes
  // The nodes depth first from the root (Gauss–Seidel's order), each with its depth (the root's 0).
  struct SweepStep {
    std::uint32_t node, depth;
  };
  std::vector<SweepStep> sweepOrder_;
  std::size_t sweepDepth_ = 0;  // the deepest node's depth + 1
  std::vector<std::uint32_t> nodeOfLeaf_;
  // distribute(): the communicator, every rank's leaves one run after another (rank r's from
  // firstLeaf_[r]), how many each rank has, and the nodes on the paths to this rank's, in
  // increasing order (parents first).
  std::shared_ptr<Communicator> communicator_;
  std::vector<std::uint32_t> leavesByRank_;
  std::vector<std::size_t> firstLeaf_;
  std::vector<int> leavesPerRank_;
  std::vector<std::uint32_t> ownPath_;
  // The exchange of what crosses the cut: each node's rank (distribute()'s nodeRank); this rank's nodes (increasing); the shared nodes and every rank's subtrees' tops
  // (increasing); the nodes whose power this rank sends each sweep (its tops, and its nodes other
  // ranks' links read), and every rank's such nodes in rank order with how many each sends.
  std::vector<int> nodeOwner_;
  std::vector<std::uint32_t> ownNodes_, combined_, sentNodes_, receivedNodes_;
  std::vector<int> sentPerRank_;
  mutable double sweepCommunicationSeconds_ = 0;
  std::shared_ptr<const Links> links_;
};

}  // namespace lambert
