// The cut exchange of a distributed transport (hierarchical/distributed_transport.h).
#include "lambert/hierarchical/distributed_transport.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/core/timer.h"

namespace lambert {

DistributedTransport::DistributedTransport(const ElementHierarchy& hierarchy, std::shared_ptr<const Links> links,
                                           std::span<const double> leafOpenFraction, std::span<const Rgb> leafAlbedo,
                                           std::shared_ptr<Communicator> communicator, std::span<const int> nodeRank)
    : HierarchicalTransport(hierarchy, std::move(links), leafOpenFraction, leafAlbedo), communicator_(std::move(communicator)) {
  LAMBERT_CHECK(communicator_ && communicator_->size() >= 1 && nodeRank.size() == parent_.size());
  const std::size_t n = parent_.size(), ranks = static_cast<std::size_t>(communicator_->size());
  nodeOwner_.assign(nodeRank.begin(), nodeRank.end());
  leavesPerRank_.assign(ranks, 0);
  for (std::uint32_t l = 0; l < nodeOfLeaf_.size(); ++l) {
    const int r = rankOfLeaf(l);
    LAMBERT_CHECK(r >= 0 && static_cast<std::size_t>(r) < ranks);
    ++leavesPerRank_[static_cast<std::size_t>(r)];
  }
  firstLeaf_.assign(ranks + 1, 0);
  for (std::size_t r = 0; r < ranks; ++r) firstLeaf_[r + 1] = firstLeaf_[r] + static_cast<std::size_t>(leavesPerRank_[r]);
  leavesByRank_.resize(nodeOfLeaf_.size());
  std::vector<std::size_t> next(firstLeaf_.begin(), firstLeaf_.end() - 1);
  for (std::uint32_t l = 0; l < nodeOfLeaf_.size(); ++l) leavesByRank_[next[static_cast<std::size_t>(rankOfLeaf(l))]++] = l;
  // The nodes on the paths to this rank's leaves.
  std::vector<char> onPath(n, 0);
  for (std::uint32_t l : ownLeaves())
    for (std::uint32_t i = nodeOfLeaf_[l]; i != kNoNode && !onPath[i]; i = parent_[i]) onPath[i] = 1;
  ownPath_.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (onPath[i]) ownPath_.push_back(static_cast<std::uint32_t>(i));
  for (const SweepStep& step : sweepOrder_)
    if (onPath[step.node]) ownSweepOrder_.push_back(step);
  planExchange();
  // The push's and the pull's weights need every link of the hierarchy: each rank hands the others
  // its links into the nodes it alone holds, and the lowest rank under a shared node those into
  // that node, so that each link comes once; sorted by receiver (each receiver's links from one
  // rank, in that rank's order), they sum as one process sums its own.
  std::vector<int> lowestRank(n, std::numeric_limits<int>::max());
  for (std::uint32_t l = 0; l < nodeOfLeaf_.size(); ++l)
    for (std::uint32_t i = nodeOfLeaf_[l]; i != kNoNode; i = parent_[i]) lowestRank[i] = std::min(lowestRank[i], rankOfLeaf(l));
  struct LinkRecord {
    std::uint32_t receiver, source;
    float formFactor;
    std::array<std::uint8_t, 6> facing;
    std::uint8_t unused[2];
  };
  static_assert(sizeof(LinkRecord) == 20);
  std::vector<LinkRecord> mine;
  const int me = communicator_->rank();
  for (std::uint32_t r = 0; r < n; ++r) {
    if ((nodeOwner_[r] == kSharedNode ? lowestRank[r] : nodeOwner_[r]) != me) continue;
    for (std::uint32_t k = links_->start[r]; k < links_->start[r + 1]; ++k) mine.push_back({r, links_->source[k], links_->formFactor[k], links_->facing[k], {0, 0}});
  }
  std::vector<LinkRecord> every = communicator_->allGatherVariable<LinkRecord>(mine);
  std::stable_sort(every.begin(), every.end(), [](const LinkRecord& a, const LinkRecord& b) { return a.receiver < b.receiver; });
  std::vector<double> gathers(n, 0.0), sends(n, 0.0);
  std::vector<std::array<double, kBins>> clusterGathers(n, std::array<double, kBins>{});
  for (const LinkRecord& link : every) {
    gathers[link.receiver] += link.formFactor;
    sends[link.source] += link.formFactor * openArea_[link.receiver];
    if (isCluster_[link.receiver]) {
      const std::array<double, kBins> share = binShares(link.facing);
      for (int b = 0; b < kBins; ++b) clusterGathers[link.receiver][b] += link.formFactor * share[b];
    }
  }
  weigh(hierarchy, gathers, clusterGathers, sends, leafOpenFraction, leafAlbedo);
  // The row sums and their bound over this rank's leaves only: the others' links are not here.
  largestRowSum_ = 0;
  rowsScaled_ = 0;
  for (std::uint32_t l : ownLeaves()) {
    largestRowSum_ = std::fmax(largestRowSum_, leafRowSum_[l]);
    rowsScaled_ += leafScaled_[l];
  }
}

void DistributedTransport::gather(const std::vector<Rgb>& radiosity, std::vector<Rgb>& irradiance) const {
  LAMBERT_CHECK(radiosity.size() == size());
  irradiance = exchangeOwn(gatherOwn(radiosity));
}

SweepChange DistributedTransport::sweep(const std::vector<Rgb>& emitted, const std::vector<Rgb>& albedo,
                                        std::vector<Rgb>& radiosity, bool inPlace) const {
  LAMBERT_CHECK(!inPlace);  // the engine sweeps a distributed solve by Jacobi (engine/radiosity.cpp)
  SweepChange change;
  const std::span<const std::uint32_t> own = ownLeaves();
  const std::vector<Rgb> irradiance = gatherOwn(radiosity);
  std::vector<Rgb> mine(own.size());
  for (std::size_t k = 0; k < own.size(); ++k) {
    const std::uint32_t l = own[k];
    mine[k] = emitted[l] + albedo[l] * irradiance[k];
    change.change = std::fmax(change.change, largestChange(mine[k], radiosity[l]));
    change.magnitude = std::fmax(change.magnitude, mine[k].maxComponent());
  }
  // Only this rank's leaves are current now: the next sweep's exchange reads them.
  for (std::size_t k = 0; k < own.size(); ++k) radiosity[own[k]] = mine[k];
  double figures[2] = {change.change, change.magnitude};
  const Timer exchange;
  communicator_->maxAll(figures);
  sweepCommunicationSeconds_ += exchange.seconds();
  return {figures[0], figures[1]};
}

void DistributedTransport::completeSweeps(std::vector<Rgb>& radiosity) const {
  const std::span<const std::uint32_t> own = ownLeaves();
  std::vector<Rgb> mine(own.size());
  for (std::size_t k = 0; k < own.size(); ++k) mine[k] = radiosity[own[k]];
  radiosity = exchangeOwn(mine);
}

std::vector<Rgb> DistributedTransport::gatherOwn(const std::vector<Rgb>& radiosity) const {
  // Gather and push along this rank's paths only, as gather() does over every node.
  const std::size_t n = parent_.size();
  std::vector<Rgb> gathered(n), leafGathered(size());
  const std::vector<Rgb> mean = exchangeMeans(radiosity);
  parallelFor(0, ownPath_.size(), [&](std::size_t k) {
    if (!isCluster_[ownPath_[k]]) gathered[ownPath_[k]] = gatherNode(ownPath_[k], mean);
  }, 256);
  pushAlong(ownSweepOrder_, mean, gathered, leafGathered);
  const std::span<const std::uint32_t> own = ownLeaves();
  std::vector<Rgb> irradiance(own.size());
  for (std::size_t k = 0; k < own.size(); ++k) irradiance[k] = leafGathered[own[k]];
  return irradiance;
}

std::vector<Rgb> DistributedTransport::exchangeOwn(const std::vector<Rgb>& mine) const {
  static_assert(sizeof(Rgb) == 3 * sizeof(double));
  std::vector<Rgb> all(leavesByRank_.size()), byLeaf(leavesByRank_.size());
  const Timer exchange;
  communicator_->allGather<Rgb>(mine, leavesPerRank_, all);
  sweepCommunicationSeconds_ += exchange.seconds();
  for (std::size_t k = 0; k < leavesByRank_.size(); ++k) byLeaf[leavesByRank_[k]] = all[k];
  return byLeaf;
}

void DistributedTransport::planExchange() {
  const std::size_t n = parent_.size();
  const int me = communicator_->rank();
  ownNodes_.clear();
  combined_.clear();
  std::vector<std::uint32_t> asked;  // the others' nodes this rank's links read
  for (std::size_t i = 0; i < n; ++i) {
    const bool top = nodeOwner_[i] != kSharedNode && (parent_[i] == kNoNode || nodeOwner_[parent_[i]] == kSharedNode);
    if (nodeOwner_[i] == me) ownNodes_.push_back(static_cast<std::uint32_t>(i));
    if (nodeOwner_[i] == kSharedNode || top) combined_.push_back(static_cast<std::uint32_t>(i));
  }
  for (std::uint32_t r : ownPath_)
    for (std::uint32_t k = links_->start[r]; k < links_->start[r + 1]; ++k)
      if (const std::uint32_t s = links_->source[k]; nodeOwner_[s] != me && nodeOwner_[s] != kSharedNode) asked.push_back(s);
  std::sort(asked.begin(), asked.end());
  asked.erase(std::unique(asked.begin(), asked.end()), asked.end());
  // What this rank sends each sweep: the power of its subtrees' tops (the shared nodes above
  // them are sums of those) and of its nodes any other rank's links read.
  std::vector<std::uint32_t> sent;
  for (std::uint32_t s : communicator_->allGatherVariable<std::uint32_t>(asked))
    if (nodeOwner_[s] == me) sent.push_back(s);
  for (std::uint32_t i : combined_)
    if (nodeOwner_[i] == me) sent.push_back(i);
  std::sort(sent.begin(), sent.end());
  sent.erase(std::unique(sent.begin(), sent.end()), sent.end());
  sentNodes_ = std::move(sent);
  receivedNodes_ = communicator_->allGatherVariable<std::uint32_t>(sentNodes_);
  sentPerRank_.assign(static_cast<std::size_t>(communicator_->size()), 0);
  for (std::uint32_t i : receivedNodes_) ++sentPerRank_[static_cast<std::size_t>(nodeOwner_[i])];
}

std::vector<Rgb> DistributedTransport::exchangeMeans(const std::vector<Rgb>& radiosity) const {
  // pull() over what this rank needs, summed in pull()'s order (each node's children in
  // decreasing index order), so that every mean is the one process's to the bit: this rank's
  // subtrees from its leaves, the others' nodes its links read and every subtree's top from the
  // exchange, the shared nodes from their children.
  const std::size_t n = parent_.size();
  const int me = communicator_->rank();
  std::vector<Rgb> power(n);
  for (std::size_t k = ownNodes_.size(); k-- > 0;) {
    const std::uint32_t i = ownNodes_[k];
    if (const std::uint32_t l = leafOfNode_[i]; l != kNoNode) power[i] = radiosity[l] * area_[i];
    if (const std::uint32_t p = parent_[i]; p != kNoNode && nodeOwner_[p] == me) power[p] += power[i] * pullWeight_[i];
  }
  std::vector<Rgb> sent(sentNodes_.size()), all(receivedNodes_.size());
  for (std::size_t k = 0; k < sentNodes_.size(); ++k) sent[k] = power[sentNodes_[k]];
  const Timer exchange;
  communicator_->allGather<Rgb>(sent, sentPerRank_, all);
  sweepCommunicationSeconds_ += exchange.seconds();
  for (std::size_t k = 0; k < receivedNodes_.size(); ++k) power[receivedNodes_[k]] = all[k];
  for (std::size_t k = combined_.size(); k-- > 0;)
    if (const std::uint32_t p = parent_[combined_[k]]; p != kNoNode) power[p] += power[combined_[k]] * pullWeight_[combined_[k]];
  std::vector<Rgb>& mean = power;
  for (std::size_t i = 0; i < n; ++i) mean[i] = openArea_[i] > 0 ? power[i] / openArea_[i] : Rgb{};
  return mean;
}

std::span<const std::uint32_t> DistributedTransport::ownLeaves() const {
  const auto r = static_cast<std::size_t>(communicator_->rank());
  return std::span<const std::uint32_t>(leavesByRank_).subspan(firstLeaf_[r], firstLeaf_[r + 1] - firstLeaf_[r]);
}

}  // namespace lambert
