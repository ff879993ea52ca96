// The final gather's outputs beside the irradiance (hierarchical/final_gather_outputs.h).
#include "lambert/hierarchical/final_gather_outputs.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include "lambert/core/error.h"

namespace lambert {

GatherOutputs::GatherOutputs(std::size_t numSites, FinalGatherCounts* counts, const GatherVisibility* known, GatherVisibility* record,
                             NearFieldWeights* near, GatherWeights* weights)
    : numSites_(numSites),
      counts_(counts),
      known_(known),
      record_(record),
      near_(near),
      weights_(weights),
      siteWeights_(weights ? numSites : 0),
      work_(counts ? numSites : 0, {0, 0, 0, 0}) {
  if (near) near->meanPart.assign(numSites, Rgb{});
}

std::uint32_t* GatherOutputs::work(std::size_t site, std::uint32_t* unused) { return counts_ ? work_[site].data() : unused; }

void GatherOutputs::used(std::uint32_t site, std::uint32_t link, std::uint32_t flaggedSource, double seen) {
  if (record_) used_.local().push_back({site, link, flaggedSource, seen});
}

void GatherOutputs::addNearField(std::uint32_t site, std::uint32_t corner, float weight) {
  nearEntries_.local().push_back({site, corner, weight});
}

void GatherOutputs::addWeights(std::uint32_t site, const std::vector<std::pair<std::uint32_t, double>>& entries) {
  std::vector<std::pair<std::uint32_t, float>>& merged = siteWeights_[site];
  for (std::size_t i = 0; i < entries.size();) {
    double w = 0;
    std::size_t j = i;
    for (; j < entries.size() && entries[j].first == entries[i].first; ++j) w += entries[j].second;
    merged.push_back({entries[i].first, static_cast<float>(w)});
    i = j;
  }
}

void GatherOutputs::finish(const std::vector<std::uint32_t>& leafOfSite) {
  if (near_) finishNearField();
  if (weights_) finishWeights();
  if (counts_) finishCounts(leafOfSite);
  if (record_) finishRecord();
}

void GatherOutputs::finishNearField() {
  near_->start.assign(numSites_ + 1, 0);
  std::size_t total = 0;
  for (const std::vector<NearEntry>& entries : nearEntries_) {
    total += entries.size();
    for (const NearEntry& e : entries) ++near_->start[e.vertex + 1];
  }
  LAMBERT_CHECK(total < std::numeric_limits<std::uint32_t>::max());
  for (std::size_t v = 0; v < numSites_; ++v) near_->start[v + 1] += near_->start[v];
  near_->corner.resize(total);
  near_->weight.resize(total);
  std::vector<std::uint32_t> next(near_->start.begin(), near_->start.end() - 1);
  for (const std::vector<NearEntry>& entries : nearEntries_)
    for (const NearEntry& e : entries) {
      near_->corner[next[e.vertex]] = e.corner;
      near_->weight[next[e.vertex]++] = e.weight;
    }
}

void GatherOutputs::finishWeights() {
  weights_->start.assign(numSites_ + 1, 0);
  for (std::size_t v = 0; v < numSites_; ++v) weights_->start[v + 1] = weights_->start[v] + static_cast<std::uint32_t>(siteWeights_[v].size());
  LAMBERT_CHECK(std::accumulate(siteWeights_.begin(), siteWeights_.end(), std::size_t{0},
                                [](std::size_t n, const auto& w) { return n + w.size(); }) < std::numeric_limits<std::uint32_t>::max());
  weights_->node.resize(weights_->start.back());
  weights_->weight.resize(weights_->start.back());
  for (std::size_t v = 0; v < numSites_; ++v) {
    std::size_t k = weights_->start[v];
    for (const auto& [node, w] : siteWeights_[v]) {
      weights_->node[k] = node;
      weights_->weight[k++] = w;
    }
    std::vector<std::pair<std::uint32_t, float>>().swap(siteWeights_[v]);
  }
}

void GatherOutputs::finishCounts(const std::vector<std::uint32_t>& leafOfSite) {
  *counts_ = {};
  for (std::size_t v = 0; v < work_.size(); ++v) {
    if (leafOfSite[v] == kNoNode) continue;
    ++counts_->vertices;
    counts_->sourcesGathered += work_[v][0];
    counts_->sourcesOpened += work_[v][1];
    counts_->visibilityRays += work_[v][2];
    counts_->visibilityKnown += work_[v][3];
    counts_->maxSourcesGathered = std::max<std::uint64_t>(counts_->maxSourcesGathered, work_[v][0]);
    counts_->maxVisibilityRays = std::max<std::uint64_t>(counts_->maxVisibilityRays, work_[v][2]);
  }
}

void GatherOutputs::finishRecord() {
  // Grouped by vertex, each vertex's in (link, source) order, each value once (a pair met
  // twice has one value): counted per vertex, placed, then sorted within each vertex.
  *record_ = {};
  record_->start.assign(numSites_ + 1, 0);
  std::size_t total = 0;
  for (const std::vector<SeenEntry>& entries : used_) {
    total += entries.size();
    for (const SeenEntry& e : entries) ++record_->start[e.vertex + 1];
  }
  LAMBERT_CHECK(total < std::numeric_limits<std::uint32_t>::max());
  for (std::size_t v = 0; v < numSites_; ++v) record_->start[v + 1] += record_->start[v];
  std::vector<SeenEntry> placed(total);
  std::vector<std::uint32_t> next(record_->start.begin(), record_->start.end() - 1);
  for (std::vector<SeenEntry>& entries : used_) {
    for (const SeenEntry& e : entries) placed[next[e.vertex]++] = e;
    std::vector<SeenEntry>().swap(entries);
  }
  std::vector<std::uint32_t>().swap(next);
  record_->link.reserve(total);
  record_->source.reserve(total);
  record_->seen.reserve(total);
  std::uint32_t kept = 0;
  for (std::size_t v = 0; v < numSites_; ++v) {
    const auto first = placed.begin() + record_->start[v], last = placed.begin() + record_->start[v + 1];
    std::sort(first, last, [](const SeenEntry& a, const SeenEntry& b) { return a.link != b.link ? a.link < b.link : a.source < b.source; });
    record_->start[v] = kept;
    for (auto e = first; e != last; ++e) {
      if (e != first && e->link == (e - 1)->link && e->source == (e - 1)->source) continue;
      record_->link.push_back(e->link);
      record_->source.push_back(e->source);
      record_->seen.push_back(e->seen);
      ++kept;
    }
  }
  record_->start.back() = kept;
}

}  // namespace lambert
