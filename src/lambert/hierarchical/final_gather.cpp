#include "lambert/hierarchical/final_gather.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include <tbb/enumerable_thread_specific.h>

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"
#include "lambert/formfactor/kernels.h"

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
// Rays from a vertex to a source, as a multiple of the link's, where the first ones disagree.
constexpr int kPenumbraRays = 4;

// Levels below an element gathered whole over which its radiosity's shape is followed.
constexpr int kShapeDepth = 2;

// One visibility value as a gather used it (GatherVisibility's entry, with its vertex).
struct SeenEntry {
  std::uint32_t vertex, link, source;
  double seen;
};

// Irradiance is never negative: the shaped means' and the corners' corrections, added to a sum
// that should be 0 (a covered site), leave rounding of either sign (−1e-17).
Rgb nonNegative(const Rgb& e) { return {std::fmax(0.0, e.r), std::fmax(0.0, e.g), std::fmax(0.0, e.b)}; }

// One corner weight of a close leaf source (NearFieldWeights' entry, with its vertex).
struct NearEntry {
  std::uint32_t vertex, corner;
  float weight;
};

}  // namespace

const double* GatherVisibility::find(std::uint32_t vertex, std::uint32_t k, std::uint32_t flaggedSource) const {
  if (vertex + 1 >= start.size()) return nullptr;
  const auto first = link.begin() + start[vertex], last = link.begin() + start[vertex + 1];
  // Entries are few per vertex (a few links' rays disagree): a linear scan.
  for (auto it = first; it != last; ++it) {
    const std::size_t e = static_cast<std::size_t>(it - link.begin());
    if (*it == k && source[e] == flaggedSource) return &seen[e];
  }
  return nullptr;
}

std::vector<std::uint32_t> FinalGather::gatheringLeaves(const Mesh& mesh) {
  std::vector<std::uint32_t> leaf(mesh.numVertices(), kNoNode);
  for (std::uint32_t p = 0; p < mesh.numPatches(); ++p) {
    const Patch& patch = mesh.patches[p];
    for (std::uint32_t v : mesh.cornerIndices(p)) {
      const std::uint32_t current = leaf[v];
      if (current == kNoNode) {
        leaf[v] = p;
        continue;
      }
      const Patch& other = mesh.patches[current];
      if (patch.openFraction > other.openFraction || (patch.openFraction == other.openFraction && patch.area < other.area))
        leaf[v] = p;
    }
  }
  return leaf;
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

std::vector<Rgb> FinalGather::withCorners(const std::vector<Rgb>& gathered, const NearFieldWeights& near,
                                         const std::vector<Rgb>& cornerRadiosity) {
  LAMBERT_CHECK(near.start.size() == gathered.size() + 1 && near.meanPart.size() == gathered.size());
  std::vector<Rgb> out(gathered.size());
  parallelFor(0, gathered.size(), [&](std::size_t v) {
    Rgb e = gathered[v] - near.meanPart[v];
    for (std::uint32_t k = near.start[v]; k < near.start[v + 1]; ++k) e += cornerRadiosity[near.corner[k]] * near.weight[k];
    out[v] = nonNegative(e);
  }, 1024);
  return out;
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

double FinalGather::visibility(std::uint32_t vertex, std::uint32_t link, std::uint32_t s, std::uint32_t& raysCast,
                               bool penumbraRays) const {
  const VertexSite& site = sites_[vertex];
  // Seeded by the nodes, not the link's index: a distributed solve's ranks each hold their own
  // links, numbered apart, and must draw the rays one process draws.
  Pcg32 rng(seed_ ^ (links_.source[link] * 0x9e3779b97f4a7c15ull), (static_cast<std::uint64_t>(vertex) << 32) ^ s);
  const std::uint32_t su = rng.nextUint(), sv = rng.nextUint();
  // Each ray counts with the point-to-point kernel at its end: the visibility the factor needs is
  // ∫ k V dA / ∫ k dA over the source, not the share of its area in view. Counted by area, a
  // vertex that sees only the near strip of a source (a floor corner beside a block, the lamp
  // through a gap) is given that strip's share of the whole factor, far below the strip's own.
  // With penumbraRays, where the first rays disagree, kPenumbraRays times as many in all,
  // continuing the same (0,2)-sequence so that they stay stratified.
  double open = 0, facing = 0;
  const Vec3 from = site.point + site.normal * epsilon_;
  for (int i = 0; i < (penumbraRays ? kPenumbraRays : 1) * rays_; ++i) {
    if (i == rays_ && !(open > 0 && open < facing)) break;
    auto [u, v] = scrambledZeroTwo(static_cast<std::uint32_t>(i), su, sv);
    // On a cluster, a point of the faces inside it: down through the children in proportion to
    // their areas, u picking the child and rescaled within it, to an element.
    std::uint32_t on = s;
    while (hierarchy_.node(on).isCluster()) {
      const std::span<const std::uint32_t> children = hierarchy_.children(on);
      if (children.empty()) break;
      double total = 0;
      for (std::uint32_t c : children) total += hierarchy_.node(c).area;
      double pick = u * total;
      std::uint32_t next = children.back();
      for (std::uint32_t c : children) {
        const double area = hierarchy_.node(c).area;
        if (pick < area) {
          next = c;
          u = std::clamp(pick / area, 0.0, 1.0 - 1e-12);
          break;
        }
        pick -= area;
      }
      on = next;
    }
    const HierarchyNode& element = hierarchy_.node(on);
    if (element.isCluster()) continue;
    const Vec3 y = sampleConvexPolygon(element.polygon(), u, v);
    const double kernel = pointToPointKernel(site.point, site.normal, y, element.normal);
    if (!(kernel > 0)) continue;
    facing += kernel;
    ++raysCast;
    const Vec3 to = y + element.normal * epsilon_;
    if (!caster_.occluded(Ray{from, to - from, 0, 1})) open += kernel;
  }
  // No ray pair faces (a source seen edge-on from here): keep what the link measured.
  if (!(facing > 0)) return links_.uncertainty[link] > 0 ? links_.formFactor[link] / links_.uncertainty[link] : 0.0;
  return open / facing;
}

std::vector<Rgb> FinalGather::irradiance(const std::vector<Rgb>& mean, FinalGatherCounts* counts, const GatherVisibility* known,
                                         GatherVisibility* record, NearFieldWeights* near, GatherWeights* weights) const {
  LAMBERT_CHECK(mean.size() == hierarchy_.nodes().size());
  if (known && known->numVertices() != sites_.size()) known = nullptr;
  // Recorded per thread (24 bytes a value, a few values a vertex), sorted into `record` after.
  tbb::enumerable_thread_specific<std::vector<SeenEntry>> used;
  tbb::enumerable_thread_specific<std::vector<NearEntry>> nearEntries;
  // Per site, its weights on the node means, sorted by node and merged (weights only).
  std::vector<std::vector<std::pair<std::uint32_t, float>>> siteWeights(weights ? sites_.size() : 0);
  if (near) near->meanPart.assign(sites_.size(), Rgb{});
  const std::size_t numNodes = hierarchy_.nodes().size();
  // The lowest and highest radiosity of the leaves under each node, per channel: children have
  // larger indices than their parents, so one pass in decreasing order sees them first.
  std::vector<Rgb> lowest(mean), highest(mean);
  for (std::size_t i = numNodes; i-- > 0;) {
    if (hierarchy_.node(static_cast<std::uint32_t>(i)).isLeaf()) continue;
    Rgb lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    for (std::uint32_t c : hierarchy_.children(static_cast<std::uint32_t>(i))) {
      lo = {std::fmin(lo.r, lowest[c].r), std::fmin(lo.g, lowest[c].g), std::fmin(lo.b, lowest[c].b)};
      hi = {std::fmax(hi.r, highest[c].r), std::fmax(hi.g, highest[c].g), std::fmax(hi.b, highest[c].b)};
    }
    lowest[i] = lo;
    highest[i] = hi;
  }
  std::vector<Rgb> out(sites_.size());
  // Per vertex: sources gathered, sources opened, visibility rays.
  std::vector<std::array<std::uint32_t, 4>> work(counts ? sites_.size() : 0, {0, 0, 0, 0});
  const std::vector<std::uint32_t>& leafNodes = hierarchy_.leafNodes();
  parallelFor(0, sites_.size(), [&](std::size_t v) {
    if (leaf_[v] == kNoNode) return;
    const VertexSite& site = sites_[v];
    std::uint32_t noCount[4] = {0, 0, 0, 0};
    std::uint32_t* tally = counts ? work[v].data() : noCount;
    // The visibility of a source through a link from this vertex: from `known` where it holds it.
    const auto seenFrom = [&](std::uint32_t k, std::uint32_t s, bool penumbraRays) {
      const std::uint32_t flagged = s | (penumbraRays ? GatherVisibility::kPenumbra : 0u);
      const double* stored = known ? known->find(static_cast<std::uint32_t>(v), k, flagged) : nullptr;
      double seen;
      if (stored) {
        seen = *stored;
        ++tally[3];
      } else {
        seen = visibility(static_cast<std::uint32_t>(v), k, s, tally[2], penumbraRays);
      }
      if (record) used.local().push_back({static_cast<std::uint32_t>(v), k, flagged, seen});
      return seen;
    };
    // An element source as the vertex sees it: what it brings, and whether the rays to it
    // disagree (a shadow edge crosses it as seen from here).
    struct Term {
      std::uint32_t link, source;
      bool resolvesVisibility;  // the rays to it are cast here, so its children's would be too
      double factor, seen;
      bool mixed;
      bool resolvable = false;  // an element receiver's link whose rays all got through: seen = 1 so far
    };
    // Per thread, reused from vertex to vertex (about a hundred terms each: not allocated anew).
    thread_local std::vector<Term> terms;
    thread_local std::vector<std::uint32_t> open;  // sources still to gather
    thread_local std::vector<std::pair<std::uint32_t, double>> clusterTerms;  // (cluster source, factor × visibility)
    terms.clear();
    clusterTerms.clear();
    const auto closeBy = [&](const HierarchyNode& source) {
      // Barnes–Hut's opening criterion on the source's bounding sphere: only seen from closer
      // than this can its children's point factors differ from shares of its own by area.
      return !source.isLeaf() && source.radius > kOpeningRatio * length(source.centre - site.point);
    };
    const auto evaluate = [&](std::uint32_t k, std::uint32_t s, bool resolvesVisibility) {
      const HierarchyNode& source = hierarchy_.node(s);
      ++tally[0];
      Term term{k, s, resolvesVisibility, pointToPolygonFormFactor(site.point, site.normal, source.polygon(), source.normal), 0, false};
      if (!(term.factor > 0)) return term;
      if (resolvesVisibility) {
        term.seen = seenFrom(k, s, false);
        term.mixed = term.seen > 0 && term.seen < 1;
      } else {
        const bool allVisible = links_.receiverSide[k] != 0;
        term.seen = allVisible ? 1.0 : links_.uncertainty[k] > 0 ? links_.formFactor[k] / links_.uncertainty[k] : 0.0;
      }
      return term;
    };
    // First, every link's source as one element, clusters opened where close by (their kernel
    // is a far-field one): the irradiance the opening below is judged against.
    Rgb sum;
    for (std::uint32_t r = leafNodes[leaf_[v]]; r != kNoNode; r = hierarchy_.node(r).parent) {
      const bool clusterReceiver = hierarchy_.node(r).isCluster();
      for (std::uint32_t k = links_.start[r]; k < links_.start[r + 1]; ++k) {
        // What the link measured: its rays all got through (an element pair's receiverSide
        // verdict), or the share that did.
        const bool allVisible = links_.receiverSide[k] != 0;
        const double linkVisibility =
            allVisible ? 1.0 : links_.uncertainty[k] > 0 ? links_.formFactor[k] / links_.uncertainty[k] : 0.0;
        open.assign(1, links_.source[k]);
        while (!open.empty()) {
          const std::uint32_t s = open.back();
          open.pop_back();
          const HierarchyNode& source = hierarchy_.node(s);
          if (!source.isCluster()) {
            // Visibility is resolved at the vertex where the link's rays disagreed or were all
            // blocked (links.h keeps such element links for this: a vertex at the receiver's rim
            // may see the source through a gap, and a Cornell floor vertex beside the tall
            // block's foot lost the lamp, −46%). Where they all got through, below.
            Term term = evaluate(k, s, !allVisible && !clusterReceiver);
            term.resolvable = allVisible && !clusterReceiver;
            if (term.factor > 0) {
              sum += mean[s] * (term.factor * term.seen);
              terms.push_back(term);
            }
            continue;
          }
          if (closeBy(source)) {
            ++tally[1];
            for (std::uint32_t child : hierarchy_.children(s)) open.push_back(child);
            continue;
          }
          ++tally[0];
          const double distance = length(source.centre - site.point);
          const Vec3 w = (source.centre - site.point) / distance;
          const double factor = source.projectedArea(-w) * std::fmax(0.0, dot(site.normal, w)) / (kPi * distance * distance);
          if (factor > 0) {
            // A link some of whose rays were blocked measured the visibility over its whole
            // receiver. At points (a lightmap's texels) each is resolved by its own rays to
            // points on the faces inside the cluster: a ceiling under a lamp panel hung 10 cm
            // below it sees the walls past the panel's edge, and with its receivers' visibility
            // the two sides of a leaf edge beside the panel differed by up to 35% (steps in the
            // lightmap; HierarchicalTest.PointsUnderACeilingSeePastALampHungBelowIt). Vertices
            // keep the link's: interpolated, their values show no step, and resolving there
            // doubled the gather's time on RenderPark's classroom.
            const double seen = resolveClusterVisibility_ && linkVisibility < 1 ? seenFrom(k, s, false) : linkVisibility;
            sum += mean[s] * (factor * seen);
            if (weights) clusterTerms.push_back({s, factor * seen});
          }
        }
      }
    }
    // Then an element seen from close by is taken through its children where that can change
    // the irradiance here by more than kOpeningTolerance of the first pass's: by the spread of
    // the radiosity under it, and where the rays to it disagree, by all it brings (the floor
    // next to a block's base is in the block's shadow while the floor element the link reached
    // is lit further out). The exact polygon factor is additive, so a uniform, uniformly visible
    // source gives the same through its children; a long thin one (a lamp strip) would
    // otherwise be opened to its leaves by every vertex its bounding sphere reaches.
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
    const double resolveAbove = kResolveShare * sum.maxComponent();
    thread_local std::vector<std::pair<double, std::uint32_t>> candidates;  // (what it brings, term)
    candidates.clear();
    double unresolved = 0;
    for (std::size_t t = 0; t < terms.size(); ++t) {
      if (!(terms[t].resolvable || terms[t].mixed)) continue;
      const double brings = terms[t].factor * mean[terms[t].source].maxComponent();
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
      sum += mean[term.source] * (term.factor * (seen - term.seen));
      term.seen = seen;
      term.resolvesVisibility = true;
      term.mixed = seen > 0 && seen < 1;
    }
    const double threshold = kOpeningTolerance * sum.maxComponent();
    const auto opens = [&](const Term& term) {
      const HierarchyNode& source = hierarchy_.node(term.source);
      if (!closeBy(source)) return false;
      const double spread = (highest[term.source] - lowest[term.source]).maxComponent();
      const double variation = term.mixed ? std::fmax(spread, highest[term.source].maxComponent()) : spread;
      return term.factor * variation > threshold;
    };
    thread_local std::vector<Term> pending, gatheredTerms;
    gatheredTerms.clear();
    for (const Term& top : terms) {
      if (!opens(top)) {
        gatheredTerms.push_back(top);
        continue;
      }
      sum -= mean[top.source] * (top.factor * top.seen);
      pending.assign(1, top);
      while (!pending.empty()) {
        const Term term = pending.back();
        pending.pop_back();
        if (!opens(term)) {
          sum += mean[term.source] * (term.factor * term.seen);
          gatheredTerms.push_back(term);
          continue;
        }
        ++tally[1];
        for (std::uint32_t child : hierarchy_.children(term.source)) {
          const Term c = evaluate(term.link, child, term.resolvesVisibility);
          if (c.factor > 0) pending.push_back(c);
        }
      }
    }
    // An element gathered whole still shows the vertex its radiosity's shape: a wall's brighter
    // half near the lamp is nearer the ceiling vertex above it, and with the element's mean the
    // Cornell box's ceiling was 3% dark. Its F × B̄ becomes F × Σ w_c B̄_c over its descendants
    // kShapeDepth levels down, w_c their shares of the point kernel × area (the exact F kept).
    for (const Term& term : gatheredTerms) {
      const HierarchyNode& source = hierarchy_.node(term.source);
      if (source.isLeaf() || !(term.seen > 0)) continue;
      sum += (shapedMean(site, term.source, mean) - mean[term.source]) * (term.factor * term.seen);
    }
    out[v] = nonNegative(sum);
    // A close leaf source whose light NearFieldWeights takes from its corners instead.
    const auto nearSource = [&](const Term& term) {
      const HierarchyNode& source = hierarchy_.node(term.source);
      // A partly covered leaf (a floor leaf under a block's edge) has corners in the dark whose
      // values are not light it shows: its mean is over its open part (links.h).
      return near && source.isLeaf() && term.seen > 0 && mesh_.patches[source.leaf].openFraction >= 1 &&
             source.radius > kOpeningRatio * length(source.centre - site.point);
    };
    if (weights) {
      // The sum above, term by term, as weights: the clusters gathered whole, then every element
      // gathered whole with its shaped mean's shares (a leaf's is its own).
      thread_local std::vector<std::pair<std::uint32_t, double>> entries;
      entries.assign(clusterTerms.begin(), clusterTerms.end());
      for (const Term& term : gatheredTerms)
        if (term.seen > 0 && !nearSource(term)) shapedWeights(site, term.source, term.factor * term.seen, entries);
      std::sort(entries.begin(), entries.end());
      std::vector<std::pair<std::uint32_t, float>>& merged = siteWeights[v];
      for (std::size_t i = 0; i < entries.size();) {
        double w = 0;
        std::size_t j = i;
        for (; j < entries.size() && entries[j].first == entries[i].first; ++j) w += entries[j].second;
        merged.push_back({entries[i].first, static_cast<float>(w)});
        i = j;
      }
    }
    if (!near) return;
    for (const Term& term : gatheredTerms) {
      const HierarchyNode& source = hierarchy_.node(term.source);
      if (!nearSource(term)) continue;
      // The leaf's patch has the node's corners, in the node's order (ElementHierarchy::leaves).
      const std::array<double, 4> w = cornerFormFactors(site.point, site.normal, source.polygon(), source.normal);
      const std::span<const std::uint32_t> corners = mesh_.cornerIndices(source.leaf);
      for (std::size_t c = 0; c < corners.size(); ++c)
        if (w[c] > 0) nearEntries.local().push_back({static_cast<std::uint32_t>(v), corners[c], static_cast<float>(w[c] * term.seen)});
      near->meanPart[v] += mean[term.source] * (term.factor * term.seen);
    }
  }, 64);
  if (near) {
    near->start.assign(sites_.size() + 1, 0);
    std::size_t total = 0;
    for (const std::vector<NearEntry>& entries : nearEntries) {
      total += entries.size();
      for (const NearEntry& e : entries) ++near->start[e.vertex + 1];
    }
    LAMBERT_CHECK(total < std::numeric_limits<std::uint32_t>::max());
    for (std::size_t v = 0; v < sites_.size(); ++v) near->start[v + 1] += near->start[v];
    near->corner.resize(total);
    near->weight.resize(total);
    std::vector<std::uint32_t> next(near->start.begin(), near->start.end() - 1);
    for (const std::vector<NearEntry>& entries : nearEntries)
      for (const NearEntry& e : entries) {
        near->corner[next[e.vertex]] = e.corner;
        near->weight[next[e.vertex]++] = e.weight;
      }
  }
  if (weights) {
    weights->start.assign(sites_.size() + 1, 0);
    for (std::size_t v = 0; v < sites_.size(); ++v) weights->start[v + 1] = weights->start[v] + static_cast<std::uint32_t>(siteWeights[v].size());
    LAMBERT_CHECK(std::accumulate(siteWeights.begin(), siteWeights.end(), std::size_t{0},
                                  [](std::size_t n, const auto& w) { return n + w.size(); }) < std::numeric_limits<std::uint32_t>::max());
    weights->node.resize(weights->start.back());
    weights->weight.resize(weights->start.back());
    for (std::size_t v = 0; v < sites_.size(); ++v) {
      std::size_t k = weights->start[v];
      for (const auto& [node, w] : siteWeights[v]) {
        weights->node[k] = node;
        weights->weight[k++] = w;
      }
      std::vector<std::pair<std::uint32_t, float>>().swap(siteWeights[v]);
    }
  }
  if (counts) {
    *counts = {};
    for (std::size_t v = 0; v < work.size(); ++v) {
      if (leaf_[v] == kNoNode) continue;
      ++counts->vertices;
      counts->sourcesGathered += work[v][0];
      counts->sourcesOpened += work[v][1];
      counts->visibilityRays += work[v][2];
      counts->visibilityKnown += work[v][3];
      counts->maxSourcesGathered = std::max<std::uint64_t>(counts->maxSourcesGathered, work[v][0]);
      counts->maxVisibilityRays = std::max<std::uint64_t>(counts->maxVisibilityRays, work[v][2]);
    }
  }
  if (record) {
    // Grouped by vertex, each vertex's in (link, source) order, each value once (a pair met
    // twice has one value): counted per vertex, placed, then sorted within each vertex.
    *record = {};
    record->start.assign(sites_.size() + 1, 0);
    std::size_t total = 0;
    for (const std::vector<SeenEntry>& entries : used) {
      total += entries.size();
      for (const SeenEntry& e : entries) ++record->start[e.vertex + 1];
    }
    LAMBERT_CHECK(total < std::numeric_limits<std::uint32_t>::max());
    for (std::size_t v = 0; v < sites_.size(); ++v) record->start[v + 1] += record->start[v];
    std::vector<SeenEntry> placed(total);
    std::vector<std::uint32_t> next(record->start.begin(), record->start.end() - 1);
    for (std::vector<SeenEntry>& entries : used) {
      for (const SeenEntry& e : entries) placed[next[e.vertex]++] = e;
      std::vector<SeenEntry>().swap(entries);
    }
    std::vector<std::uint32_t>().swap(next);
    record->link.reserve(total);
    record->source.reserve(total);
    record->seen.reserve(total);
    std::uint32_t kept = 0;
    for (std::size_t v = 0; v < sites_.size(); ++v) {
      const auto first = placed.begin() + record->start[v], last = placed.begin() + record->start[v + 1];
      std::sort(first, last, [](const SeenEntry& a, const SeenEntry& b) { return a.link != b.link ? a.link < b.link : a.source < b.source; });
      record->start[v] = kept;
      for (auto e = first; e != last; ++e) {
        if (e != first && e->link == (e - 1)->link && e->source == (e - 1)->source) continue;
        record->link.push_back(e->link);
        record->source.push_back(e->source);
        record->seen.push_back(e->seen);
        ++kept;
      }
    }
    record->start.back() = kept;
  }
  return out;
}

std::vector<Rgb> FinalGather::coupleNearField(const std::vector<Rgb>& gathered, const NearFieldWeights& near,
                                              std::span<const Rgb> emitted, std::span<const Rgb> albedo, std::span<const Rgb> direct,
                                              int* iterations) {
  const std::size_t n = gathered.size();
  LAMBERT_CHECK(near.start.size() == n + 1 && near.meanPart.size() == n && emitted.size() == n && albedo.size() == n &&
                direct.size() == n);
  constexpr int kMaxIterations = 100;
  constexpr double kTolerance = 1e-6;
  std::vector<Rgb> far(n), radiosity(n), next(n);
  parallelFor(0, n, [&](std::size_t v) {
    far[v] = gathered[v] - near.meanPart[v];
    radiosity[v] = emitted[v] + albedo[v] * (gathered[v] + direct[v]);
  }, 1024);
  const auto irradianceAt = [&](std::size_t v, const std::vector<Rgb>& b) {
    Rgb e = far[v];
    for (std::uint32_t k = near.start[v]; k < near.start[v + 1]; ++k) e += b[near.corner[k]] * near.weight[k];
    return e;
  };
  int steps = 0;
  if (near.size() > 0) {
    double largest = 0;
    for (const Rgb& b : radiosity) largest = std::fmax(largest, b.maxComponent());
    for (; steps < kMaxIterations; ++steps) {
      std::vector<double> change(n, 0.0);
      parallelFor(0, n, [&](std::size_t v) {
        next[v] = near.start[v] == near.start[v + 1] ? radiosity[v] : emitted[v] + albedo[v] * (irradianceAt(v, radiosity) + direct[v]);
        change[v] = (next[v] - radiosity[v]).maxComponent();
        change[v] = std::fmax(change[v], (radiosity[v] - next[v]).maxComponent());
      }, 1024);
      radiosity.swap(next);
      if (!(*std::max_element(change.begin(), change.end()) > kTolerance * largest)) {
        ++steps;
        break;
      }
    }
  }
  if (iterations) *iterations = steps;
  return withCorners(gathered, near, radiosity);
}

}  // namespace lambert
