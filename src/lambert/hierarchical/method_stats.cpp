// The hierarchical method's figures (hierarchical/method.h): its hierarchy, links, times, caches
// and last final gather. Its own file: a long list that reads no better beside the algorithms.
#include "lambert/hierarchical/method.h"

#include <mutex>
#include <string>

namespace lambert {

void HierarchicalMethod::addStats(Stats& stats) const {
  const auto count = [](auto n) { return static_cast<std::int64_t>(n); };
  stats.add("mesh", "mesh", std::string(options_.links.clusters ? "hierarchical, clustered" : "hierarchical, unclustered"));
  stats.add("faces", "input faces", count(hierarchy_.numFaces()));
  stats.add("clusters", "clusters", count(hierarchy_.numClusters()));
  stats.add("elements", "elements", count(hierarchy_.numElements()));
  stats.add("patches", "leaf elements", count(leaves_.mesh.numPatches()));
  stats.add("vertices", "vertices", count(leaves_.mesh.numVertices()));
  stats.add("hanging_vertices", "T-junction vertices (constrained)", count(leaves_.hanging.size()));
  stats.add("link_error", "link error", options_.links.linkError);
  ranks_.addCommunicationStats(stats, transport_->size());
  stats.add("min_element_area", "minimum element area", minimumElementArea(hierarchy_, options_.links), "scene units²");
  stats.add("refine_passes", "refinement passes", count(passesDone_));
  if (ranks_.distributed()) {
    ranks_.addLinkStats(stats, *links_);
  } else {
    stats.add("links", "links", count(links_->size()));
  }
  stats.add("cluster_links", "links with a cluster end", count(refinement_.clusterLinks));
  stats.add("largest_row_sum", "largest Σ K over a leaf's links and its ancestors'", transport_->largestRowSum());
  stats.add("rows_scaled", "leaves whose Σ K was scaled down (the bound)", count(transport_->rowsScaled()));
  stats.add("initial_links", "initial links", count(refinement_.initialLinks));
  stats.add("links_estimated", "links estimated", count(refinement_.estimated));
  stats.add("visibility_rays", "visibility rays", count(refinement_.rays));
  stats.add("light_splits", "elements split at light edges", count(lightSplits_));
  stats.add("light_edge_samples", "light-edge samples (points × lights not culled by their bounds)", count(lightSamples_));
  stats.add("light_edge_rays", "light-edge shadow rays (lights that could split an element)", count(lightEdgeRays_));
  const double linkBytes = static_cast<double>(links_->bytes());
  const double nodeBytes = static_cast<double>(hierarchy_.bytes());
  stats.add("link_bytes", ranks_.distributed() ? "link memory (this rank, 0)" : "link memory", linkBytes / (1024.0 * 1024.0), "MiB");
  stats.add("bytes_per_link", "bytes per link", links_->size() ? linkBytes / static_cast<double>(links_->size()) : 0.0, "B");
  stats.add("node_bytes", "hierarchy memory", nodeBytes / (1024.0 * 1024.0), "MiB");
  stats.add("bytes_per_element", "bytes per node", nodeBytes / static_cast<double>(hierarchy_.nodes().size()), "B");
  stats.add("hierarchy_seconds", "hierarchy build time", buildSeconds_, "s");
  stats.add("bvh_seconds", "BVH build time", bvhSeconds_, "s");
  stats.add("light_edge_seconds", "light-edge refinement time", lightSeconds_, "s");
  stats.add("link_seconds", "link refinement time", refinement_.seconds, "s");
  stats.add("leaf_mesh_seconds", "leaf mesh time", leafSeconds_, "s");
  stats.add("coverage_seconds", "open-fraction (coverage) time", coverageSeconds_, "s");
  stats.add("transport_seconds", "transport setup time", transportSeconds_, "s");
  stats.add("formfactor_seconds", "form-factor time", refinement_.seconds + lightSeconds_, "s");
  stats.add("formfactor_cache", "link cache", linkCache_.status);
  if (linkCache_.bytes > 0) stats.add("link_cache_bytes", "link cache file size", static_cast<std::int64_t>(linkCache_.bytes), "B");
  if (!linkCache_.directory.empty())
    stats.add("link_cache_seconds", "link cache time (key, load and replay, or save)", linkCache_.seconds, "s");
  if (!linkCache_.directory.empty()) gatherCache_.addStats(stats);
  const std::lock_guard<std::mutex> lock(gatherMutex_);
  if (gatherCounts_.vertices > 0) {
    const double vertices = static_cast<double>(gatherCounts_.vertices);
    stats.add("gather_vertices", "final gather: vertices", count(gatherCounts_.vertices));
    stats.add("gather_sources_per_vertex", "final gather: sources per vertex (mean)",
              static_cast<double>(gatherCounts_.sourcesGathered) / vertices);
    stats.add("gather_sources_max", "final gather: sources at one vertex (most)", count(gatherCounts_.maxSourcesGathered));
    stats.add("gather_opened_per_vertex", "final gather: sources opened per vertex (mean)",
              static_cast<double>(gatherCounts_.sourcesOpened) / vertices);
    stats.add("gather_rays_per_vertex", "final gather: visibility rays per vertex (mean)",
              static_cast<double>(gatherCounts_.visibilityRays) / vertices);
    stats.add("gather_rays_max", "final gather: visibility rays at one vertex (most)", count(gatherCounts_.maxVisibilityRays));
    stats.add("gather_visibility_cached", "final gather: visibility values read from the cache", count(gatherCounts_.visibilityKnown));
    stats.add("gather_near_weights", "final gather: corner weights of sources seen from close by", count(nearFieldWeights_));
    stats.add("gather_near_iterations", "final gather: BiCGSTAB iterations coupling those corners", count(nearFieldCoupling_.iterations));
    stats.add("gather_near_converged", "final gather: whether those steps converged (else the leaves' means are shown)",
              std::string(nearFieldCoupling_.converged ? "yes" : "no"));
    stats.add("gather_near_rows_scaled", "final gather: vertices whose close sources' weights the contraction bound scaled",
              count(nearFieldCoupling_.rowsScaled));
    stats.add("gather_reused", "final gather: vertex outputs answered by this process's last gather (the same input)", count(gatherReuses_));
    stats.add("gather_seconds", "final gather time (last: sites, gather, direct light at the vertices)", gatherSeconds_, "s");
  }
}

}  // namespace lambert
