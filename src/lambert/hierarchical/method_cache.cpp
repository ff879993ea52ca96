// The hierarchical method's cache files (hierarchical/method_cache.h): the link cache's load and
// save, and the final gather's visibility and irradiance files.
#include "lambert/hierarchical/method_cache.h"

#include <cstdio>
#include <filesystem>

#include "lambert/core/cache_file.h"
#include "lambert/core/timer.h"
#include "lambert/core/warning.h"
#include "lambert/hierarchical/method.h"

namespace lambert {
namespace {

std::string mebibytes(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MiB", static_cast<double>(bytes) / (1024.0 * 1024.0));
  return text;
}

}  // namespace

bool HierarchicalMethod::loadLinks(const std::vector<Light>& lights, std::vector<Rgb>& radiosity) {
  if (!linkCacheUsable(linkCache_.options, linkCache_.firstBudget)) {
    linkCache_.status = "off: a time budget stops the solves between refinement passes at no fixed point";
    return false;
  }
  Timer timer;
  linkCache_.key = linkCacheKey(scene_, lights, linkCache_.options, linkCache_.firstBudget);
  linkCache_.path = linkCachePath(linkCache_.directory, linkCache_.key);
  Result<CachedRefinement> loaded = loadRefinement(linkCache_.path, linkCache_.key);
  if (!loaded) {
    // No file is the ordinary first run; anything else (unreadable, damaged, stale) is reported
    // and recomputed, and the file replaced.
    if (!cachefile::isMissing(linkCache_.path)) warning(loaded.error().message + "; recomputing");
    linkCache_.seconds += timer.seconds();
    return false;
  }
  if (Status replayed = replaySplits(hierarchy_, *loaded); !replayed) {
    warning(linkCache_.path + ": " + replayed.error().message + "; recomputing");
    hierarchy_ = ElementHierarchy(scene_);  // the leaves_ of the constructor still describe it
    linkCache_.seconds += timer.seconds();
    return false;
  }
  if (!loaded->splits.empty()) leaves_ = hierarchy_.leaves(scene_);
  leafMeshNodes_ = hierarchy_.nodes().size();
  for (std::size_t i = 0; i < leaves_.mesh.numPatches(); ++i) leaves_.mesh.patches[i].openFraction = loaded->openFraction[i];
  ++leafMeshGeneration_;
  measuredLeafNodes_ = hierarchy_.leafNodes();
  links_ = loaded->links;
  transport_ = makeTransport();
  radiosity = std::move(loaded->warmStart);
  refinement_.initialLinks = loaded->initialLinks;
  refinement_.clusterLinks = loaded->clusterLinks;
  lightSplits_ = loaded->lightSplits;
  passesDone_ = options_.refinePasses;
  std::error_code ec;
  linkCache_.bytes = std::filesystem::file_size(linkCache_.path, ec);
  linkCache_.status = "loaded " + linkCache_.path + " (" + mebibytes(linkCache_.bytes) + ")";
  linkCache_.seconds += timer.seconds();
  return true;
}

void HierarchicalMethod::saveLinks(const std::vector<Rgb>& warmStart) {
  Timer timer;
  CachedRefinement refinement;
  refinement.splits = splitOrder(hierarchy_);
  refinement.numNodes = hierarchy_.nodes().size();
  refinement.links = links_;
  refinement.warmStart = warmStart;
  refinement.openFraction = openFractions(leaves_.mesh);
  refinement.initialLinks = refinement_.initialLinks;
  refinement.clusterLinks = refinement_.clusterLinks;
  refinement.lightSplits = lightSplits_;
  Result<std::uint64_t> saved = saveRefinement(linkCache_.path, linkCache_.key, refinement);
  if (saved) {
    linkCache_.bytes = *saved;
    linkCache_.status = "saved " + linkCache_.path + " (" + mebibytes(*saved) + ")";
  } else {
    warning(saved.error().message + "; links not cached");
    linkCache_.status = "not saved: " + saved.error().message;
  }
  linkCache_.seconds += timer.seconds();
}

GatherCacheFiles::Use GatherCacheFiles::open(const LinkCacheFile& links, std::size_t numVertices, std::size_t numLinks,
                                             std::size_t numNodes) {
  Use use;
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!tried_) {
    tried_ = true;
    Timer timer;
    const std::string path = gatherVisibilityPath(links.directory, links.key);
    Result<GatherVisibility> loaded = loadGatherVisibility(path, links.key, numVertices, numLinks, numNodes);
    if (loaded) {
      std::error_code ec;
      bytes_ = std::filesystem::file_size(path, ec);
      status_ = "loaded " + path + " (" + std::to_string(loaded->size()) + " values, " + mebibytes(bytes_) + ")";
      known_ = std::make_shared<const GatherVisibility>(std::move(*loaded));
    } else {
      // As for the links: no file is the ordinary first run, anything else is reported.
      if (!cachefile::isMissing(path)) warning(loaded.error().message + "; recomputing");
      use.recordPath = path;
    }
    knownDigest_ = gatherVisibilityDigest(known_.get());
    seconds_ += timer.seconds();
    Timer irradianceTimer;
    use.irradiancePath = gatherIrradiancePath(links.directory, links.key);
    Result<CachedGatherIrradiance> irradiance = loadGatherIrradiance(use.irradiancePath, links.key, numVertices);
    if (irradiance) {
      std::error_code ec;
      irradianceBytes_ = std::filesystem::file_size(use.irradiancePath, ec);
      irradianceStatus_ = "loaded " + use.irradiancePath + " (" + mebibytes(irradianceBytes_) + ")";
      irradiance_ = std::make_shared<const CachedGatherIrradiance>(std::move(*irradiance));
    } else {
      if (!cachefile::isMissing(use.irradiancePath)) warning(irradiance.error().message + "; recomputing");
      irradianceStatus_ = "none";
    }
    irradianceSeconds_ += irradianceTimer.seconds();
  }
  use.known = known_;
  use.knownDigest = knownDigest_;
  use.stored = irradiance_;
  return use;
}

void GatherCacheFiles::readIrradiance(double seconds) {
  const std::lock_guard<std::mutex> lock(mutex_);
  ++irradianceReads_;
  irradianceSeconds_ += seconds;
}

void GatherCacheFiles::saveVisibility(const LinkCacheFile& links, const std::string& path, const GatherVisibility& recorded) {
  Timer timer;
  Result<std::uint64_t> saved = saveGatherVisibility(path, links.key, recorded);
  const std::lock_guard<std::mutex> lock(mutex_);
  if (saved) {
    bytes_ = *saved;
    status_ = "saved " + path + " (" + std::to_string(recorded.size()) + " values, " + mebibytes(*saved) + ")";
  } else {
    warning(saved.error().message + "; final gather visibility not cached");
    status_ = "not saved: " + saved.error().message;
  }
  seconds_ += timer.seconds();
}

void GatherCacheFiles::saveIrradiance(const LinkCacheFile& links, const std::string& path, const CachedGatherIrradiance& made,
                                      double seconds) {
  Timer timer;
  Result<std::uint64_t> saved = saveGatherIrradiance(path, links.key, made);
  const std::lock_guard<std::mutex> lock(mutex_);
  if (saved) {
    irradianceBytes_ = *saved;
    irradianceStatus_ = "saved " + path + " (" + mebibytes(*saved) + ")";
  } else {
    warning(saved.error().message + "; final gather irradiance not cached");
    irradianceStatus_ = "not saved: " + saved.error().message;
  }
  irradianceSeconds_ += seconds + timer.seconds();
}

void GatherCacheFiles::addIrradianceSeconds(double seconds) {
  const std::lock_guard<std::mutex> lock(mutex_);
  irradianceSeconds_ += seconds;
}

void GatherCacheFiles::addStats(Stats& stats) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  stats.add("gather_cache", "final gather visibility cache", status_);
  if (bytes_ > 0) stats.add("gather_cache_bytes", "final gather visibility file size", static_cast<std::int64_t>(bytes_), "B");
  stats.add("gather_cache_seconds", "final gather visibility cache time (load or save)", seconds_, "s");
  stats.add("gather_irradiance_cache", "final gather irradiance cache", irradianceStatus_);
  if (irradianceBytes_ > 0)
    stats.add("gather_irradiance_cache_bytes", "final gather irradiance file size", static_cast<std::int64_t>(irradianceBytes_), "B");
  stats.add("gather_irradiance_reads", "final gathers read from the irradiance cache", static_cast<std::int64_t>(irradianceReads_));
  stats.add("gather_irradiance_cache_seconds", "final gather irradiance cache time (digest, load or save)", irradianceSeconds_, "s");
}

}  // namespace lambert
