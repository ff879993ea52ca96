#include "lambert/hierarchical/final_gather.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/formfactor/kernels.h"
#include "lambert/geometry/coverage.h"
#include "lambert/hierarchical/final_gather_outputs.h"

namespace lambert {
namespace {

// A source node whose bounding sphere is wider than this share of its distance from the vertex
// may be gathered from its children instead (a cluster always is)...
constexpr double kOpeningRatio = 0.5;
// ...an element only where that can change the vertex's irradiance by more than this share.
constexpr double kOpeningTolerance = 1e-3;
// Sources whose link's rays all got through have their visibility resolved at the vertex, the
// largest first, until those left bring less than this share of the vertex's irradiance together.
constexpr double kResolveShare = 0.003;
// Far clusters whose link's rays were partly blocked have their visibility resolved at a vertex,
// the largest first, until those left bring less than this share of its irradiance together
// (SiteGather::resolveClusters).
constexpr double kResolveClusterShare = 0.02;

// Levels below an element gathered whole over which its radiosity's shape is followed.
constexpr int kShapeDepth = 2;
// A source's brightest leaf over its mean beyond which its hidden part matters (variesBehind).
constexpr double kVariesBehind = 2.0;

// An element source as the vertex sees it: what it brings, and whether the rays to it
// disagree (a shadow edge crosses it as seen from here).
struct Term {
  std::uint32_t link, source;
  bool resolvesVisibility;  // the rays to it are cast here, so its children's would be too
  double factor, seen;
  bool mixed;
  bool resolvable = false;  // an element receiver's link whose rays all got through: seen = 1 so far
};

// A far cluster source gathered at a vertex with its link's visibility, some of whose rays were
// blocked: what it brings unoccluded (its light toward the vertex × the kernel), the visibility
// taken, and its entry among the weights (or kNoWeight).
struct ClusterTerm {
  static constexpr std::size_t kNoWeight = static_cast<std::size_t>(-1);
  std::uint32_t link, source;
  Rgb unoccluded;
  double seen;
  double weightPerSeen;  // its weight over the visibility
  std::size_t weight;
};

// Per thread, reused from vertex to vertex (about a hundred terms each: not allocated anew).
struct Scratch {
  std::vector<Term> terms;
  std::vector<ClusterTerm> partlySeenClusters;
  std::vector<std::uint32_t> open;  // sources still to gather
  std::vector<std::pair<std::uint32_t, double>> clusterTerms;  // (cluster source, factor × visibility)
  std::vector<std::pair<double, std::uint32_t>> candidates;  // (what it brings, term)
  std::vector<Term> pending, gatheredTerms;
  std::vector<std::pair<std::uint32_t, double>> entries;  // the site's weights on the node means
};

// The lowest and highest radiosity of the leaves under each node, per channel; and per cluster
// the power its leaves send toward each axis direction, Σ B·A_open·max(0, ±n_axis) over them
// (+x, −x, +y, −y, +z, −z), so that a far cluster shows each direction the light of the faces
// that face it. A luminaire's emitting strip faces down and its housing up and sideways: with the
// cluster's mean radiosity over all its faces times the area it shows, RenderPark's classroom
// desks got 55% of their light and the ceiling above the lamps 2.7 times its own.
struct LeafRange {
  std::vector<Rgb> lowest, highest;
  std::vector<std::uint32_t> clusterSlot;    // per node: its index in axisPower, or kNoNode
  std::vector<std::array<Rgb, 6>> axisPower;  // per cluster
  // Per cluster and axis direction: where the light it sends that way comes from, the centroid
  // of its leaves weighted by the power they send that way (the box's centre where they send
  // none). A cluster of floor pieces and the luminaires over them sends its light down from the
  // luminaires: from its box's centre, half way down, the floor's far vertices saw it at half the
  // elevation and got half its light. And it sends its light up from the floor and the tables'
  // tops, not from the luminaires' strips (which face down): with one centroid for every
  // direction, at the strips, the ceiling 20 cm over them saw the tables' light level with it
  // and lost a fifth to a third of it.
  std::vector<std::array<Vec3, 6>> lightCentre;

  // Where cluster s's light toward u (any length) comes from: the centroids of the sides u faces,
  // weighted by |u_axis| × the power sent that way.
  Vec3 lightCentreToward(std::uint32_t s, const Vec3& u, const Vec3& boxCentre) const {
    const std::uint32_t slot = clusterSlot[s];
    const std::array<Rgb, 6>& p = axisPower[slot];
    const double components[3] = {u.x, u.y, u.z};
    Vec3 sum;
    double total = 0;
    for (int a = 0; a < 3; ++a) {
      const int side = axisSide(a, components[a]);
      const double w = std::fabs(components[a]) * (p[side].r + p[side].g + p[side].b);
      sum += lightCentre[slot][side] * w;
      total += w;
    }
    return total > 0 ? sum / total : boxCentre;
  }

  // What cluster s sends toward the unit direction u, per steradian × π: Σ |u_axis| × the power
  // toward u's side of that axis (B̄ × the area shown, for a cluster of uniform radiosity).
  Rgb shownToward(std::uint32_t s, const Vec3& u) const {
    const std::array<Rgb, 6>& p = axisPower[clusterSlot[s]];
    return p[u.x > 0 ? 0 : 1] * std::fabs(u.x) + p[u.y > 0 ? 2 : 3] * std::fabs(u.y) + p[u.z > 0 ? 4 : 5] * std::fabs(u.z);
  }
};

LeafRange leafRange(const ElementHierarchy& hierarchy, const Mesh& leaves, const std::vector<Rgb>& mean) {
  const std::size_t numNodes = hierarchy.nodes().size();
  // Children have larger indices than their parents, so one pass in decreasing order sees them
  // first.
  std::vector<Rgb> lowest(mean), highest(mean);
  for (std::size_t i = numNodes; i-- > 0;) {
    if (hierarchy.node(static_cast<std::uint32_t>(i)).isLeaf()) continue;
    Rgb lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    for (std::uint32_t c : hierarchy.children(static_cast<std::uint32_t>(i))) {
      lo = {std::fmin(lo.r, lowest[c].r), std::fmin(lo.g, lowest[c].g), std::fmin(lo.b, lowest[c].b)};
      hi = {std::fmax(hi.r, highest[c].r), std::fmax(hi.g, highest[c].g), std::fmax(hi.b, highest[c].b)};
    }
    lowest[i] = lo;
    highest[i] = hi;
  }
  LeafRange range{std::move(lowest), std::move(highest), std::vector<std::uint32_t>(numNodes, kNoNode), {}, {}};
  for (std::uint32_t i = 0; i < numNodes; ++i)
    if (hierarchy.node(i).isCluster()) {
      range.clusterSlot[i] = static_cast<std::uint32_t>(range.axisPower.size());
      range.axisPower.emplace_back();
    }
  std::vector<std::array<Vec3, 6>> weighted(range.axisPower.size());
  std::vector<std::array<double, 6>> weight(range.axisPower.size(), std::array<double, 6>{});
  for (const std::uint32_t l : hierarchy.leafNodes()) {
    const HierarchyNode& leaf = hierarchy.node(l);
    std::uint32_t cluster = leaf.parent;
    while (cluster != kNoNode && !hierarchy.node(cluster).isCluster()) cluster = hierarchy.node(cluster).parent;
    if (cluster == kNoNode) continue;
    const std::uint32_t slot = range.clusterSlot[cluster];
    const Rgb power = mean[l] * (leaf.area * leaves.patches[leaf.leaf].openFraction);
    std::array<Rgb, 6>& p = range.axisPower[slot];
    const double components[3] = {leaf.normal.x, leaf.normal.y, leaf.normal.z};
    const double w = power.r + power.g + power.b;
    for (int a = 0; a < 3; ++a) {
      const int side = axisSide(a, components[a]);
      p[side] += power * std::fabs(components[a]);
      weighted[slot][side] += leaf.centre * (w * std::fabs(components[a]));
      weight[slot][side] += w * std::fabs(components[a]);
    }
  }
  // Clusters have smaller indices than the clusters under them: children's sums are whole first.
  for (std::size_t i = numNodes; i-- > 1;) {
    const HierarchyNode& node = hierarchy.node(static_cast<std::uint32_t>(i));
    if (!node.isCluster() || node.parent == kNoNode) continue;
    const std::uint32_t up = range.clusterSlot[node.parent], own = range.clusterSlot[i];
    for (int k = 0; k < 6; ++k) {
      range.axisPower[up][k] += range.axisPower[own][k];
      weighted[up][k] += weighted[own][k];
      weight[up][k] += weight[own][k];
    }
  }
  range.lightCentre.resize(range.axisPower.size());
  for (std::uint32_t i = 0; i < numNodes; ++i)
    if (const std::uint32_t slot = range.clusterSlot[i]; slot != kNoNode)
      for (int k = 0; k < 6; ++k)
        range.lightCentre[slot][k] = weight[slot][k] > 0 ? weighted[slot][k] / weight[slot][k] : hierarchy.node(i).centre;
  return range;
}

}  // namespace

std::vector<std::uint32_t> FinalGather::gatheringLeaves(const Mesh& mesh) {
  static_assert(kNoSitePatch == kNoNode, "a vertex without a patch has no gathering leaf");
  return vertexSitePatches(mesh);  // the leaf the vertex's site lies on
}

FinalGather::FinalGather(const ElementHierarchy& hierarchy, const ElementHierarchy::LeafMesh& leaves, const Links& links,
                         const RayCaster& caster, double rayEpsilon, double nudge, int visibilityRays, std::uint64_t seed)
    : FinalGather(hierarchy, leaves, links, caster, rayEpsilon, vertexSites(leaves.mesh, nudge), gatheringLeaves(leaves.mesh),
                  visibilityRays, seed, false) {}

FinalGather::FinalGather(const ElementHierarchy& hierarchy, const ElementHierarchy::LeafMesh& leaves, const Links& links,
                         const RayCaster& caster, double rayEpsilon, std::vector<VertexSite> sites, std::vector<std::uint32_t> leafOfSite,
                         int visibilityRays, std::uint64_t seed, bool resolveClusterVisibility)
    : hierarchy_(hierarchy),
      links_(links),
      caster_(caster),
      epsilon_(rayEpsilon),
      rays_(std::max(1, visibilityRays)),
      seed_(seed),
      resolveClusterVisibility_(resolveClusterVisibility),
      mesh_(leaves.mesh),
      sites_(std::move(sites)),
      leaf_(std::move(leafOfSite)) {
  LAMBERT_CHECK(leaves.mesh.numPatches() == hierarchy.leafNodes().size());
  LAMBERT_CHECK(leaf_.size() == sites_.size());
}

FinalGather FinalGather::throughLeaves(std::vector<std::uint32_t> leafOfSite) const {
  LAMBERT_CHECK(leafOfSite.size() == sites_.size());
  FinalGather gather(*this);
  gather.leaf_ = std::move(leafOfSite);
  return gather;
}

Rgb FinalGather::shapedMean(const VertexSite& site, std::uint32_t s, const std::vector<Rgb>& mean, int depth) const {
  const HierarchyNode& source = hierarchy_.node(s);
  if (source.isLeaf() || depth >= kShapeDepth) return mean[s];
  Rgb sum;
  double total = 0;
  for (std::uint32_t c : hierarchy_.children(s)) {
    const HierarchyNode& child = hierarchy_.node(c);
    const double w = std::fmax(0.0, pointToPointKernel(site.point, site.normal, child.centre, child.normal)) * child.area;
    if (!(w > 0)) continue;
    sum += shapedMean(site, c, mean, depth + 1) * w;
    total += w;
  }
  return total > 0 ? sum * (1 / total) : mean[s];
}

void FinalGather::shapedWeights(const VertexSite& site, std::uint32_t s, double scale,
                                std::vector<std::pair<std::uint32_t, double>>& out, int depth) const {
  // shapedMean's recursion, its children's shares handed down instead of their means summed.
  const HierarchyNode& source = hierarchy_.node(s);
  if (source.isLeaf() || depth >= kShapeDepth) {
    out.push_back({s, scale});
    return;
  }
  double total = 0;
  for (std::uint32_t c : hierarchy_.children(s)) {
    const HierarchyNode& child = hierarchy_.node(c);
    const double w = std::fmax(0.0, pointToPointKernel(site.point, site.normal, child.centre, child.normal)) * child.area;
    if (w > 0) total += w;
  }
  if (!(total > 0)) {
    out.push_back({s, scale});
    return;
  }
  for (std::uint32_t c : hierarchy_.children(s)) {
    const HierarchyNode& child = hierarchy_.node(c);
    const double w = std::fmax(0.0, pointToPointKernel(site.point, site.normal, child.centre, child.normal)) * child.area;
    if (w > 0) shapedWeights(site, c, scale * (w / total), out, depth + 1);
  }
}

// One site's gather, in the steps final_gather.h describes: every link's source taken whole
// (clusters opened close by), the largest sources' visibility resolved at the site, the elements
// seen from close by opened to their children, and the radiosity's shape under the elements
// gathered whole; then the site's share of the outputs asked for (final_gather_outputs.h).
class FinalGather::SiteGather {
 public:
  SiteGather(const FinalGather& gather, std::uint32_t v, const std::vector<Rgb>& mean, const LeafRange& range, GatherOutputs& outputs)
      : g_(gather),
        v_(v),
        site_(gather.sites_[v]),
        mean_(mean),
        range_(range),
        outputs_(outputs),
        tally_(outputs.work(v, noCount_)),
        scratch_(threadScratch()) {
    scratch_.terms.clear();
    scratch_.clusterTerms.clear();
    scratch_.partlySeenClusters.clear();
  }

  Rgb irradiance() {
    gatherLinks();
    resolveVisibility();
    resolveClusters();
    openCloseSources();
    followShapes();
    if (outputs_.wantsWeights()) addWeights();
    if (outputs_.wantsNearField()) addNearField();
    return nonNegative(sum_);
  }

 private:
  static Scratch& threadScratch() {
    thread_local Scratch scratch;
    return scratch;
  }

  // The visibility of a source through a link from this vertex: from `known` where it holds it.
  double seenFrom(std::uint32_t k, std::uint32_t s, bool penumbraRays) {
    const std::uint32_t flagged = s | (penumbraRays ? GatherVisibility::kPenumbra : 0u);
    const GatherVisibility* known = outputs_.known();
    const double* stored = known ? known->find(v_, k, flagged) : nullptr;
    double seen;
    if (stored) {
      seen = *stored;
      ++tally_[3];
    } else {
      seen = g_.visibility(v_, k, s, tally_[2], penumbraRays);
    }
    outputs_.used(v_, k, flagged, seen);
    return seen;
  }

  // What the link measured: its rays all got through (an element pair's receiverSide verdict),
  // or the share that did.
  double linkVisibility(std::uint32_t k) const {
    const bool allVisible = g_.links_.receiverSide[k] != 0;
    return allVisible ? 1.0 : g_.links_.uncertainty[k] > 0 ? g_.links_.formFactor[k] / g_.links_.uncertainty[k] : 0.0;
  }

  bool closeBy(const HierarchyNode& source) const {
    // Barnes–Hut's opening criterion on the source's bounding sphere: only seen from closer
    // than this can its children's point factors differ from shares of its own by area.
    return !source.isLeaf() && source.radius > kOpeningRatio * length(source.centre - site_.point);
  }

  Term evaluate(std::uint32_t k, std::uint32_t s, bool resolvesVisibility) {
    const HierarchyNode& source = g_.hierarchy_.node(s);
    ++tally_[0];
    Term term{k, s, resolvesVisibility, pointToPolygonFormFactorFast(site_.point, site_.normal, source.polygon(), source.normal), 0, false};
    if (!(term.factor > 0)) return term;
    if (resolvesVisibility) {
      term.seen = seenFrom(k, s, false);
      term.mixed = term.seen > 0 && term.seen < 1;
    } else {
      term.seen = linkVisibility(k);
    }
    return term;
  }

  // First, every link's source as one element, clusters opened where close by (their kernel
  // is a far-field one): the irradiance the opening below is judged against.
  void gatherLinks() {
    const ElementHierarchy& hierarchy = g_.hierarchy_;
    const Links& links = g_.links_;
    std::vector<std::uint32_t>& open = scratch_.open;
    for (std::uint32_t r = hierarchy.leafNodes()[g_.leaf_[v_]]; r != kNoNode; r = hierarchy.node(r).parent) {
      const bool clusterReceiver = hierarchy.node(r).isCluster();
      for (std::uint32_t k = links.start[r]; k < links.start[r + 1]; ++k) {
        const bool allVisible = links.receiverSide[k] != 0;
        const double measured = linkVisibility(k);
        open.assign(1, links.source[k]);
        while (!open.empty()) {
          const std::uint32_t s = open.back();
          open.pop_back();
          const HierarchyNode& source = hierarchy.node(s);
          if (!source.isCluster()) {
            // Visibility is resolved at the vertex where the link's rays disagreed or were all
            // blocked (links.h keeps such element links for this: a vertex at the receiver's rim
            // may see the source through a gap, and a Cornell floor vertex beside the tall
            // block's foot lost the lamp, −46%). Where they all got through, below.
            Term term = evaluate(k, s, (!allVisible && !clusterReceiver) || (clusterReceiver && variesBehind(s)));
            term.resolvable = allVisible && !clusterReceiver;
            if (term.factor > 0) {
              sum_ += mean_[s] * (term.factor * term.seen);
              scratch_.terms.push_back(term);
            }
            continue;
          }
          if (closeBy(source)) {
            ++tally_[1];
            for (std::uint32_t child : hierarchy.children(s)) open.push_back(child);
            continue;
          }
          ++tally_[0];
          // From where the light toward the site comes from (the sides the site's direction from
          // the box's centre faces).
          const Vec3 centre = range_.lightCentreToward(s, site_.point - source.centre, source.centre);
          const double distance = length(centre - site_.point);
          if (!(distance > 0)) continue;
          const Vec3 w = (centre - site_.point) / distance;
          const double kernel = std::fmax(0.0, dot(site_.normal, w)) / (kPi * distance * distance);
          const Rgb shown = range_.shownToward(s, -w);
          if (kernel > 0 && source.projectedArea(-w) > 0) {
            // A link some of whose rays were blocked measured the visibility over its whole
            // receiver. At points (a lightmap's texels) each is resolved by its own rays to
            // points on the faces inside the cluster: a ceiling under a lamp panel hung 10 cm
            // below it sees the walls past the panel's edge, and with its receivers' visibility
            // the two sides of a leaf edge beside the panel differed by up to 35% (steps in the
            // lightmap; HierarchicalTest.PointsUnderACeilingSeePastALampHungBelowIt). At
            // vertices the largest are resolved after every link is gathered (resolveClusters).
            const double seen = g_.resolveClusterVisibility_ && measured < 1 ? seenFrom(k, s, false) : measured;
            sum_ += shown * (kernel * seen);
            // The weights multiply the cluster's mean: what it shows this way, over its mean,
            // as the light is now (a luminaire's faces keep their shares when it moves).
            const double meanSum = mean_[s].r + mean_[s].g + mean_[s].b, shownSum = shown.r + shown.g + shown.b;
            const double shows = meanSum > 0 ? shownSum / meanSum : source.projectedArea(-w);
            std::size_t weight = ClusterTerm::kNoWeight;
            if (outputs_.wantsWeights()) {
              weight = scratch_.clusterTerms.size();
              scratch_.clusterTerms.push_back({s, shows * kernel * seen});
            }
            if (!g_.resolveClusterVisibility_ && measured < 1)
              scratch_.partlySeenClusters.push_back({k, s, shown * kernel, seen, shows * kernel, weight});
          }
        }
      }
    }
  }

  // Links whose rays all got through start at the receiver's quadrature points; a vertex on
  // the receiver's rim may lie in a penumbra they missed (a floor element's corner beside a
  // block). Taken as wholly visible at every vertex, the Cornell box's floor vertices were
  // noisy by 2.7% between seeds (whether a link in a penumbra happened to see everything).
  // Their visibility is resolved here where the source brings at least kResolveShare of the
  // irradiance: the lamp and the bright walls close by, not the many small sources of a
  // luminaire's vertex (RenderPark's examp1.mgf took twice the CPU time resolving them all).
  // The share bounds what is left unresolved in total, not each source's: the largest are
  // resolved first until the rest bring less than it together. With the share per source, many
  // sources just under it could hide several times it (CIE 171 §5.7's wall points just below
  // where the far floor reappears over a partition: each far-floor leaf brought under 1%, all
  // of them 2.8% more than the closed form). Every source above the share alone is still resolved.
  void resolveVisibility() {
    std::vector<Term>& terms = scratch_.terms;
    std::vector<std::pair<double, std::uint32_t>>& candidates = scratch_.candidates;
    const double resolveAbove = kResolveShare * sum_.maxComponent();
    candidates.clear();
    double unresolved = 0;
    for (std::size_t t = 0; t < terms.size(); ++t) {
      if (!(terms[t].resolvable || terms[t].mixed)) continue;
      const double brings = terms[t].factor * mean_[terms[t].source].maxComponent();
      if (!(brings > 0)) continue;
      candidates.emplace_back(brings, static_cast<std::uint32_t>(t));
      unresolved += brings;
    }
    std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); });
    // These, and those whose rays disagreed, take kPenumbraRays times the rays where the first
    // ones disagree: the vertices in a penumbra carry most of the gather's noise, and they are few.
    for (const auto& [brings, t] : candidates) {
      if (!(unresolved > resolveAbove)) break;
      unresolved -= brings;
      Term& term = terms[t];
      const double seen = seenFrom(term.link, term.source, true);
      sum_ += mean_[term.source] * (term.factor * (seen - term.seen));
      term.seen = seen;
      term.resolvesVisibility = true;
      term.mixed = seen > 0 && seen < 1;
    }
  }

  // A vertex takes a far cluster's visibility from its link, measured over the link's whole
  // receiver: where some of those rays were blocked, the receiver's mean is not the vertex's.
  // Blocks on a floor, lit by an area light hung under the ceiling, one cluster link bringing the
  // light to all three: their tops' vertices showed 13% (under the light) to 20% (the far one)
  // less than the path tracer, and the points there, which resolve every such cluster, 2–3% less
  // (tests/blender_lights_test.py's room; docs/hierarchical.md). Resolving every one at every
  // vertex as well doubled the gather's time on RenderPark's classroom: here the largest are
  // resolved, until those left could bring kResolveClusterShare of the vertex's light together.
  void resolveClusters() {
    std::vector<ClusterTerm>& terms = scratch_.partlySeenClusters;
    if (terms.empty()) return;
    std::sort(terms.begin(), terms.end(), [](const ClusterTerm& a, const ClusterTerm& b) {
      const double x = a.unoccluded.maxComponent(), y = b.unoccluded.maxComponent();
      return x > y || (x == y && (a.link < b.link || (a.link == b.link && a.source < b.source)));
    });
    double unresolved = 0;
    for (const ClusterTerm& term : terms) unresolved += term.unoccluded.maxComponent();
    const double resolveAbove = kResolveClusterShare * sum_.maxComponent();
    for (ClusterTerm& term : terms) {
      if (!(unresolved > resolveAbove)) break;
      unresolved -= term.unoccluded.maxComponent();
      const double seen = seenFrom(term.link, term.source, false);
      sum_ += term.unoccluded * (seen - term.seen);
      term.seen = seen;
      if (term.weight != ClusterTerm::kNoWeight) scratch_.clusterTerms[term.weight].second = term.weightPerSeen * seen;
    }
  }

  // A source whose leaves differ by more than kVariesBehind times its mean, reached through a link
  // into a cluster: that link's few rays, over the cluster's faces, say little of which part a
  // vertex sees, and the hidden part may be the bright one. A ceiling element around a lamp hung
  // 1 cm under it is bright only over the lamp, which hides just that part from a sphere below:
  // at its mean, with the link's visibility, the sphere's top vertices took up to 1.5 times the
  // path tracer's light (flat shading, the leaves, 0.8 times). Such a source's visibility is
  // resolved at the vertex and, where its rays disagree, it is opened, each part with its own
  // rays, however far it is.
  bool variesBehind(std::uint32_t s) const {
    return !g_.hierarchy_.node(s).isLeaf() && range_.highest[s].maxComponent() > kVariesBehind * mean_[s].maxComponent();
  }

  bool opens(const Term& term, double threshold) const {
    const HierarchyNode& source = g_.hierarchy_.node(term.source);
    if (!closeBy(source) && !(term.mixed && variesBehind(term.source))) return false;
    const double spread = (range_.highest[term.source] - range_.lowest[term.source]).maxComponent();
    const double variation = term.mixed ? std::fmax(spread, range_.highest[term.source].maxComponent()) : spread;
    return term.factor * variation > threshold;
  }

  // Then an element seen from close by is taken through its children where that can change
  // the irradiance here by more than kOpeningTolerance of the first pass's: by the spread of
  // the radiosity under it, and where the rays to it disagree, by all it brings (the floor
  // next to a block's base is in the block's shadow while the floor element the link reached
  // is lit further out). The exact polygon factor is additive, so a uniform, uniformly visible
  // source gives the same through its children; a long thin one (a lamp strip) would
  // otherwise be opened to its leaves by every vertex its bounding sphere reaches.
  void openCloseSources() {
    std::vector<Term>& pending = scratch_.pending;
    std::vector<Term>& gatheredTerms = scratch_.gatheredTerms;
    const double threshold = kOpeningTolerance * sum_.maxComponent();
    gatheredTerms.clear();
    for (const Term& top : scratch_.terms) {
      if (!opens(top, threshold)) {
        gatheredTerms.push_back(top);
        continue;
      }
      sum_ -= mean_[top.source] * (top.factor * top.seen);
      pending.assign(1, top);
      while (!pending.empty()) {
        const Term term = pending.back();
        pending.pop_back();
        if (!opens(term, threshold)) {
          sum_ += mean_[term.source] * (term.factor * term.seen);
          gatheredTerms.push_back(term);
          continue;
        }
        ++tally_[1];
        for (std::uint32_t child : g_.hierarchy_.children(term.source)) {
          const Term c = evaluate(term.link, child, term.resolvesVisibility);
          if (c.factor > 0) pending.push_back(c);
        }
      }
    }
  }

  // An element gathered whole still shows the vertex its radiosity's shape: a wall's brighter
  // half near the lamp is nearer the ceiling vertex above it, and with the element's mean the
  // Cornell box's ceiling was 3% dark. Its F × B̄ becomes F × Σ w_c B̄_c over its descendants
  // kShapeDepth levels down, w_c their shares of the point kernel × area (the exact F kept).
  void followShapes() {
    for (const Term& term : scratch_.gatheredTerms) {
      const HierarchyNode& source = g_.hierarchy_.node(term.source);
      if (source.isLeaf() || !(term.seen > 0)) continue;
      sum_ += (g_.shapedMean(site_, term.source, mean_) - mean_[term.source]) * (term.factor * term.seen);
    }
  }

  // A close leaf source whose light NearFieldWeights takes from its corners instead.
  bool nearSource(const Term& term) const {
    const HierarchyNode& source = g_.hierarchy_.node(term.source);
    // A partly covered leaf (a floor leaf under a block's edge) has corners in the dark whose
    // values are not light it shows: its mean is over its open part (links.h).
    return outputs_.wantsNearField() && source.isLeaf() && term.seen > 0 && g_.mesh_.patches[source.leaf].openFraction >= 1 &&
           source.radius > kOpeningRatio * length(source.centre - site_.point);
  }

  // The sum above, term by term, as weights: the clusters gathered whole, then every element
  // gathered whole with its shaped mean's shares (a leaf's is its own).
  void addWeights() {
    std::vector<std::pair<std::uint32_t, double>>& entries = scratch_.entries;
    entries.assign(scratch_.clusterTerms.begin(), scratch_.clusterTerms.end());
    for (const Term& term : scratch_.gatheredTerms)
      if (term.seen > 0 && !nearSource(term)) g_.shapedWeights(site_, term.source, term.factor * term.seen, entries);
    std::sort(entries.begin(), entries.end());
    outputs_.addWeights(v_, entries);
  }

  void addNearField() {
    for (const Term& term : scratch_.gatheredTerms) {
      const HierarchyNode& source = g_.hierarchy_.node(term.source);
      if (!nearSource(term)) continue;
      // The leaf's patch has the node's corners, in the node's order (ElementHierarchy::leaves).
      const std::array<double, 4> w = cornerFormFactors(site_.point, site_.normal, source.polygon(), source.normal);
      const std::span<const std::uint32_t> corners = g_.mesh_.cornerIndices(source.leaf);
      for (std::size_t c = 0; c < corners.size(); ++c)
        if (w[c] > 0) outputs_.addNearField(v_, corners[c], static_cast<float>(w[c] * term.seen));
      outputs_.nearFieldMeanPart(v_) += mean_[term.source] * (term.factor * term.seen);
    }
  }

  const FinalGather& g_;
  std::uint32_t v_;
  const VertexSite& site_;
  const std::vector<Rgb>& mean_;
  const LeafRange& range_;
  GatherOutputs& outputs_;
  std::uint32_t noCount_[4] = {0, 0, 0, 0};
  std::uint32_t* tally_;
  Scratch& scratch_;
  Rgb sum_;
};

std::vector<Rgb> FinalGather::irradiance(const std::vector<Rgb>& mean, FinalGatherCounts* counts, const GatherVisibility* known,
                                         GatherVisibility* record, NearFieldWeights* near, GatherWeights* weights) const {
  LAMBERT_CHECK(mean.size() == hierarchy_.nodes().size());
  if (known && known->numVertices() != sites_.size()) known = nullptr;
  GatherOutputs outputs(sites_.size(), counts, known, record, near, weights);
  const LeafRange range = leafRange(hierarchy_, mesh_, mean);
  std::vector<Rgb> out(sites_.size());
  parallelFor(0, sites_.size(), [&](std::size_t v) {
    // No light reaches inside a closed two-sided object (geometry/enclosures.h), whatever the
    // links of the clusters holding it carry: on its inner faces, nor at a point of the floor it
    // stands on (a cluster link's visibility is its receiver's mean, open where such a point is not).
    if (leaf_[v] == kNoNode || hierarchy_.node(hierarchy_.leafNodes()[leaf_[v]]).enclosed) return;
    if (isInsideClosedObject(caster_, sites_[v].point, sites_[v].normal, epsilon_)) return;
    out[v] = SiteGather(*this, static_cast<std::uint32_t>(v), mean, range, outputs).irradiance();
  }, 64);
  outputs.finish(leaf_);
  return out;
}

}  // namespace lambert
