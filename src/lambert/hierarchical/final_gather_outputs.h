#pragma once
// What a final gather (hierarchical/final_gather.h) hands back beside the irradiance at each site,
// each only where its caller asked for it: the work it did (FinalGatherCounts), the visibility
// values it used (a GatherVisibility to record), the close leaf sources' corner weights
// (NearFieldWeights) and the weights on the node means (GatherWeights). The sites are gathered in
// parallel: each output is collected per thread or per site while they are, then put in site
// order once all are done (finish). Its own file so that the gather's traversal
// (final_gather.cpp) reads as the light's path alone. Internal to hierarchical/.
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "lambert/core/rgb.h"
#include "lambert/method/point_gather.h"
#include "lambert/hierarchical/final_gather.h"

namespace lambert {

// Irradiance is never negative (core/rgb.h's nonNegative): the shaped means' and the corners'
// corrections, added to a sum that should be 0 (a covered site), leave rounding of either sign
// (−1e-17).
class GatherOutputs {
 public:
  // The outputs FinalGather::irradiance was given (null: not asked for); known: the visibility
  // values it may read instead of casting rays (null: none).
  GatherOutputs(std::size_t numSites, FinalGatherCounts* counts, const GatherVisibility* known, GatherVisibility* record,
                NearFieldWeights* near, GatherWeights* weights);

  // A site's work: sources gathered, sources opened, visibility rays, visibility values read;
  // `unused` where no counts were asked for.
  std::uint32_t* work(std::size_t site, std::uint32_t* unused);
  const GatherVisibility* known() const { return known_; }
  // One visibility value the site used (flaggedSource: the source | GatherVisibility::kPenumbra).
  void used(std::uint32_t site, std::uint32_t link, std::uint32_t flaggedSource, double seen);
  bool wantsNearField() const { return near_ != nullptr; }
  bool wantsWeights() const { return weights_ != nullptr; }
  // A close leaf source's corner weight at the site, and the share of the site's irradiance
  // those corners take over (NearFieldWeights::meanPart).
  void addNearField(std::uint32_t site, std::uint32_t corner, float weight);
  Rgb& nearFieldMeanPart(std::uint32_t site) { return near_->meanPart[site]; }
  // The site's weights on the node means, sorted by node: merged into one per node.
  void addWeights(std::uint32_t site, const std::vector<std::pair<std::uint32_t, double>>& sorted);
  // Every output asked for, in site order (leafOfSite: kNoNode where a site was not gathered).
  void finish(const std::vector<std::uint32_t>& leafOfSite);

 private:
  // One visibility value as a gather used it (GatherVisibility's entry, with its vertex).
  struct SeenEntry {
    std::uint32_t vertex, link, source;
    double seen;
  };
  // One corner weight of a close leaf source (NearFieldWeights' entry, with its vertex).
  struct NearEntry {
    std::uint32_t vertex, corner;
    float weight;
  };
  void finishNearField();
  void finishWeights();
  void finishCounts(const std::vector<std::uint32_t>& leafOfSite);
  void finishRecord();

  std::size_t numSites_;
  FinalGatherCounts* counts_;
  const GatherVisibility* known_;
  GatherVisibility* record_;
  NearFieldWeights* near_;
  GatherWeights* weights_;
  // Recorded per thread (24 bytes a value, a few values a vertex), sorted into `record` after.
  tbb::enumerable_thread_specific<std::vector<SeenEntry>> used_;
  tbb::enumerable_thread_specific<std::vector<NearEntry>> nearEntries_;
  // Per site, its weights on the node means, sorted by node and merged (weights only).
  std::vector<std::vector<std::pair<std::uint32_t, float>>> siteWeights_;
  // Per vertex: sources gathered, sources opened, visibility rays, visibility values read.
  std::vector<std::array<std::uint32_t, 4>> work_;
};

}  // namespace lambert
