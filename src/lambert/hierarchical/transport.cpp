#include "lambert/hierarchical/transport.h"

#include <algorithm>
#include <cmath>

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/solve/row_contraction.h"

namespace lambert {

double HierarchicalTransport::largestChange(const Rgb& a, const Rgb& b) {
  return std::fmax(std::fabs(a.r - b.r), std::fmax(std::fabs(a.g - b.g), std::fabs(a.b - b.b)));
}

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
  for (std::size_t l = 0; l < nodeOfLeaf_.size(); ++l) openArea_[nodeOfLeaf_[l]] = area_[nodeOfLeaf_[l]] * leafOpenFraction[l];
  for (std::size_t i = nodes.size(); i-- > 1;)
    if (parent_[i] != kNoNode) openArea_[parent_[i]] += openArea_[i];
  // A cluster's links sample its faces by the light they show, not uniformly: their rays do not
  // count the covered parts out, so it shows its mean over all its area.
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].isCluster()) openArea_[i] = area_[i];
  // Σ K of each node's own links, and Σ K · A_r over the links from each node.
  std::vector<double> gathers(nodes.size(), 0.0), sends(nodes.size(), 0.0);
  for (std::size_t r = 0; r < nodes.size(); ++r)
    for (std::uint32_t k = links_->start[r]; k < links_->start[r + 1]; ++k) {
      gathers[r] += links_->formFactor[k];
      sends[links_->source[k]] += links_->formFactor[k] * openArea_[r];
    }
  weigh(hierarchy, gathers, sends, leafOpenFraction, leafAlbedo);
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

std::vector<double> HierarchicalTransport::unclaimedWeights(const ElementHierarchy& hierarchy, std::span<const double> claimedShare,
                                                           std::span<const double> leafOpenFraction, bool whereOverflowing) const {
  const auto& nodes = hierarchy.nodes();
  // Per element, its open area × the share left unclaimed, summed over its leaves: 1 − Σ claimedShare
  // over the path from the leaf up to the element (never below 0). whereOverflowing: the share of
  // what the ancestors claim (Σ claimedShare above the element) that fits in that, 1 where all does.
  std::vector<double> above(nodes.size(), 0.0);
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (parent_[i] != kNoNode) above[i] = above[parent_[i]] + claimedShare[parent_[i]];
  std::vector<double> unclaimed(nodes.size(), 0.0);
  for (std::size_t l = 0; l < nodeOfLeaf_.size(); ++l) {
    double claimed = 0;
    for (std::uint32_t i = nodeOfLeaf_[l]; i != kNoNode && !nodes[i].isCluster(); i = parent_[i]) {
      claimed += claimedShare[i];
      const double free = std::fmax(0.0, 1.0 - claimed);
      const double share = !whereOverflowing ? free : above[i] > free ? free / above[i] : 1.0;
      unclaimed[i] += area_[nodeOfLeaf_[l]] * leafOpenFraction[l] * share;
    }
  }
  // Each element child of an element: its unclaimed share over its siblings' mean, so that the
  // weights, by open area, sum to the parent's open area. Where every child is claimed whole, 1.
  std::vector<double> weight(nodes.size(), 1.0);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const std::uint32_t p = parent_[i];
    if (nodes[i].isCluster() || p == kNoNode || nodes[p].isCluster() || !(openArea_[i] > 0)) continue;
    double siblings = 0;
    for (std::uint32_t c : hierarchy.children(p)) siblings += unclaimed[c];
    if (siblings > 1e-9 * openArea_[p]) weight[i] = (unclaimed[i] / openArea_[i]) / (siblings / openArea_[p]);
  }
  return weight;
}

void HierarchicalTransport::weigh(const ElementHierarchy& hierarchy, std::span<const double> gathers, std::span<const double> sends,
                                  std::span<const double> leafOpenFraction, std::span<const Rgb> leafAlbedo) {
  const auto& nodes = hierarchy.nodes();
  largestRowSum_ = 0;
  rowsScaled_ = 0;
  // The push-down's weights: the share of what the ancestors' links gather that fits in the part
  // of each element's hemisphere its own links and those below it leave free (only where it
  // overflows: a coarse link's light comes from its source's direction, not from wherever the
  // hemisphere is free; weighing by the free share everywhere gave a floor leaf beside a block
  // less of the lamp, whose side claims half its hemisphere elsewhere). The pull's: the share of
  // each element's light the links from it and from the elements below it leave unsent (only
  // where it overflows, the column sums of CIE 171 §5.8's cube lost 0.9–2.4%).
  pushWeight_ = unclaimedWeights(hierarchy, gathers, leafOpenFraction, true);
  std::vector<double> sent(nodes.size(), 0.0);
  for (std::size_t i = 0; i < nodes.size(); ++i) sent[i] = openArea_[i] > 0 ? sends[i] / openArea_[i] : 0.0;
  pullWeight_ = unclaimedWeights(hierarchy, sent, leafOpenFraction, false);
  // Σ K over each node's links and its ancestors', as the push hands them down (parents have
  // smaller indices).
  std::vector<double> rowSum(nodes.size(), 0.0);
  for (std::size_t i = 0; i < nodes.size(); ++i) rowSum[i] = gathers[i] + (parent_[i] != kNoNode ? pushWeight_[i] * rowSum[parent_[i]] : 0.0);
  leafOwnGain_.resize(nodeOfLeaf_.size());
  leafAncestorGain_.resize(nodeOfLeaf_.size());
  leafRowSum_.resize(nodeOfLeaf_.size());
  leafScaled_.resize(nodeOfLeaf_.size());
  for (std::size_t l = 0; l < nodeOfLeaf_.size(); ++l) {
    const std::uint32_t node = nodeOfLeaf_[l];
    const double sum = rowSum[node], own = gathers[node], ancestors = sum - own;
    LAMBERT_CHECK(std::isfinite(sum) && sum >= 0);
    largestRowSum_ = std::fmax(largestRowSum_, sum);
    const double rho = leafAlbedo[l].maxComponent();
    const bool scale = rho * sum > rowContractionBound(rho);
    rowsScaled_ += scale;
    leafRowSum_[l] = sum;
    leafScaled_[l] = scale;
    const double ownKept = std::fmin(own, 1.0);
    const double ancestorsKept = scale && ancestors > 0 ? std::fmax(0.0, 1.0 - ownKept) / ancestors : 1.0;
    leafOwnGain_[l] = leafOpenFraction[l] * (scale && own > 1 ? 1 / own : 1.0);
    leafAncestorGain_[l] = leafOpenFraction[l] * std::fmin(1.0, ancestorsKept) * pushWeight_[node];
  }
}

void HierarchicalTransport::pull(const std::vector<Rgb>& radiosity, std::vector<Rgb>& mean) const {
  pullWeighted(radiosity, mean, {});
}

void HierarchicalTransport::pullWeighted(const std::vector<Rgb>& radiosity, std::vector<Rgb>& mean, std::span<const double> weight) const {
  const std::size_t n = parent_.size();
  mean.assign(n, Rgb{});  // power first, W per scene unit² of radiosity
  for (std::size_t l = 0; l < nodeOfLeaf_.size(); ++l) mean[nodeOfLeaf_[l]] = radiosity[l] * area_[nodeOfLeaf_[l]];
  // Children have larger indices than their parents: going down the indices, each node's power is
  // whole when it is reached, handed to its parent (by its weight, if any) and turned into its mean.
  for (std::size_t i = n; i-- > 0;) {
    const Rgb power = mean[i];
    if (parent_[i] != kNoNode) mean[parent_[i]] += weight.empty() ? power : power * weight[i];
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

Rgb HierarchicalTransport::leafIrradiance(std::size_t leaf, const std::vector<Rgb>& gathered) const {
  const std::uint32_t node = nodeOfLeaf_[leaf], parent = parent_[node];
  const Rgb ancestors = parent != kNoNode ? gathered[parent] * leafAncestorGain_[leaf] : Rgb{};
  return gathered[node] * leafOwnGain_[leaf] + ancestors;
}

void HierarchicalTransport::gather(const std::vector<Rgb>& radiosity, std::vector<Rgb>& irradiance) const {
  LAMBERT_CHECK(radiosity.size() == size());
  irradiance.resize(size());
  const std::size_t n = parent_.size();
  std::vector<Rgb> mean, gathered(n);
  pullWeighted(radiosity, mean, pullWeight_);
  parallelFor(0, n, [&](std::size_t i) { gathered[i] = gatherNode(static_cast<std::uint32_t>(i), mean); }, 256);
  // Push: parents come first, so each node adds what every ancestor gathered.
  for (std::size_t i = 1; i < n; ++i)
    if (parent_[i] != kNoNode && leafOfNode_[i] == kNoNode) gathered[i] += gathered[parent_[i]] * pushWeight_[i];
  for (std::size_t l = 0; l < nodeOfLeaf_.size(); ++l) irradiance[l] = leafIrradiance(l, gathered);
}

SweepChange HierarchicalTransport::sweep(const std::vector<Rgb>& emitted, const std::vector<Rgb>& albedo,
                                         std::vector<Rgb>& radiosity, bool inPlace) const {
  SweepChange change;
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
  pullWeighted(radiosity, mean, pullWeight_);
  // Along the path from the root to the node being swept, per depth: the node, what it and its
  // ancestors gathered, and the power its leaves changed that its mean does not hold yet (W).
  std::vector<std::uint32_t> nodeAt(sweepDepth_);
  std::vector<Rgb> pushedAt(sweepDepth_), unpulledAt(sweepDepth_);
  for (std::size_t k = 0; k < n; ++k) {
    const auto [i, depth] = sweepOrder_[k];
    nodeAt[depth] = i;
    const Rgb own = gatherNode(i, mean);
    pushedAt[depth] = depth > 0 ? own + pushedAt[depth - 1] * pushWeight_[i] : own;
    unpulledAt[depth] = Rgb{};
    if (const std::uint32_t l = leafOfNode_[i]; l != kNoNode) {
      const Rgb gathered = own * leafOwnGain_[l] + (depth > 0 ? pushedAt[depth - 1] * leafAncestorGain_[l] : Rgb{});
      const Rgb updated = emitted[l] + albedo[l] * gathered;
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
      if (d > 0) unpulledAt[d - 1] += unpulledAt[d] * pullWeight_[a];
    }
  }
  return change;
}

}  // namespace lambert
