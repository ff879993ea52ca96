// A distributed solve's shares of the hierarchy, its transport and its figures
// (hierarchical/distributed_ranks.h); the outputs' gathers are distributed_gathers.cpp's.
#include "lambert/hierarchical/distributed_ranks.h"

#include <algorithm>
#include <utility>

namespace lambert {

HierarchyRanks::HierarchyRanks(std::shared_ptr<Communicator> communicator) : communicator_(std::move(communicator)) {}

std::optional<LinkShare> HierarchyRanks::linkShare(const ElementHierarchy& hierarchy) {
  if (!communicator_) return std::nullopt;
  if (nodeRank_.empty()) assignRanks(hierarchy);
  // This rank's nodes: its own subtrees, and the shared nodes over them.
  const int me = communicator_->rank();
  std::vector<std::uint8_t> mine(hierarchy.nodes().size(), 0);
  for (std::size_t i = hierarchy.nodes().size(); i-- > 0;) {
    if (nodeRank_[i] == me) mine[i] = 1;
    const std::uint32_t parent = hierarchy.node(static_cast<std::uint32_t>(i)).parent;
    if (parent != kNoNode && mine[i]) mine[parent] = 1;
  }
  return LinkShare(*communicator_, std::move(mine));
}

void HierarchyRanks::refined(const ElementHierarchy& hierarchy, std::size_t nodesBefore, const Links& links) {
  if (!communicator_) return;
  // The elements split take their parent's rank.
  nodeRank_.resize(hierarchy.nodes().size());
  for (std::size_t i = nodesBefore; i < nodeRank_.size(); ++i) nodeRank_[i] = nodeRank_[hierarchy.node(static_cast<std::uint32_t>(i)).parent];
  countLinksOverRanks(hierarchy, links);
}

void HierarchyRanks::assignRanks(const ElementHierarchy& hierarchy) {
  // The leaves depth first (the children of a node after it, in the hierarchy's order), so that
  // a rank's run of them fills few subtrees, and each leaf's cost: its share of the area (where
  // the links go: refinement splits the lit area finely) and of the leaves, half and half.
  const std::size_t ranks = static_cast<std::size_t>(communicator_->size());
  std::vector<std::uint32_t> order, stack{0};
  while (!stack.empty()) {
    const std::uint32_t node = stack.back();
    stack.pop_back();
    if (hierarchy.node(node).isLeaf()) order.push_back(node);
    const std::span<const std::uint32_t> children = hierarchy.children(node);
    for (std::size_t c = children.size(); c-- > 0;) stack.push_back(children[c]);
  }
  const double totalArea = hierarchy.totalArea(), count = static_cast<double>(order.size());
  const auto cost = [&](std::uint32_t node) { return 0.5 * hierarchy.node(node).area / totalArea + 0.5 / count; };
  nodeRank_.assign(hierarchy.nodes().size(), DistributedTransport::kSharedNode);
  // Rank r takes the leaves whose cumulative cost starts in [r/R, (r+1)/R) of the whole.
  double before = 0;
  for (std::uint32_t node : order) {
    nodeRank_[node] = std::min(static_cast<int>(ranks) - 1, static_cast<int>(before * static_cast<double>(ranks) + 1e-9));
    before += cost(node);
  }
  // A node over leaves of one rank alone is that rank's (children have larger indices).
  std::vector<int> below(hierarchy.nodes().size(), -2);  // -2: nothing yet
  for (std::size_t i = hierarchy.nodes().size(); i-- > 0;) {
    if (hierarchy.node(static_cast<std::uint32_t>(i)).isLeaf()) below[i] = nodeRank_[i];
    else nodeRank_[i] = below[i];
    const std::uint32_t parent = hierarchy.node(static_cast<std::uint32_t>(i)).parent;
    if (parent != kNoNode) below[parent] = below[parent] == -2 || below[parent] == below[i] ? below[i] : DistributedTransport::kSharedNode;
  }
}

void HierarchyRanks::countLinksOverRanks(const ElementHierarchy& hierarchy, const Links& links) {
  // A shared node's links are held by every rank under it: the lowest counts them.
  const std::size_t n = hierarchy.nodes().size();
  std::vector<int> lowest(n);
  for (std::size_t i = 0; i < n; ++i) lowest[i] = nodeRank_[i] == DistributedTransport::kSharedNode ? communicator_->size() : nodeRank_[i];
  for (std::size_t i = n; i-- > 1;)
    if (const std::uint32_t parent = hierarchy.node(static_cast<std::uint32_t>(i)).parent; parent != kNoNode && nodeRank_[parent] == DistributedTransport::kSharedNode)
      lowest[parent] = std::min(lowest[parent], lowest[i]);
  double counted = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (lowest[i] == communicator_->rank()) counted += links.start[i + 1] - links.start[i];
  const double mine[3] = {static_cast<double>(links.size()), counted, static_cast<double>(links.bytes())};
  const auto ranks = static_cast<std::size_t>(communicator_->size());
  std::vector<int> counts(ranks, 3);
  std::vector<double> all(3 * ranks);
  communicator_->allGather<double>(mine, counts, all);
  linksOverRanks_ = {};
  for (std::size_t r = 0; r < ranks; ++r) {
    linksOverRanks_.mostHeld = std::max(linksOverRanks_.mostHeld, all[3 * r]);
    linksOverRanks_.total += all[3 * r + 1];
    linksOverRanks_.mostBytes = std::max(linksOverRanks_.mostBytes, all[3 * r + 2]);
  }
}

std::shared_ptr<const HierarchicalTransport> HierarchyRanks::makeTransport(const ElementHierarchy& hierarchy,
                                                                          std::shared_ptr<const Links> links,
                                                                          std::span<const double> leafOpenFraction,
                                                                          std::span<const Rgb> leafAlbedo) {
  if (transport_) sweepCommunicationSeconds_ += transport_->sweepCommunicationSeconds();
  transport_ = std::make_shared<DistributedTransport>(hierarchy, std::move(links), leafOpenFraction, leafAlbedo, communicator_, nodeRank_);
  return transport_;
}

void HierarchyRanks::addCommunicationStats(Stats& stats, std::size_t transportSize) const {
  if (!communicator_) return;
  // Before the first refinement the transport is not spread: no leaf is this rank's alone.
  const std::size_t ownLeaves = transport_ ? transport_->ownLeaves().size() : 0;
  const std::size_t receivedPerSweep = transport_ ? transport_->receivedPerSweep() : 0;
  const double sweepSeconds = transport_ ? transport_->sweepCommunicationSeconds() : 0;
  const CommunicationStats& sent = communicator_->stats();
  stats.add("ranks", "ranks (a distributed solve)", static_cast<std::int64_t>(communicator_->size()));
  stats.add("rank_leaves", "leaves this rank (0) sweeps", static_cast<std::int64_t>(ownLeaves));
  stats.add("exchange_bytes_per_sweep", "bytes a sweep hands this rank (0): the power of the others' nodes its links read",
            static_cast<std::int64_t>(sizeof(Rgb) * receivedPerSweep));
  stats.add("exchange_bytes_per_sweep_all_leaves", "bytes a sweep would hand it with every leaf's B",
            static_cast<std::int64_t>(sizeof(Rgb) * (transportSize - ownLeaves)));
  stats.add("communication_bytes_received", "bytes this rank received in all", static_cast<std::int64_t>(sent.bytesReceived));
  stats.add("communication_bytes_sent", "bytes this rank sent in all", static_cast<std::int64_t>(sent.bytesSent));
  stats.add("communication_calls", "collective calls", static_cast<std::int64_t>(sent.calls));
  stats.add("communication_seconds", "time in collective calls (waiting for the other ranks included)", sent.seconds, "s");
  stats.add("sweep_communication_seconds", "of which the sweeps' exchanges (every pass)",
            sweepCommunicationSeconds_ + sweepSeconds, "s");
}

void HierarchyRanks::addLinkStats(Stats& stats, const Links& links) const {
  const auto count = [](auto n) { return static_cast<std::int64_t>(n); };
  stats.add("links", "links (every rank's, each once)", count(linksOverRanks_.total));
  stats.add("rank_links", "links this rank (0) holds", count(links.size()));
  stats.add("rank_links_most", "links the rank holding most holds", count(linksOverRanks_.mostHeld));
  stats.add("rank_link_bytes_most", "link memory of the rank holding most", linksOverRanks_.mostBytes / (1024.0 * 1024.0), "MiB");
}

}  // namespace lambert
