// The collective calls of a distributed refinement (hierarchical/distributed_links.h).
#include "lambert/hierarchical/distributed_links.h"

#include <algorithm>
#include <utility>

namespace lambert {

LinkShare::LinkShare(Communicator& communicator, std::vector<std::uint8_t> mine)
    : communicator_(&communicator), mine_(std::move(mine)) {}

void LinkShare::addChildren(std::uint32_t parent, std::size_t count) {
  for (std::size_t k = 0; k < count; ++k) mine_.push_back(mine_[parent]);
}

std::vector<std::uint32_t> LinkShare::splitsOfEveryRank(const std::vector<std::uint32_t>& mine) const {
  const std::vector<std::uint32_t> all = communicator_->allGatherVariable<std::uint32_t>(mine);
  std::vector<std::uint32_t> splits(all.begin(), all.end());
  std::sort(splits.begin(), splits.end());
  splits.erase(std::unique(splits.begin(), splits.end()), splits.end());
  return splits;
}

bool LinkShare::everyRankGoesOn(std::size_t candidates, bool fitting, double& memoryNeeded) const {
  double figures[3] = {static_cast<double>(candidates), fitting ? 0.0 : 1.0, memoryNeeded};
  communicator_->maxAll(figures);
  memoryNeeded = figures[2];
  return !(figures[1] > 0 || figures[0] == 0);
}

}  // namespace lambert
