#pragma once
// A distributed refinement's share of the hierarchy (docs/distributed.md): the ranks meet through
// the communicator, and this rank refines and keeps the links into the nodes marked its own (per
// node of the hierarchy: those over its leaves, and under them). The refinement
// (hierarchical/refiner.h) marks the nodes it adds as their parents are, and asks here the two
// things the ranks must agree on each wave: the elements split, and whether to go on. Its own
// file so that the refiner's serial path holds no collective call (hierarchical/distributed_ranks.h
// makes the share).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "lambert/core/communicator.h"

namespace lambert {

class LinkShare {
 public:
  // mine: per node of the hierarchy, whether this rank refines the links into it.
  LinkShare(Communicator& communicator, std::vector<std::uint8_t> mine);

  std::size_t numNodes() const { return mine_.size(); }
  bool holds(std::uint32_t receiver) const { return mine_[receiver] != 0; }
  // The children of a node just split (the hierarchy's newest count nodes) are this rank's as it is.
  void addChildren(std::uint32_t parent, std::size_t count);
  // Every rank's splits of a wave (this rank's: `mine`), in increasing order, each once: every
  // rank splits them all, so that all hold the same hierarchy.
  std::vector<std::uint32_t> splitsOfEveryRank(const std::vector<std::uint32_t>& mine) const;
  // Every rank goes on while any has candidates left, and stops with the first that cannot fit;
  // memoryNeeded becomes the largest any rank needs.
  bool everyRankGoesOn(std::size_t candidates, bool fitting, double& memoryNeeded) const;

 private:
  Communicator* communicator_;
  std::vector<std::uint8_t> mine_;
};

}  // namespace lambert
