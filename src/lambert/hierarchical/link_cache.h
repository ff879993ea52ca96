#pragma once
// The hierarchical method's links cached on disk, as the flat method keeps its master form-factor table, saved so
// that "the form factors computed during the initial computation run do not have to be
// recomputed", for the element hierarchy and its
// links (Hanrahan, Salzman & Aupperle 1991) instead of a quad-tree's pairs.
//
// A file holds what the first solve's refinement passes leave behind, so that a later process
// with the same inputs loads it instead of refining, and solves to the same bits:
//   - the elements split, in the order they were split: replaying ElementHierarchy::split over
//     the hierarchy built from the scene gives the same nodes under the same numbers;
//   - the links (Links, compressed rows over those nodes);
//   - the radiosity the last pass handed the solve as its warm start (each new leaf from its old
//     ancestor), so the one solve of a loading run starts where the computing run's last solve
//     started and takes the same sweeps;
//   - the leaves' open fractions (geometry/coverage.h: 16 rays a leaf, a fifth of a loading run's
//     time on a 10⁵-face building when measured again).
// Everything the refinement reads is in the key (linkCacheKey): the scene's geometry, materials
// (albedo and emission judge links through the BF oracle's radiosity estimate) and textures, the
// lights at the first solve (their direct light is in that estimate, and they split elements at
// cone and shadow edges), the link options and refinement passes, the solver, tolerance, sweep
// limits and direct-light sampling of the solves between passes, the file's format, and a digest
// of the library sources that compute any of it (link_sources_digest.h, made by the build), so
// that a changed refinement never serves links from an older one. Lights that move after the
// first solve (setLights + solve, animate) re-solve over the same links and never touch the file.
//
// Beside it, two files of the same key hold what the final gather over those links computed: its
// visibility values (.lhv, geometry only) and its irradiance at the vertices for one radiosity
// (.lhg, under a digest of the radiosity and the visibility values it read).
//
// Files share the flat caches' header, XXH64 checksum, validation and atomic write
// (core/cache_file.h), so concurrent processes on one cache directory see a whole file or
// none, and a file that is stale, truncated or damaged is reported and recomputed, never trusted.
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <string>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/rgb.h"
#include "lambert/hierarchical/final_gather.h"
#include "lambert/hierarchical/links.h"
#include "lambert/hierarchical/element_hierarchy.h"
#include "lambert/scene/scene.h"

namespace lambert {

struct RadiosityOptions;
struct SolveBudget;

// Whether a first solve under this budget refines reproducibly: a time budget stops the solves
// between refinement passes wherever the clock says, and the next pass refines from that, so its
// links cannot be keyed (with one pass no solve comes before the refinement, and any budget is).
bool linkCacheUsable(const RadiosityOptions& options, const SolveBudget& firstBudget);

// XXH64 over every input the first solve's refinement reads (see above): scene, lights at the
// first solve, options, the first solve's sweep budget (with more than one pass), format and
// source digest.
std::uint64_t linkCacheKey(const Scene& scene, const std::vector<Light>& lights, const RadiosityOptions& options,
                           const SolveBudget& firstBudget);

// The file for a key inside a cache directory: <directory>/links-<16 hex digits>.lhl
std::string linkCachePath(const std::string& directory, std::uint64_t key);

// What the refinement passes leave: enough to rebuild the hierarchy and the solve's start.
struct CachedRefinement {
  std::vector<std::uint32_t> splits;  // elements split, in the order they were split
  std::uint64_t numNodes = 0;         // nodes after the splits (checked when replaying)
  std::shared_ptr<const Links> links;
  std::vector<Rgb> warmStart;         // per leaf (after the splits), W/m²
  std::vector<double> openFraction;   // per leaf: Patch::openFraction (geometry/coverage.h)
  // Descriptions of the links carried over to the stats of a loading run.
  std::uint64_t initialLinks = 0, clusterLinks = 0, lightSplits = 0;
};

// The splits that made `hierarchy` from the one its scene builds, in the order they were made:
// children are appended at a split, so the order of the elements' first children is the order of
// the splits.
std::vector<std::uint32_t> splitOrder(const ElementHierarchy& hierarchy);

// Replays cached.splits on a hierarchy just built from the scene and numbers its leaves. Checks
// every split before making it (a leaf element, in range) and the node and leaf counts after, and
// the links, warm start and open fractions against them; an Error (hierarchy then unusable)
// otherwise.
Status replaySplits(ElementHierarchy& hierarchy, const CachedRefinement& cached);

// Writes the file atomically (core/cache_file.h); the Error names the path. Returns the
// file's size in bytes.
Result<std::uint64_t> saveRefinement(const std::string& path, std::uint64_t key, const CachedRefinement& refinement);

// Reads and validates a file written by saveRefinement with the same key: magic, version, key,
// exact size, checksum, and every count and index inside it (rows increasing, sources among the
// nodes). Any problem is an Error "<path>: <what is wrong>". Nothing is allocated beyond the
// file's actual size.
Result<CachedRefinement> loadRefinement(const std::string& path, std::uint64_t key);

// The final gather's visibility values (hierarchical/final_gather.h: GatherVisibility) over the links
// of the same key, beside the links: <directory>/links-<16 hex digits>.lhv. They depend on the
// hierarchy, the links, the leaf mesh's vertices, the ray caster and the gather's own code and
// parameters, all of which the key fixes (the gather is among the digested sources); they do
// not depend on the lights or the radiosity, which choose only which of them a gather asks for.
std::string gatherVisibilityPath(const std::string& directory, std::uint64_t key);

// Writes the values atomically, as saveRefinement does; returns the file's size in bytes.
Result<std::uint64_t> saveGatherVisibility(const std::string& path, std::uint64_t key, const GatherVisibility& visibility);

// Reads and validates a file written by saveGatherVisibility with the same key: the header,
// exact size and checksum, and inside it: vertexCount vertices, entries grouped by vertex and
// strictly ordered by (link, source, penumbra) within each, links below numLinks, sources below
// numNodes, values finite and not negative. Any problem is an Error "<path>: <what is wrong>".
Result<GatherVisibility> loadGatherVisibility(const std::string& path, std::uint64_t key, std::uint64_t vertexCount,
                                              std::uint64_t numLinks, std::uint64_t numNodes);

// The final gather's irradiance at every vertex (FinalGather::irradiance's result) for one input,
// beside the links: <directory>/links-<16 hex digits>.lhg. The result is fixed by what the key
// fixes (the hierarchy, the links, the leaf mesh's vertices, the ray caster, the gather's code and
// parameters) and by two inputs the key does not hold: the node radiosity gathered (which the
// lights and the solve choose) and the visibility values read from the .lhv file. Their digest is
// stored with the values, and a gather whose digest differs (another radiosity: lights moved, a
// looser tolerance) computes its own; so a second run of the same solve reads its vertices'
// irradiance, where a gather over 10⁵ faces' links takes most of that run's time.
struct CachedGatherIrradiance {
  std::uint64_t inputDigest = 0;  // gatherInputDigest of the gather that made the values
  std::vector<Rgb> irradiance;    // per vertex of the leaf mesh, W/m² (0 at vertices without a leaf)
};

std::string gatherIrradiancePath(const std::string& directory, std::uint64_t key);

// XXH64 over the visibility values a gather reads (start, link, source and value arrays, as a
// saved and reloaded file holds them); a distinct value when there are none.
std::uint64_t gatherVisibilityDigest(const GatherVisibility* visibility);

// XXH64 over a gather's inputs beyond the key: every node's mean radiosity (exact bits) and the
// digest of the visibility values it reads, and any per-vertex arrays its result also depends on
// (the corners' coupling reads the vertices' direct light, emission and albedo).
std::uint64_t gatherInputDigest(const std::vector<Rgb>& nodeMeanRadiosity, std::uint64_t visibilityDigest,
                                std::initializer_list<const std::vector<Rgb>*> perVertex = {});

// Writes the values atomically, as saveRefinement does; returns the file's size in bytes.
Result<std::uint64_t> saveGatherIrradiance(const std::string& path, std::uint64_t key, const CachedGatherIrradiance& gathered);

// Reads and validates a file written by saveGatherIrradiance with the same key: the header, exact
// size and checksum, vertexCount vertices, finite values. Any problem is an Error
// "<path>: <what is wrong>". Whether the values are for the caller's input is the caller's check
// (inputDigest): a file for another input is an ordinary miss, not damage.
Result<CachedGatherIrradiance> loadGatherIrradiance(const std::string& path, std::uint64_t key, std::uint64_t vertexCount);

}  // namespace lambert
