#pragma once
// The sweeps of hierarchical radiosity spread over MPI ranks (docs/distributed.md): the same
// transport as hierarchical/transport.h, each rank sweeping its own leaves over its own links and
// exchanging what crosses the cut between the ranks' subtrees. Its own file so that the serial
// transport holds no rank logic; hierarchical/distributed_ranks.h decides which rank owns what
// and makes this transport once the ranks share the hierarchy.
#include <memory>
#include <span>
#include <vector>

#include "lambert/core/communicator.h"
#include "lambert/hierarchical/transport.h"

namespace lambert {

class DistributedTransport final : public HierarchicalTransport {
 public:
  // The Jacobi sweep spread over the communicator's ranks (docs/distributed.md): rank
  // nodeRank[i] is the rank whose leaves alone lie under node i, or kSharedNode where several
  // ranks' do. A rank sweeps its leaves, and holds the links into them and their ancestors (a distributed
  // refinement's share, hierarchical/distributed_links.h: the links here are this rank's alone). A sweep then
  // gathers, on each rank, the nodes on the paths to its own leaves only and updates those leaves,
  // reading the means of its own nodes, of the shared nodes above the ranks' subtrees and of the
  // others' nodes its links read; one collective per sweep hands every rank the power of each
  // rank's subtree tops and of its nodes that others read (what crosses the cut, planned here
  // with one more collective). The sweep's change is the largest over the ranks. Each leaf ends a
  // sweep, on its rank, with the radiosity a single process's Jacobi sweep over the union of the
  // ranks' links gives, to the bit; the others' leaves are stale until completeSweeps() hands
  // every rank the whole. gather() is then collective too. The in-place (Gauss–Seidel) sweep
  // cannot be spread so: sweep() refuses it. Every rank must make this transport, and then every
  // sweep and gather, alike. The row sums (largestRowSum, rowsScaled) are this rank's leaves'.
  static constexpr int kSharedNode = -1;
  DistributedTransport(const ElementHierarchy& hierarchy, std::shared_ptr<const Links> links, std::span<const double> leafOpenFraction,
                       std::span<const Rgb> leafAlbedo, std::shared_ptr<Communicator> communicator, std::span<const int> nodeRank);

  void gather(const std::vector<Rgb>& radiosity, std::vector<Rgb>& irradiance) const override;
  SweepChange sweep(const std::vector<Rgb>& emitted, const std::vector<Rgb>& albedo, std::vector<Rgb>& radiosity,
                    bool inPlace) const override;
  void completeSweeps(std::vector<Rgb>& radiosity) const override;
  // The records a sweep's exchange hands this rank (the others' nodes' power, 24 B each).
  std::size_t receivedPerSweep() const { return receivedNodes_.size() - sentNodes_.size(); }
  // This rank's leaves, and the values a sweep sends from each rank.
  std::span<const std::uint32_t> ownLeaves() const;
  const std::vector<int>& leavesPerRank() const { return leavesPerRank_; }
  // Seconds this rank's sweeps spent in their exchange (waiting for the other ranks included).
  double sweepCommunicationSeconds() const { return sweepCommunicationSeconds_; }
  // The rank that sweeps a leaf.
  int rankOfLeaf(std::uint32_t leaf) const { return nodeOwner_[nodeOfLeaf_[leaf]]; }

 private:
  // What this rank's leaves gather (in ownLeaves() order).
  std::vector<Rgb> gatherOwn(const std::vector<Rgb>& radiosity) const;
  // The node means this rank's links read, from its own leaves' radiosity (the
  // others' may be stale) and one collective: what crosses the cut (planExchange).
  std::vector<Rgb> exchangeMeans(const std::vector<Rgb>& radiosity) const;
  void planExchange();
  // Every rank's values of its own leaves (in ownLeaves() order), placed at their leaves.
  std::vector<Rgb> exchangeOwn(const std::vector<Rgb>& mine) const;

  // The communicator, every rank's leaves one run after another (rank r's from
  // firstLeaf_[r]), how many each rank has, and the nodes on the paths to this rank's, in
  // increasing order (parents first).
  std::shared_ptr<Communicator> communicator_;
  std::vector<std::uint32_t> leavesByRank_;
  std::vector<std::size_t> firstLeaf_;
  std::vector<int> leavesPerRank_;
  std::vector<std::uint32_t> ownPath_;
  std::vector<SweepStep> ownSweepOrder_;  // ownPath_ depth first, as sweepOrder_ orders it
  // The exchange of what crosses the cut: each node's rank (the constructor's nodeRank); this
  // rank's nodes (increasing); the shared nodes and every rank's subtrees' tops (increasing); the nodes whose power this rank sends each sweep (its tops, and its nodes other
  // ranks' links read), and every rank's such nodes in rank order with how many each sends.
  std::vector<int> nodeOwner_;
  std::vector<std::uint32_t> ownNodes_, combined_, sentNodes_, receivedNodes_;
  std::vector<int> sentPerRank_;
  mutable double sweepCommunicationSeconds_ = 0;
};

}  // namespace lambert
