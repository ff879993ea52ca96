#include "lambert/hierarchical/transport.h"

#include <algorithm>
#include <bit>
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
  // count the covered parts out, so it shows its mean over all its area, but for the faces inside
  // closed two-sided objects (geometry/enclosures.h), which no link sees: over them too, the
  // mean of a two-sided wall's cluster was half what its room side shows, and a link whose K
  // was estimated before that side was lit (the faces alike) carried half its light.
  const std::vector<double> unenclosed = hierarchy.unenclosedAreas();
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].isCluster()) openArea_[i] = unenclosed[i];
  // Depth first from the root, children in the hierarchy's order.
  sweepOrder_.reserve(nodes.size());
  std::vector<SweepStep> stack{{0, 0, 0}};
  while (!stack.empty()) {
    SweepStep step = stack.back();
    stack.pop_back();
    step.step = static_cast<std::uint32_t>(sweepOrder_.size());
    sweepOrder_.push_back(step);
    sweepDepth_ = std::max<std::size_t>(sweepDepth_, step.depth + 1);
    const std::span<const std::uint32_t> children = hierarchy.children(step.node);
    for (std::size_t c = children.size(); c-- > 0;) stack.push_back({children[c], step.depth + 1, 0});
  }
  LAMBERT_CHECK(sweepOrder_.size() == nodes.size());
  shareBins(hierarchy, leafOpenFraction);
  // Σ K of each node's own links (a cluster's also in its bins), and Σ K · A_r over the links from each node.
  std::vector<double> gathers(nodes.size(), 0.0), sends(nodes.size(), 0.0);
  std::vector<std::array<double, kBins>> clusterGathers(nodes.size(), std::array<double, kBins>{});
  for (std::size_t r = 0; r < nodes.size(); ++r)
    for (std::uint32_t k = links_->start[r]; k < links_->start[r + 1]; ++k) {
      gathers[r] += links_->formFactor[k];
      sends[links_->source[k]] += links_->formFactor[k] * openArea_[r];
      if (isCluster_[r]) {
        const std::array<double, kBins> share = binShares(links_->facing[k]);
        for (int b = 0; b < kBins; ++b) clusterGathers[r][b] += links_->formFactor[k] * share[b];
      }
    }
  weigh(hierarchy, gathers, clusterGathers, sends, leafOpenFraction, leafAlbedo);
}

std::array<double, HierarchicalTransport::kBins> HierarchicalTransport::binShares(const std::array<std::uint8_t, 6>& facing) {
  std::array<double, kBins> share{};
  const int total = facing[0] + facing[1] + facing[2] + facing[3] + facing[4] + facing[5];
  if (total == 0) {
    share[6] = 1;
    return share;
  }
  for (int b = 0; b < 6; ++b) share[b] = facing[b] / static_cast<double>(total);
  return share;
}

void HierarchicalTransport::shareBins(const ElementHierarchy& hierarchy, std::span<const double> leafOpenFraction) {
  const auto& nodes = hierarchy.nodes();
  const std::size_t n = nodes.size();
  LAMBERT_CHECK(links_->facing.size() == links_->size());
  isCluster_.resize(n);
  for (std::size_t r = 0; r < n; ++r) isCluster_[r] = nodes[r].isCluster();
  clusterLinkStart_.assign(n, 0);
  std::uint32_t clusterLinks = 0;
  for (std::size_t r = 0; r < n; ++r) {
    clusterLinkStart_[r] = clusterLinks;
    if (isCluster_[r]) clusterLinks += links_->start[r + 1] - links_->start[r];
  }
  clusterLinkWeights_.resize(clusterLinks);
  for (std::size_t r = 0; r < n; ++r) {
    if (!isCluster_[r]) continue;
    for (std::uint32_t k = links_->start[r]; k < links_->start[r + 1]; ++k) {
      const std::array<double, kBins> share = binShares(links_->facing[k]);
      ClusterLinkWeights& w = clusterLinkWeights_[clusterLinkStart_[r] + (k - links_->start[r])];
      w.mask = 0;
      for (int b = 0; b < kBins; ++b) {
        w.weight[b] = static_cast<float>(links_->formFactor[k] * share[b]);
        if (w.weight[b] != 0) w.mask |= static_cast<std::uint8_t>(1u << b);
      }
    }
  }
  // Per node, the open area of the leaves under it (what a link's K is the irradiance of: covered
  // and enclosed points are left out of its rays) and that area projected on each axis side.
  std::vector<double> open(n, 0.0);
  std::vector<std::array<double, 6>> openAxis(n, std::array<double, 6>{});
  for (std::size_t l = 0; l < nodeOfLeaf_.size(); ++l) {
    const HierarchyNode& leaf = nodes[nodeOfLeaf_[l]];
    const double a = leaf.area * leafOpenFraction[l];
    open[nodeOfLeaf_[l]] = a;
    const double components[3] = {leaf.normal.x, leaf.normal.y, leaf.normal.z};
    for (int k = 0; k < 3; ++k) openAxis[nodeOfLeaf_[l]][axisSide(k, components[k])] = a * std::fabs(components[k]);
  }
  for (std::size_t i = n; i-- > 1;)  // children have larger indices than their parents
    if (const std::uint32_t p = parent_[i]; p != kNoNode) {
      open[p] += open[i];
      for (int b = 0; b < 6; ++b) openAxis[p][b] += openAxis[i][b];
    }
  // Each child of a cluster: its open projected area on each axis side over its siblings', times
  // the parent's open area over its own (1 on a side none of the siblings shows: the bin is then
  // handed out by area, as the undirected push did).
  // Held in the sweep's order, which reads them one after another.
  std::vector<std::uint32_t> stepOfNode(n);
  for (const SweepStep& step : sweepOrder_) stepOfNode[step.node] = step.step;
  foldWeight_.assign(n, std::array<float, kBins>{1, 1, 1, 1, 1, 1, 1});
  for (std::size_t p = 0; p < n; ++p) {
    if (!isCluster_[p]) continue;
    std::array<double, 6> siblings{};
    for (std::uint32_t c : hierarchy.children(static_cast<std::uint32_t>(p)))
      for (int b = 0; b < 6; ++b) siblings[b] += openAxis[c][b];
    for (std::uint32_t c : hierarchy.children(static_cast<std::uint32_t>(p)))
      for (int b = 0; b < 6; ++b)
        if (siblings[b] > 1e-9 * open[p] && open[c] > 0)
          foldWeight_[stepOfNode[c]][b] = static_cast<float>(openAxis[c][b] / siblings[b] * open[p] / open[c]);
  }
  foldMask_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    foldMask_[k] = 0;
    for (int b = 0; b < kBins; ++b)
      if (foldWeight_[k][b] != 0) foldMask_[k] |= static_cast<std::uint8_t>(1u << b);
  }
}

std::vector<double> HierarchicalTransport::handedFromAbove(std::span<const double> own, std::span<const std::array<double, kBins>> ownBins,
                                                          bool weighted) const {
  const std::size_t n = parent_.size();
  std::vector<double> arriving(n, 0.0), total(n, 0.0);
  std::vector<std::array<double, kBins>> bins(n, std::array<double, kBins>{});
  // Parents come before their children.
  for (const auto& [i, depth, step] : sweepOrder_) {
    const std::uint32_t p = parent_[i];
    if (p != kNoNode) {
      if (isCluster_[p]) {
        double folded = 0;
        for (int b = 0; b < kBins; ++b) {
          const double handed = bins[p][b] * foldWeight_[step][b];
          folded += handed;
          if (isCluster_[i]) bins[i][b] = handed;
        }
        arriving[i] = folded;
      } else {
        arriving[i] = total[p];
      }
    }
    if (isCluster_[i])
      for (int b = 0; b < kBins; ++b) bins[i][b] += ownBins[i][b];
    else
      total[i] = own[i] + (weighted ? pushWeight_[i] : 1.0) * arriving[i];
  }
  return arriving;
}

std::vector<double> HierarchicalTransport::unclaimedWeights(const ElementHierarchy& hierarchy, std::span<const double> claimedShare,
                                                           std::span<const double> leafOpenFraction, std::span<const double> above) const {
  const auto& nodes = hierarchy.nodes();
  // Per element, its open area × the share left unclaimed, summed over its leaves: 1 − Σ claimedShare
  // over the path from the leaf up to the element (never below 0). With `above`: the share of what
  // the ancestors claim that fits in that, 1 where all does.
  const bool whereOverflowing = !above.empty();
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

void HierarchicalTransport::weigh(const ElementHierarchy& hierarchy, std::span<const double> gathers,
                                  std::span<const std::array<double, kBins>> clusterGathers, std::span<const double> sends,
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
  pushWeight_ = unclaimedWeights(hierarchy, gathers, leafOpenFraction, handedFromAbove(gathers, clusterGathers, false));
  std::vector<double> sent(nodes.size(), 0.0);
  for (std::size_t i = 0; i < nodes.size(); ++i) sent[i] = openArea_[i] > 0 ? sends[i] / openArea_[i] : 0.0;
  pullWeight_ = unclaimedWeights(hierarchy, sent, leafOpenFraction, {});
  // Σ K over each node's links and its ancestors', as the push hands them down.
  const std::vector<double> arriving = handedFromAbove(gathers, clusterGathers, true);
  std::vector<double> rowSum(nodes.size(), 0.0);
  for (std::size_t i = 0; i < nodes.size(); ++i) rowSum[i] = gathers[i] + pushWeight_[i] * arriving[i];
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

std::uint8_t HierarchicalTransport::gatherBins(std::uint32_t cluster, const std::vector<Rgb>& mean, Bins& bins) const {
  const Links& links = *links_;
  std::uint8_t filled = 0;
  const ClusterLinkWeights* w = clusterLinkWeights_.data() + clusterLinkStart_[cluster];
  for (std::uint32_t k = links.start[cluster]; k < links.start[cluster + 1]; ++k, ++w) {
    const Rgb& source = mean[links.source[k]];
    for (unsigned m = w->mask; m; m &= m - 1) {
      const int b = std::countr_zero(m);
      if (!(filled & (1u << b))) {
        bins[b] = Rgb{};
        filled |= static_cast<std::uint8_t>(1u << b);
      }
      bins[b] += source * static_cast<double>(w->weight[b]);
    }
  }
  return filled;
}

void HierarchicalTransport::handDown(const SweepStep& at, const Handed* parent, const std::vector<Rgb>& mean, const Rgb* own,
                                     Handed& state, Rgb* leafGathered) const {
  const std::uint32_t i = at.node;
  // What reaches i from its ancestors, before its own links and pushWeight_.
  Rgb arriving;
  const bool fromCluster = parent && isCluster_[parent_[i]];
  if (parent && !fromCluster) arriving = parent->total;
  if (isCluster_[i]) {
    state.binMask = gatherBins(i, mean, state.bins);
    if (fromCluster) {
      const std::array<float, kBins>& fold = foldWeight_[at.step];
      for (unsigned m = parent->binMask & foldMask_[at.step]; m; m &= m - 1) {
        const int b = std::countr_zero(m);
        const Rgb handed = parent->bins[b] * static_cast<double>(fold[b]);
        if (state.binMask & (1u << b)) {
          state.bins[b] += handed;
        } else {
          state.bins[b] = handed;
          state.binMask |= static_cast<std::uint8_t>(1u << b);
        }
      }
    }
    return;
  }
  if (fromCluster) {
    const std::array<float, kBins>& fold = foldWeight_[at.step];
    for (unsigned m = parent->binMask & foldMask_[at.step]; m; m &= m - 1) {
      const int b = std::countr_zero(m);
      arriving += parent->bins[b] * static_cast<double>(fold[b]);
    }
  }
  const Rgb mine = own ? *own : gatherNode(i, mean);
  if (const std::uint32_t l = leafOfNode_[i]; l != kNoNode) {
    if (leafGathered) *leafGathered = mine * leafOwnGain_[l] + arriving * leafAncestorGain_[l];
    return;
  }
  state.total = mine + arriving * pushWeight_[i];
}

void HierarchicalTransport::pushAlong(std::span<const SweepStep> order, const std::vector<Rgb>& mean, const std::vector<Rgb>& ownGathered,
                                      std::vector<Rgb>& leafGathered) const {
  std::vector<Handed> path(sweepDepth_);
  for (const SweepStep& at : order) {
    Rgb gathered;
    handDown(at, at.depth > 0 ? &path[at.depth - 1] : nullptr, mean, isCluster_[at.node] ? nullptr : &ownGathered[at.node], path[at.depth], &gathered);
    if (const std::uint32_t l = leafOfNode_[at.node]; l != kNoNode) leafGathered[l] = gathered;
  }
}

void HierarchicalTransport::gather(const std::vector<Rgb>& radiosity, std::vector<Rgb>& irradiance) const {
  LAMBERT_CHECK(radiosity.size() == size());
  irradiance.resize(size());
  const std::size_t n = parent_.size();
  std::vector<Rgb> mean, gathered(n);
  pullWeighted(radiosity, mean, pullWeight_);
  // The elements' own links in parallel; the clusters' as the push passes them.
  parallelFor(0, n, [&](std::size_t i) { if (!isCluster_[i]) gathered[i] = gatherNode(static_cast<std::uint32_t>(i), mean); }, 256);
  pushAlong(sweepOrder_, mean, gathered, irradiance);
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
  std::vector<Handed> pushedAt(sweepDepth_);
  std::vector<Rgb> unpulledAt(sweepDepth_);
  for (std::size_t k = 0; k < n; ++k) {
    const auto [i, depth, step] = sweepOrder_[k];
    nodeAt[depth] = i;
    Rgb gathered;
    handDown(sweepOrder_[k], depth > 0 ? &pushedAt[depth - 1] : nullptr, mean, nullptr, pushedAt[depth], &gathered);
    unpulledAt[depth] = Rgb{};
    if (const std::uint32_t l = leafOfNode_[i]; l != kNoNode) {
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
