// The refinement of the links, wave by wave (hierarchical/refiner.h): each wave's candidates
// estimated in parallel (hierarchical/link_estimator.h), judged in order, and expanded into their
// children's candidates.
#include "lambert/hierarchical/refiner.h"

#include <algorithm>
#include <deque>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/memory.h"
#include "lambert/core/parallel.h"
#include "lambert/core/progress.h"
#include "lambert/core/timer.h"
#include "lambert/hierarchical/distributed_links.h"
#include "lambert/hierarchical/link_estimator.h"

namespace lambert {
namespace {

// An element link whose rays were all blocked is kept (K = 0, for the final gather) where it could
// carry at least this share of the link error's power unoccluded.
constexpr double kOccludedKept = 0.1;

// Chunked, not one array: the kept links and the waves reach 10⁷ candidates on 10⁶ faces, and a
// vector's doubling would hold up to twice that (and three times while it moves).
using Candidates = std::deque<Candidate>;

// A refined link, to be replaced by its children's links (Refiner::expand): every pair of a
// cluster's children (a cluster's link to itself), or the receiver's or the source's children.
struct Expansion {
  std::uint32_t receiver, source;
  enum Kind : std::uint8_t { Pairs, Receiver, Source } kind;
};

class Refiner {
 public:
  Refiner(ElementHierarchy& hierarchy, const RayCaster& caster, double rayEpsilon, std::span<const std::uint64_t> casterFace,
          const LinkOptions& options, std::span<const double> leafRadiosity, std::span<const double> leafOpenFraction,
          LinkShare* share)
      : h_(hierarchy), options_(options), share_(share),
        estimator_(hierarchy, caster, rayEpsilon, casterFace, options, leafRadiosity, leafOpenFraction) {
    LAMBERT_CHECK(!share_ || share_->numNodes() == hierarchy.nodes().size());
  }


  // previous: links of the same hierarchy, judged again in their order as the first wave (they
  // were estimated when they were made), read in place rather than copied into the frontier.
  Links run(const Links* previous, Candidates frontier, RefinementReport& report) {
    Timer timer;
    Progress progress("links judged", 0, options_.showProgress);
    Candidates kept;
    std::vector<Expansion> expansions;
    // What the refinement holds now, and will hold at least: kept and pending links, and the
    // hierarchy's nodes. Checked every wave, so a refinement that cannot fit stops early.
    const auto fits = [&] {
      const double bytes = static_cast<double>(kept.size() + frontier.size()) * sizeof(Candidate) +
                           static_cast<double>(h_.nodes().size()) * sizeof(HierarchyNode);
      if (const double budget = memoryBudgetBytes(options_.memoryLimitBytes); budget > 0 && bytes > budget) {
        report.memoryNeeded = bytes;
        return false;
      }
      return true;
    };
    if (share_) std::erase_if(frontier, [&](const Candidate& c) { return !share_->holds(c.receiver); });
    if (previous) {
      for (std::uint32_t r = 0; r + 1 < previous->start.size(); ++r)
        for (std::uint32_t k = previous->start[r]; k < previous->start[r + 1]; ++k) {
          Candidate c{r, previous->source[k], previous->formFactor[k], previous->uncertainty[k], previous->receiverSide[k] != 0};
          c.facing = previous->facing[k];
          c.estimated = true;
          // A link kept with every ray blocked is judged as it was: split only while it could carry
          // too much unoccluded light.
          if (!(c.formFactor > 0) && !h_.node(r).isCluster() && !h_.node(c.source).isCluster()) c.verdict = Verdict::Occluded;
          judge(c, kept, expansions, report);
        }
      progress.advance(previous->size());
      expand(expansions, frontier, report);
    }
    while (true) {
      const bool fitting = fits();
      if (share_) {
        if (!share_->everyRankGoesOn(frontier.size(), fitting, report.memoryNeeded)) break;
      } else if (!fitting || frontier.empty()) {
        break;
      }
      std::vector<std::uint8_t> rays(frontier.size(), 0);
      for (const Candidate& c : frontier) report.estimated += !c.estimated;
      parallelFor(0, frontier.size(), [&](std::size_t i) {
        if (!frontier[i].estimated) rays[i] = estimator_.estimate(frontier[i]);
      }, 64);
      for (std::uint8_t n : rays) report.rays += n;
      progress.advance(frontier.size());
      for (const Candidate& c : frontier) judge(c, kept, expansions, report);
      frontier.clear();
      expand(expansions, frontier, report);
    }
    progress.finish();
    h_.numberLeaves();

    Links links = groupByReceiver(kept);
    report.seconds += timer.seconds();
    return links;
  }

 private:
  // The kept links as compressed rows: placed by receiver (a counting sort, linear in the links),
  // then each receiver's few links ordered by source. Each (receiver, source) pair is kept at most
  // once (refinement partitions the pairs of leaves), so the order is the pairs' order.
  Links groupByReceiver(Candidates& kept) const {
    Links links;
    links.start.assign(h_.nodes().size() + 1, 0);
    for (const Candidate& c : kept) ++links.start[c.receiver + 1];
    for (std::size_t i = 0; i + 1 < links.start.size(); ++i) links.start[i + 1] += links.start[i];
    links.source.resize(kept.size());
    links.formFactor.resize(kept.size());
    links.uncertainty.resize(kept.size());
    links.receiverSide.resize(kept.size());
    links.facing.resize(kept.size());
    {
      std::vector<std::uint32_t> next(links.start.begin(), links.start.end() - 1);
      for (const Candidate& c : kept) {
        const std::uint32_t k = next[c.receiver]++;
        links.source[k] = c.source;
        links.formFactor[k] = c.formFactor;
        links.uncertainty[k] = c.uncertainty;
        links.receiverSide[k] = c.receiverSide;
        links.facing[k] = c.facing;
      }
    }
    kept = {};
    struct Row {
      std::uint32_t source;
      float formFactor, uncertainty;
      std::uint8_t receiverSide;
      std::array<std::uint8_t, 6> facing;
    };
    std::vector<Row> row;
    for (std::size_t r = 0; r + 1 < links.start.size(); ++r) {
      const std::uint32_t begin = links.start[r], end = links.start[r + 1];
      if (std::is_sorted(links.source.begin() + begin, links.source.begin() + end)) continue;
      row.clear();
      for (std::uint32_t k = begin; k < end; ++k)
        row.push_back({links.source[k], links.formFactor[k], links.uncertainty[k], links.receiverSide[k], links.facing[k]});
      std::sort(row.begin(), row.end(), [](const Row& a, const Row& b) { return a.source < b.source; });
      for (std::uint32_t k = begin; k < end; ++k) {
        const Row& link = row[k - begin];
        links.source[k] = link.source;
        links.formFactor[k] = link.formFactor;
        links.uncertainty[k] = link.uncertainty;
        links.receiverSide[k] = link.receiverSide;
        links.facing[k] = link.facing;
      }
    }
    return links;
  }

  // The wave's refined links, replaced by the links of the children of one of their nodes:
  // first every element that must split is split, in increasing node order (so that the new
  // nodes are numbered alike whatever order the candidates were judged in, and on every rank of a
  // distributed refinement, each of which judges only its own candidates and hands the others the
  // elements it splits), then each refined link makes its children's candidates, in the order the
  // links were judged. A distributed rank keeps only the candidates into its own nodes.
  void expand(std::vector<Expansion>& expansions, Candidates& next, RefinementReport& report) {
    std::vector<std::uint32_t> splits;
    for (const Expansion& e : expansions) {
      const std::uint32_t node = e.kind == Expansion::Receiver ? e.receiver : e.source;
      if (e.kind != Expansion::Pairs && h_.node(node).isLeaf()) splits.push_back(node);
    }
    std::sort(splits.begin(), splits.end());
    splits.erase(std::unique(splits.begin(), splits.end()), splits.end());
    if (share_) splits = share_->splitsOfEveryRank(splits);
    for (std::uint32_t node : splits) {
      h_.split(node);
      // The children start from their parent's estimates (and a distributed rank's share).
      estimator_.addChildren(node);
      if (share_) share_->addChildren(node, h_.children(node).size());
    }
    report.elementsSplit += splits.size();
    const auto add = [&](std::uint32_t receiver, std::uint32_t source) {
      if (!share_ || share_->holds(receiver)) next.push_back({receiver, source});
    };
    for (const Expansion& e : expansions) {
      if (e.kind == Expansion::Pairs) {
        std::span<const std::uint32_t> kids = h_.children(e.receiver);
        for (std::uint32_t a : kids)
          for (std::uint32_t b : kids) add(a, b);
      } else if (e.kind == Expansion::Receiver) {
        for (std::uint32_t k : h_.children(e.receiver)) add(k, e.source);
      } else {
        for (std::uint32_t k : h_.children(e.source)) add(e.receiver, k);
      }
    }
    expansions.clear();
  }

  void judge(const Candidate& c, Candidates& kept, std::vector<Expansion>& expansions, RefinementReport& report) {
    const HierarchyNode& r = h_.node(c.receiver);
    const HierarchyNode& s = h_.node(c.source);
    if (c.verdict == Verdict::Empty) return;
    bool refine = c.verdict == Verdict::Inadmissible || c.verdict == Verdict::Coarse;
    if (!refine) {
      // A cluster link's K is a Monte Carlo estimate, judged by a transfer independent of it.
      const double uncertainty = !r.isCluster() && !s.isCluster() ? c.uncertainty
                                 : c.judgedTransfer >= 0      ? c.judgedTransfer
                                                              : estimator_.judgedTransfer(c);
      refine = estimator_.tooCoarse(c, uncertainty);
    }
    // An element link whose source's leaves differ more than its mean can stand for is refined
    // (link_estimator.h, sourceVariesTooMuch): at the source where that is the larger, since only
    // that makes the error smaller; else as the factor's error says.
    const bool varies = c.verdict == Verdict::Estimated && !r.isCluster() && !s.isCluster() && estimator_.sourceVariesTooMuch(c);
    const bool bySource = varies && s.area > r.area;
    refine = refine || varies;
    // An element link whose rays were all blocked is kept with K = 0 where it is not split: it
    // moves nothing in the solve, but the final gather (hierarchical/final_gather.h) casts its own rays
    // to the source from each vertex, and a vertex at the receiver's rim may see part of it (the
    // floor beside a block's foot, in the penumbra of the lamp). Dropped, such a vertex lost its
    // share of the lamp: the Cornell box's floor came out 2% dark on average, up to 46% at the
    // blocks' feet. Cluster links whose rays were all blocked are dropped (the gather takes a
    // cluster's visibility from its link), and so are element links that could carry less than
    // kOccludedKept of the link error's power even unoccluded: kept, the ones between a
    // luminaire's parts (RenderPark's examp1.mgf: 8.6 k links → 14 k) doubled its gather's time.
    const bool keepOccluded = c.verdict == Verdict::Occluded && !r.isCluster() && !s.isCluster() &&
                              estimator_.radiosity(c.source) * c.uncertainty * r.area > kOccludedKept * estimator_.threshold();
    if (!refine && c.verdict == Verdict::Occluded) {
      if (keepOccluded) kept.push_back(c);
      return;
    }
    const bool canR = estimator_.splittable(c.receiver), canS = estimator_.splittable(c.source);
    if (!refine || (!canR && !canS)) {
      if (c.verdict == Verdict::Estimated || keepOccluded) {
        kept.push_back(c);
        report.clusterLinks += r.isCluster() || s.isCluster();  // counted here, where both nodes are at hand
      }
      return;
    }
    if (c.receiver == c.source) {
      expansions.push_back({c.receiver, c.source, Expansion::Pairs});
    } else if ((c.openSource || bySource) && canS) {
      expansions.push_back({c.receiver, c.source, Expansion::Source});
    } else if (canR && (!canS || r.area >= s.area || c.receiverSide || c.openReceiver)) {
      // The larger node, as HSA'91 splits, unless the error is the factor's spread over the
      // receiver: splitting the source would not make that smaller.
      expansions.push_back({c.receiver, c.source, Expansion::Receiver});
    } else {
      expansions.push_back({c.receiver, c.source, Expansion::Source});
    }
  }

  ElementHierarchy& h_;
  const LinkOptions& options_;
  LinkShare* share_;  // a distributed refinement's: this rank's nodes, and the other ranks; else null
  LinkEstimator estimator_;
};

}  // namespace

Links refineLinks(ElementHierarchy& hierarchy, const RayCaster& caster, double rayEpsilon,
                  std::span<const std::uint64_t> casterFace, const Links* previous, std::span<const double> leafRadiosity,
                  std::span<const double> leafOpenFraction, const LinkOptions& options, RefinementReport& report,
                  LinkShare* share) {
  Refiner refiner(hierarchy, caster, rayEpsilon, casterFace, options, leafRadiosity, leafOpenFraction, share);
  Candidates initial;
  if (previous) {
    report.initialLinks += previous->size();  // judged again by run()
  } else if (options.clusters) {
    initial.push_back({0, 0});
  } else {
    // Every ordered pair of faces (the hierarchy's roots below the clusters).
    std::vector<std::uint32_t> faces;
    for (std::uint32_t i = 0; i < hierarchy.nodes().size(); ++i) {
      const HierarchyNode& n = hierarchy.node(i);
      if (!n.isCluster() && n.parent != kNoNode && hierarchy.node(n.parent).isCluster()) faces.push_back(i);
    }
    for (std::uint32_t a : faces)
      for (std::uint32_t b : faces)
        if (a != b) initial.push_back({a, b});
  }
  report.initialLinks += initial.size();
  return refiner.run(previous, std::move(initial), report);
}

}  // namespace lambert
