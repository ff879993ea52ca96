#pragma once
// The hierarchical method's cache files, as the method uses them (their formats and keys:
// hierarchical/link_cache.h): the link cache its first solve loads every refinement pass from or
// saves after the last (HierarchicalMethod::loadLinks and saveLinks, method_cache.cpp), and the
// final gather's visibility and irradiance files beside it. Its own file so that the refinement
// (method.cpp) and the outputs (vertex_outputs.cpp) read without the files' bookkeeping.
// Internal to hierarchical/.
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "lambert/core/stats.h"
#include "lambert/method/options.h"
#include "lambert/method/solve_call.h"
#include "lambert/hierarchical/final_gather.h"
#include "lambert/hierarchical/link_cache.h"

namespace lambert {

struct LinkCacheFile {
  std::string directory;        // RadiosityOptions::cacheDirectory; empty: off
  RadiosityOptions options;     // what the key reads of them
  SolveBudget firstBudget;      // of the first solve
  std::string path;             // the file, once keyed
  std::uint64_t key = 0;
  std::string status = "off";   // the formfactor_cache stat
  std::uint64_t bytes = 0;      // the file's size, loaded or saved
  double seconds = 0;           // keying, loading and replaying, or saving
};

// The final gather's visibility and irradiance files beside the links (hierarchical/link_cache.h):
// read before the first gather over the last pass's links. The visibility file is written after
// that gather where it held nothing usable; the irradiance file where it held no values for
// that gather's input (so it holds the last process's first gather). Safe to use from any thread
// (vertexSolution is const and may run on any).
class GatherCacheFiles {
 public:
  // What one gather reads of the files, and the files it writes after it (empty: none).
  struct Use {
    std::shared_ptr<const GatherVisibility> known;
    std::uint64_t knownDigest = 0;  // gatherVisibilityDigest(known)
    std::shared_ptr<const CachedGatherIrradiance> stored;
    std::string recordPath, irradiancePath;
  };
  // The files beside links.path, read by the first gather (for a leaf mesh of numVertices, over
  // numLinks links and numNodes nodes); later gathers reuse what it read.
  Use open(const LinkCacheFile& links, std::size_t numVertices, std::size_t numLinks, std::size_t numNodes);
  // A gather read its result from the irradiance file; seconds: its digests.
  void readIrradiance(double seconds);
  void saveVisibility(const LinkCacheFile& links, const std::string& path, const GatherVisibility& recorded);
  // made: the gather's result under the digest of the input the next process will read it for.
  void saveIrradiance(const LinkCacheFile& links, const std::string& path, const CachedGatherIrradiance& made, double seconds);
  // A gather over the cache's links that wrote no irradiance file; seconds: its digests.
  void addIrradianceSeconds(double seconds);
  void addStats(Stats& stats) const;

 private:
  mutable std::mutex mutex_;
  bool tried_ = false;
  std::shared_ptr<const GatherVisibility> known_;
  std::uint64_t knownDigest_ = 0;  // gatherVisibilityDigest(known_)
  std::string status_ = "off";  // the gather_cache stat
  std::uint64_t bytes_ = 0;     // the file's size, loaded or saved
  double seconds_ = 0;          // loading or saving
  std::shared_ptr<const CachedGatherIrradiance> irradiance_;
  std::string irradianceStatus_ = "off";  // the gather_irradiance_cache stat
  std::uint64_t irradianceBytes_ = 0;     // the file's size, loaded or saved
  std::uint64_t irradianceReads_ = 0;     // gathers whose result was read from it
  double irradianceSeconds_ = 0;          // digests, loading or saving
};

}  // namespace lambert
