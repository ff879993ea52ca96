// The outputs' final gathers spread over a distributed solve's ranks (hierarchical/distributed_ranks.h):
// rank 0 leading the others into each gather, the sites split by the rank of their leaf and their
// values handed back in site order. Its own file: the outputs' side of the ranks, as
// distributed_ranks.cpp is the refinement's and the sweeps'.
#include "lambert/hierarchical/distributed_ranks.h"

#include "lambert/hierarchical/link_cache.h"

namespace lambert {

void HierarchyRanks::lead(bool leading) {
  if (!communicator_ || communicator_->size() < 2 || leading == leading_) return;
  if (!leading) askRanks({Ask::Done, 0, 0}, {});
  leading_ = leading;
}

void HierarchyRanks::askRanks(const Asked& asked, std::span<const SurfacePoint> points) const {
  if (!leading_ || answering_ > 0) return;  // the other ranks are making the same call already
  (void)communicator_->allGatherVariable<Asked>(std::span<const Asked>(&asked, 1));
  if (asked.ask == Ask::Points) (void)communicator_->allGatherVariable<SurfacePoint>(points);
}

void HierarchyRanks::serve(const std::function<void()>& gatherVertices,
                           const std::function<void(std::span<const SurfacePoint>, PointGatherRequest)>& gatherPoints) {
  if (!communicator_ || communicator_->size() < 2) return;
  LAMBERT_CHECK(communicator_->rank() != 0);
  const Answering answering(*this);
  while (true) {
    const std::vector<Asked> asked = communicator_->allGatherVariable<Asked>({});
    LAMBERT_CHECK(asked.size() == 1);
    if (asked[0].ask == Ask::Done) return;
    if (asked[0].ask == Ask::Vertices) {
      gatherVertices();
      // Rank 0 asked for the gather of the same input (the same solution on every rank).
      LAMBERT_CHECK(lastAtVertices_.digest == asked[0].digest);
    } else {
      const std::vector<SurfacePoint> points = communicator_->allGatherVariable<SurfacePoint>({});
      gatherPoints(points, static_cast<PointGatherRequest>(asked[0].part));
    }
  }
}

Status HierarchyRanks::canGather(PointGatherRequest part) const {
  if (!communicator_ || communicator_->size() < 2 || part == PointGatherRequest::Sites || part == PointGatherRequest::Light) return Ok{};
  return Error{"a distributed solve gathers the light at points, not its weights for later solves (they read every rank's links): "
               "solve in one process to update lightmaps as lights move"};
}

void HierarchyRanks::askForPoints(PointGatherRequest part, std::span<const SurfacePoint> points) const {
  askRanks({Ask::Points, static_cast<std::uint32_t>(part), 0}, points);
}

HierarchyRanks::SitesByRank HierarchyRanks::sitesByRank(const std::vector<std::uint32_t>& leaf) const {
  SitesByRank split{std::vector<std::vector<std::uint32_t>>(static_cast<std::size_t>(communicator_->size())),
                    std::vector<std::uint32_t>(leaf.size(), kNoNode)};
  for (std::uint32_t i = 0; i < leaf.size(); ++i) {
    if (leaf[i] == kNoNode) continue;
    const int owner = transport_ ? transport_->rankOfLeaf(leaf[i]) : 0;  // before the first refinement, rank 0's
    split.sites[static_cast<std::size_t>(owner)].push_back(i);
    if (owner == communicator_->rank()) split.mine[i] = leaf[i];
  }
  return split;
}

template <class T>
std::vector<T> HierarchyRanks::inSiteOrder(const SitesByRank& split, const std::vector<T>& ofMine) const {
  std::vector<T> sent;
  for (std::uint32_t i : split.sites[static_cast<std::size_t>(communicator_->rank())]) sent.push_back(ofMine[i]);
  std::vector<int> counts;
  std::size_t total = 0;
  for (const std::vector<std::uint32_t>& sites : split.sites) {
    counts.push_back(static_cast<int>(sites.size()));
    total += sites.size();
  }
  std::vector<T> all(total), out(ofMine.size());
  communicator_->allGather<T>(sent, counts, all);
  std::size_t k = 0;
  for (const std::vector<std::uint32_t>& sites : split.sites)
    for (std::uint32_t i : sites) out[i] = all[k++];
  return out;
}

std::vector<Rgb> HierarchyRanks::gatherAcrossRanks(const FinalGather& whole, const std::vector<Rgb>& mean, FinalGatherCounts& counts,
                                                    NearFieldWeights& near) const {
  const std::vector<std::uint32_t>& leaf = whole.gatheringLeaf();
  SitesByRank split = sitesByRank(leaf);
  // The same sites, so that every vertex draws its rays as in one process.
  const FinalGather gather = whole.throughLeaves(std::move(split.mine));
  NearFieldWeights own;
  const std::vector<Rgb> gathered = gather.irradiance(mean, &counts, nullptr, nullptr, &own);
  struct VertexRecord {
    Rgb gathered, meanPart;
    std::uint32_t entries = 0;
  };
  struct EntryRecord {
    std::uint32_t corner;
    float weight;
  };
  std::vector<VertexRecord> mine(leaf.size());
  std::vector<EntryRecord> sentEntries;
  for (std::uint32_t v : split.sites[static_cast<std::size_t>(communicator_->rank())]) {
    mine[v] = {gathered[v], own.meanPart[v], own.start[v + 1] - own.start[v]};
    for (std::uint32_t k = own.start[v]; k < own.start[v + 1]; ++k) sentEntries.push_back({own.corner[k], own.weight[k]});
  }
  const std::vector<VertexRecord> record = inSiteOrder(split, mine);
  const std::vector<EntryRecord> entries = communicator_->allGatherVariable<EntryRecord>(sentEntries);
  // The weights as compressed rows in vertex order; the entries arrived in rank order.
  std::vector<std::size_t> entryOf(leaf.size(), 0);
  std::size_t entry = 0;
  for (const std::vector<std::uint32_t>& sites : split.sites)
    for (std::uint32_t v : sites) {
      entryOf[v] = entry;
      entry += record[v].entries;
    }
  std::vector<Rgb> out(leaf.size());
  near = {};
  near.meanPart.assign(leaf.size(), Rgb{});
  near.start.assign(leaf.size() + 1, 0);
  for (std::size_t v = 0; v < leaf.size(); ++v) near.start[v + 1] = near.start[v] + record[v].entries;
  near.corner.resize(near.start.back());
  near.weight.resize(near.start.back());
  for (std::size_t v = 0; v < leaf.size(); ++v) {
    out[v] = record[v].gathered;
    near.meanPart[v] = record[v].meanPart;
    for (std::uint32_t k = 0; k < record[v].entries; ++k) {
      near.corner[near.start[v] + k] = entries[entryOf[v] + k].corner;
      near.weight[near.start[v] + k] = entries[entryOf[v] + k].weight;
    }
  }
  return out;
}

std::vector<Rgb> HierarchyRanks::gatherAtVertices(const FinalGather& whole, const std::vector<Rgb>& mean, const std::vector<Rgb>& direct,
                                                  const std::vector<Rgb>& emitted, const std::vector<Rgb>& albedo,
                                                  FinalGatherCounts& counts, NearFieldWeights& near, NearFieldCoupling* coupling) const {
  const std::uint64_t digest = gatherInputDigest(mean, 0, {&direct, &emitted, &albedo});
  if (lastAtVertices_.digest == digest && !lastAtVertices_.gathered.empty()) {
    const std::lock_guard<std::mutex> lock(lastAtVerticesMutex_);
    for (std::uint32_t l : whole.gatheringLeaf()) counts.vertices += l != kNoNode;
    return lastAtVertices_.gathered;
  }
  // Every rank gathers the vertices of its own leaves (through its own links: it holds no
  // others); the results and the close sources' corner weights go to every rank, which couples
  // them as one process would. Rank 0 writing the outputs asks the others to join first.
  askRanks({Ask::Vertices, 0, digest}, {});
  const Answering answering(*this);
  std::vector<Rgb> gathered =
      FinalGather::coupleNearField(gatherAcrossRanks(whole, mean, counts, near), near, emitted, albedo, direct, coupling);
  const std::lock_guard<std::mutex> lock(lastAtVerticesMutex_);
  lastAtVertices_ = {digest, gathered};
  return gathered;
}

std::vector<Rgb> HierarchyRanks::gatherAtSites(const FinalGather& whole, const std::vector<Rgb>& mean,
                                               const std::function<std::vector<Rgb>()>& cornerRadiosity) const {
  const Answering answering(*this);
  // Each site is gathered by the rank of its leaf, through its own links.
  SitesByRank split = sitesByRank(whole.gatheringLeaf());
  const FinalGather gather = whole.throughLeaves(std::move(split.mine));
  NearFieldWeights near;
  const std::vector<Rgb> gathered = gather.irradiance(mean, nullptr, nullptr, nullptr, &near, nullptr);
  return inSiteOrder(split, FinalGather::withCorners(gathered, near, cornerRadiosity()));
}

}  // namespace lambert
