#include "lambert/hierarchical/transport.h"

#include <algorithm>
#include <cmath>

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/solve/row_contraction.h"

namespace lambert {
namespace {

double largestChange(const Rgb& a, const Rgb& b) {
  return std::fmax(std::fabs(a.r - b.r), std::fmax(std::fabs(a.g - b.g), std::fabs(a.b - b.b)));
}

}  // namespace

HierarchicalTransport::HierarchicalTransport(const ElementHierarchy& hierarchy, std::shared_ptr<const Links> links,
                                             std::span<const double> leafOpenFraction, std::span<const Rgb> leafAlbedo)
    : nodeOfLeaf_(hierarchy.leafNodes()), links_(std::move(links)) {
  const auto& nodes = hierarchy.nodes();
  LAMBERT_CHECK(links_ && links_->start.size() == nodes.size() + 1);
  LAMBERT_CHECK(leafOpenFraction.size() == nodeOfLeaf_.size());
  LAMBERT_CHECK(leafAlbedo.size() == nodeOfLeaf_.size());
  parent_.resize(nodes.size());
  area_.resize(nodes.size());
  openArea_.assign(nodes.size(), 0.0);
  leafOfNode_.resize(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    parent_[i] = nodes[i].parent;
    area_[i] = nodes[i].area;
    leafOfNode_[i] = nodes[i].leaf;
  }
  // Σ K over each node's links and its ancestors' (parents have smaller indices).
  std::vector<double> rowSum(nodes.size(), 0.0);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (parent_[i] != kNoNode) rowSum[i] = rowSum[parent_[i]];
    for (std::uint32_t k = links_->start[i]; k < links_->start[i + 1]; ++k) rowSum[i] += links_->formFactor[k];
  }
  leafGain_.resize(nodeOfLeaf_.size());
  leafRowSum_.resize(nodeOfLeaf_.size());
  leafScaled_.resize(nodeOfLeaf_.size());
  for (std::size_t l = 0; l < nodeOfLeaf_.size(); ++l) {
    const double sum = rowSum[nodeOfLeaf_[l]];
    LAMBERT_CHECK(std::isfinite(sum) && sum >= 0);
    largestRowSum_ = std::fmax(largestRowSum_, sum);
    const double rho = leafAlbedo[l].maxComponent();
    const bool scale = rho * sum > rowContractionBound(rho);
    rowsScaled_ += scale;
    leafRowSum_[l] = sum;
    leafScaled_[l] = scale;
    leafGain_[l] = leafOpenFraction[l] * (scale ? 1 / sum : 1.0);
  }
  for (std::size_t l = 0; l < nodeOfLeaf_.size(); ++l) openArea_[nodeOfLeaf_[l]] = area_[nodeOfLeaf_[l]] * leafOpenFraction[l];
  for (std::size_t i = nodes.size(); i-- > 1;)
    if (parent_[i] != kNoNode) openArea_[parent_[i]] += openArea_[i];
  // A cluster's links sample its faces by the light they show, not uniformly: their rays do not
  // count the covered parts out, so it shows its mean over all its area.
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].isCluster()) openArea_[i] = area_[i];
  // Depth first from the root, children in the hierarchy's order.
  sweepOrder_.reserve(nodes.size());
  std::vector<SweepStep> stack{{0, 0}};
  while (!stack.empty()) {
    const SweepStep step = stack.back();
    stack.pop_back();
    sweepOrder_.push_back(step);
    sweepDepth_ = std::max<std::size_t>(sweepDepth_, step.depth + 1);
    const std::span<const std::uint32_t> children = hierarchy.children(step.node);
    for (std::size_t c = children.size(); c-- > 0;) stack.push_back({children[c], step.depth + 1});
  }
  LAMBERT_CHECK(sweepOrder_.size() == nodes.size());
}

void HierarchicalTransport::pull(const std::vector<Rgb>& radiosity, std::vector<Rgb>& mean) const {
  const std::size_t n = parent_.size();
  mean.assign(n, Rgb{});  // power first, W per scene unit² of radiosity
  for (std::size_t l = 0; l < nodeOfLeaf_.size(); ++l) mean[nodeOfLeaf_[l]] = radiosity[l] * area_[nodeOfLeaf_[l]];
  // Children have larger indices than their parents: going down the indices, each node's power is
  // whole when it is reached, handed to its parent and turned into its mean.
  for (std::size_t i = n; i-- > 0;) {
    const Rgb power = mean[i];
    if (parent_[i] != kNoNode) mean[parent_[i]] += power;
    mean[i] = openArea_[i] > 0 ? power / openArea_[i] : Rgb{};
  }
}

Rgb HierarchicalTransport::gatherNode(std::uint32_t node, const std::vector<Rgb>& mean) const {
  const Links& links = *links_;
  double r = 0, g = 0, b = 0;
  for (std::uint32_t k = links.start[node]; k < links.start[node + 1]; ++k) {
    const double f = links.formFactor[k];
    const Rgb& s = mean[links.source[k]];
    r += f * s.r;
    g += f * s.g;
    b += f * s.b;
  }
  return {r, g, b};
}

void HierarchicalTransport::gather(const std::vector<Rgb>& radiosity, std::vector<Rgb>& irradiance) const {
  LAMBERT_CHECK(radiosity.size() == size());
  irradiance.resize(size());
  if (communicator_) {
    irradiance = exchangeOwn(gatherOwn(radiosity));
    return;
  }
  const std::size_t n = parent_.size();
  std::vector<Rgb> mean, gathered(n);
  pull(radiosity, mean);
  parallelFor(0, n, [&](std::size_t i) { gathered[i] = gatherNode(static_cast<std::uint32_t>(i), mean); }, 256);
  // Push: parents come first, so each node adds what every ancestor gathered.
  for (std::size_t i = 1; i < n; ++i)
    if (parent_[i] != kNoNode) gathered[i] += gathered[parent_[i]];
  for (std::size_t l = 0; l < nodeOfLeaf_.size(); ++l) irradiance[l] = gathered[nodeOfLeaf_[l]] * leafGain_[l];
}

std::vector<Rgb> HierarchicalTransport::gatherOwn(const std::vector<Rgb>& radiosity) const {
  // Gather and push along this rank's paths only, as gather() does over every node.
  const std::size_t n = parent_.size();
  std::vector<Rgb> gathered(n);
  const std::vector<Rgb> mean = exchangeMeans(radiosity);
  parallelFor(0, ownPath_.size(), [&](std::size_t k) { gathered[ownPath_[k]] = gatherNode(ownPath_[k], mean); }, 256);
  for (std::uint32_t i : ownPath_)
    if (parent_[i] != kNoNode) gathered[i] += gathered[parent_[i]];
  const std::span<const std::uint32_t> own = ownLeaves();
  std::vector<Rgb> irradiance(own.size());
  for (std::size_t k = 0; k < own.size(); ++k) irradiance[k] = gathered[nodeOfLeaf_[own[k]]] * leafGain_[own[k]];
  return irradiance;
}

std::vector<Rgb> HierarchicalTransport::exchangeOwn(const std::vector<Rgb>& mine) const {
  static_assert(sizeof(Rgb) == 3 * sizeof(double));
  std::vector<Rgb> all(leavesByRank_.size()), byLeaf(leavesByRank_.size());
  const Timer exchange;
  communicator_->allGather<Rgb>(mine, leavesPerRank_, all);
  sweepCommunicationSeconds_ += exchange.seconds();
  for (std::size_t k = 0; k < leavesByRank_.size(); ++k) byLeaf[leavesByRank_[k]] = all[k];
  return byLeaf;
}

void HierarchicalTransport::distribute(std::shared_ptr<Communicator> communicator, std::span<const int> nodeRank) {
  LAMBERT_CHECK(communicator && communicator->size() >= 1 && nodeRank.size() == parent_.size());
  communicator_ = std::move(communicator);
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
  planExchange();
  // The row sums and their bound over this rank's leaves only: the others' links are not here.
  largestRowSum_ = 0;
  rowsScaled_ = 0;
  for (std::uint32_t l : ownLeaves()) {
    largestRowSum_ = std::fmax(largestRowSum_, leafRowSum_[l]);
    rowsScaled_ += leafScaled_[l];
  }
}

void HierarchicalTransport::planExchange() {
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

std::vector<Rgb> HierarchicalTransport::exchangeMeans(const std::vector<Rgb>& radiosity) const {
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
    if (const std::uint32_t p = parent_[i]; p != kNoNode && nodeOwner_[p] == me) power[p] += power[i];
  }
  std::vector<Rgb> sent(sentNodes_.size()), all(receivedNodes_.size());
  for (std::size_t k = 0; k < sentNodes_.size(); ++k) sent[k] = power[sentNodes_[k]];
  const Timer exchange;
  communicator_->allGather<Rgb>(sent, sentPerRank_, all);
  sweepCommunicationSeconds_ += exchange.seconds();
  for (std::size_t k = 0; k < receivedNodes_.size(); ++k) power[receivedNodes_[k]] = all[k];
  for (std::size_t k = combined_.size(); k-- > 0;)
    if (const std::uint32_t p = parent_[combined_[k]]; p != kNoNode) power[p] += power[combined_[k]];
  std::vector<Rgb>& mean = power;
  for (std::size_t i = 0; i < n; ++i) mean[i] = openArea_[i] > 0 ? power[i] / openArea_[i] : Rgb{};
  return mean;
}

std::span<const std::uint32_t> HierarchicalTransport::ownLeaves() const {
  if (!communicator_) return {};
  const auto r = static_cast<std::size_t>(communicator_->rank());
  return std::span<const std::uint32_t>(leavesByRank_).subspan(firstLeaf_[r], firstLeaf_[r + 1] - firstLeaf_[r]);
}

void HierarchicalTransport::completeSweeps(std::vector<Rgb>& radiosity) const {
  if (!communicator_) return;
  const std::span<const std::uint32_t> own = ownLeaves();
  std::vector<Rgb> mine(own.size());
  for (std::size_t k = 0; k < own.size(); ++k) mine[k] = radiosity[own[k]];
  radiosity = exchangeOwn(mine);
}

SweepChange HierarchicalTransport::sweep(const std::vector<Rgb>& emitted, const std::vector<Rgb>& albedo,
                                         std::vector<Rgb>& radiosity, bool inPlace) const {
  SweepChange change;
  if (communicator_) {
    LAMBERT_CHECK(!inPlace);  // the engine sweeps a distributed solve by Jacobi (engine/radiosity.cpp)
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
  if (!inPlace) {
    std::vector<Rgb> irradiance;
    gather(radiosity, irradiance);
    for (std::size_t l = 0; l < radiosity.size(); ++l) {
      Rgb updated = emitted[l] + albedo[l] * irradiance[l];
      change.change = std::fmax(change.change, largestChange(updated, radiosity[l]));
      change.magnitude = std::fmax(change.magnitude, updated.maxComponent());
      radiosity[l] = updated;
    }
    return change;
  }
  const std::size_t n = parent_.size();
  std::vector<Rgb> mean;
  pull(radiosity, mean);
  // Along the path from the root to the node being swept, per depth: the node, what it and its
  // ancestors gathered, and the power its leaves changed that its mean does not hold yet (W).
  std::vector<std::uint32_t> nodeAt(sweepDepth_);
  std::vector<Rgb> pushedAt(sweepDepth_), unpulledAt(sweepDepth_);
  for (std::size_t k = 0; k < n; ++k) {
    const auto [i, depth] = sweepOrder_[k];
    nodeAt[depth] = i;
    pushedAt[depth] = depth > 0 ? gatherNode(i, mean) + pushedAt[depth - 1] : gatherNode(i, mean);
    unpulledAt[depth] = Rgb{};
    if (const std::uint32_t l = leafOfNode_[i]; l != kNoNode) {
      const Rgb updated = emitted[l] + albedo[l] * pushedAt[depth] * leafGain_[l];
      change.change = std::fmax(change.change, largestChange(updated, radiosity[l]));
      change.magnitude = std::fmax(change.magnitude, updated.maxComponent());
      unpulledAt[depth] = (updated - radiosity[l]) * area_[i];
      radiosity[l] = updated;
    }
    // The subtrees that end here (the next node's depth and deeper on the path) take their
    // leaves' change into their means and hand it up.
    const std::uint32_t next = k + 1 < n ? sweepOrder_[k + 1].depth : 0;
    for (std::uint32_t d = depth + 1; d-- > next;) {
      const std::uint32_t a = nodeAt[d];
      if (openArea_[a] > 0) mean[a] += unpulledAt[d] / openArea_[a];
      if (d > 0) unpulledAt[d - 1] += unpulledAt[d];
    }
  }
  return change;
}

}  // namespace lambert
