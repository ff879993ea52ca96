// Hierarchical link cache files (.lhl). The header, checksum and atomic write are
// core/cache_file.h's; all fields are little-endian.
//
//   offset  size      field
//   0       32        header: magic "LMBRTHL\0", u32 format version (2), u32 0, u64 key
//                     (linkCacheKey), u64 P: the payload's size in bytes
//   32      P         payload:
//                       64 bytes  u64 nodes N, splits S, links L, leaves V, initial links,
//                                 cluster links, elements split at light edges, 0
//                       4·S       u32 element split, in the order of the splits
//                       4·(N+1)   u32 row starts (Links::start): node r's links are [start[r], start[r+1])
//                       4·L       u32 source node (Links::source)
//                       4·L       float32 K (Links::formFactor)
//                       4·L       float32 ΔK (Links::uncertainty)
//                       L         u8 0 or 1 (Links::receiverSide)
//                       6·L       u8 × 6: the shares of each link's light by the way the receiving
//                                 cluster's faces face, in 255ths (Links::facing)
//                       0–7       zero bytes, to a multiple of 8
//                       24·V      float64 r, g, b of each leaf's warm start, leaves in node order
//                       8·V       float64 each leaf's open fraction, in [0, 1]
//   32+P    8         u64 checksum: XXH64 (seed 0) of every byte before it
//
// Each array is one contiguous block, copied to memory as it is: loading 8 × 10⁵ links is a read
// and a checksum at several GB/s, not a parse.
#include "lambert/hierarchical/link_cache.h"
#include "lambert/solve/solver.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numeric>

#include "lambert/method/options.h"
#include "lambert/method/solve_call.h"
#include "lambert/light/sky.h"
#include "lambert/core/cache_file.h"
#include "lambert/scene/scene_hash.h"
#include "lambert/link_sources_digest.h"
#include "lambert/version.h"

namespace lambert {
namespace {

using cachefile::KeyHasher;

constexpr cachefile::Format kFormat{{'L', 'M', 'B', 'R', 'T', 'H', 'L', '\0'}, 2, "hierarchical link cache file"};
constexpr std::size_t kPreambleBytes = 64;

static_assert(sizeof(Vec3) == 3 * sizeof(double) && sizeof(Rgb) == 3 * sizeof(double) && sizeof(Uv) == 2 * sizeof(double),
              "hashed and stored as their doubles");

// What irradiance() reads of a light (not its name, nor its angular velocity: the lights are
// taken as they are at the first solve).
void hashLight(KeyHasher& h, const Light& light) {
  h.i64(static_cast<std::int64_t>(light.kind));
  h.vec3(light.position);
  h.vec3(light.direction);
  hashRgb(h, light.intensity);
  hashRgb(h, light.irradiance);
  h.f64(light.coneAngleDegrees);
  h.f64(light.falloffDegrees);
  if (light.kind == LightKind::Sky && light.sky) {
    h.i64(light.sky->cieType());
    h.f64(light.sky->sunAzimuthDegrees());
    h.f64(light.sky->sunElevationDegrees());
    h.vec3(light.sky->north());
    h.f64(light.sky->zenithLuminance());
    hashRgb(h, light.sky->colour());
    h.i64(light.skyDirections);
    if (light.sky->isPerez()) {  // its shape is its coefficients (other skies' keys stay as they were)
      const PerezCoefficients& p = light.sky->perezCoefficients();
      for (double x : {p.a, p.b, p.c, p.d, p.e}) h.f64(x);
    }
  }
}

// Overflow-safe payload arithmetic: every count is checked against what the file can hold.
struct Layout {
  std::uint64_t splits = 0, starts = 0, links = 0, side = 0, facing = 0, padded = 0, warm = 0, open = 0, total = 0;
};

// Offsets of each block for the counts, or false when they would not fit in the address space.
bool layout(std::uint64_t nodes, std::uint64_t splits, std::uint64_t links, std::uint64_t leaves, Layout& out) {
  constexpr std::uint64_t kLimit = std::numeric_limits<std::uint32_t>::max();
  if (nodes == 0 || nodes >= kLimit || splits >= kLimit || links >= kLimit || leaves >= kLimit) return false;
  out.splits = kPreambleBytes;
  out.starts = out.splits + 4 * splits;
  out.links = out.starts + 4 * (nodes + 1);
  out.side = out.links + 12 * links;
  out.facing = out.side + links;
  out.padded = out.facing + 6 * links;
  out.warm = (out.padded + 7) / 8 * 8;
  out.open = out.warm + 24 * leaves;
  out.total = out.open + 8 * leaves;
  return out.total <= std::numeric_limits<std::size_t>::max() - cachefile::kHeaderBytes - cachefile::kChecksumBytes;
}

template <typename T>
void copyOut(std::vector<T>& to, const unsigned char* from, std::uint64_t count) {
  to.resize(static_cast<std::size_t>(count));
  if (count) std::memcpy(to.data(), from, static_cast<std::size_t>(count) * sizeof(T));
}

template <typename T>
unsigned char* copyIn(unsigned char* to, const std::vector<T>& from) {
  if (!from.empty()) std::memcpy(to, from.data(), from.size() * sizeof(T));
  return to + from.size() * sizeof(T);
}

// A cache file's whole payload, after its header and checksum are checked: refused when shorter
// than minimumBytes (what cannot hold `what`), and its length checked against the header's count
// before anything is allocated.
struct Payload {
  std::unique_ptr<unsigned char[]> data;
  std::uint64_t bytes = 0;
};
Result<Payload> readPayload(const std::string& path, const cachefile::Format& format, std::uint64_t key,
                            std::uint64_t minimumBytes, const std::string& what) {
  Result<cachefile::Reader> opened = cachefile::Reader::open(path, format, key);
  if (!opened) return opened.error();
  cachefile::Reader& reader = *opened;
  Payload payload;
  payload.bytes = reader.count();
  if (payload.bytes < minimumBytes ||
      payload.bytes > std::numeric_limits<std::size_t>::max() - cachefile::kHeaderBytes - cachefile::kChecksumBytes)
    return Error{path + ": a payload of " + std::to_string(payload.bytes) + " bytes cannot hold " + what};
  if (Status sized = reader.checkSize(static_cast<std::size_t>(payload.bytes), std::to_string(payload.bytes) + " payload bytes"); !sized)
    return sized.error();
  payload.data.reset(new unsigned char[static_cast<std::size_t>(payload.bytes)]);
  if (Status read = reader.readPayload(payload.data.get()); !read) return read.error();
  return payload;
}

}  // namespace

bool linkCacheUsable(const RadiosityOptions& options, const SolveBudget& firstBudget) {
  return !(options.hierarchical.refinePasses > 1 && firstBudget.maxMilliseconds > 0);
}

std::uint64_t linkCacheKey(const Scene& scene, const std::vector<Light>& lights, const RadiosityOptions& options,
                           const SolveBudget& firstBudget) {
  KeyHasher h;
  h.text("lambert hierarchical links");
  h.u32(kFormat.version);
  h.text(LAMBERT_VERSION_STRING);
  h.text(LAMBERT_LINK_SOURCES_DIGEST);
  hashScene(h, scene);
  h.u64(lights.size());
  for (const Light& light : lights) hashLight(h, light);
  const HierarchicalOptions& hierarchical = options.hierarchical;
  h.f64(hierarchical.links.linkError);
  h.f64(hierarchical.links.minElementArea);
  h.i64(hierarchical.links.visibilityRays);
  h.u32(hierarchical.links.clusters ? 1 : 0);
  h.u64(hierarchical.links.seed);
  h.i64(hierarchical.refinePasses);
  h.u32(hierarchical.refineAtLights ? 1 : 0);
  // The lights' first estimate, which the first pass refines from, is Ward's (many_lights.h).
  h.f64(options.directLight.shadowTolerance);
  // The solves between passes, which the later passes refine from; a single pass refines before
  // any solve and hands the solve no warm start.
  h.u32(hierarchical.refinePasses > 1 ? 1 : 0);
  if (hierarchical.refinePasses > 1) {
    h.text(solverName(options.solver));
    h.f64(options.tolerance);
    h.i64(options.maxIterations);
    h.i64(firstBudget.maxSweeps);
    h.i64(options.directLight.samplesPerPatch);
    h.u64(options.directLight.seed);
  }
  return h.digest();
}

std::string linkCachePath(const std::string& directory, std::uint64_t key) {
  return cachefile::keyedPath(directory, "links-", key, ".lhl");
}

std::vector<std::uint32_t> splitOrder(const ElementHierarchy& hierarchy) {
  std::vector<std::uint32_t> split;
  for (std::uint32_t i = 0; i < hierarchy.nodes().size(); ++i) {
    const HierarchyNode& n = hierarchy.node(i);
    if (!n.isCluster() && !n.isLeaf()) split.push_back(i);
  }
  std::sort(split.begin(), split.end(),
            [&](std::uint32_t a, std::uint32_t b) { return hierarchy.children(a)[0] < hierarchy.children(b)[0]; });
  return split;
}

Status replaySplits(ElementHierarchy& hierarchy, const CachedRefinement& cached) {
  for (std::uint32_t e : cached.splits) {
    if (e >= hierarchy.nodes().size() || hierarchy.node(e).isCluster() || !hierarchy.node(e).isLeaf())
      return Error{"split of node " + std::to_string(e) + " does not apply to this hierarchy (" +
                   std::to_string(hierarchy.nodes().size()) + " nodes)"};
    hierarchy.split(e);
  }
  hierarchy.numberLeaves();
  if (hierarchy.nodes().size() != cached.numNodes)
    return Error{"replaying the splits made " + std::to_string(hierarchy.nodes().size()) + " nodes, the file holds " +
                 std::to_string(cached.numNodes)};
  if (hierarchy.leafNodes().size() != cached.warmStart.size())
    return Error{"the hierarchy has " + std::to_string(hierarchy.leafNodes().size()) + " leaves, the file's warm start " +
                 std::to_string(cached.warmStart.size())};
  return Ok{};
}

Result<std::uint64_t> saveRefinement(const std::string& path, std::uint64_t key, const CachedRefinement& r) {
  LAMBERT_CHECK(r.links);
  const Links& links = *r.links;
  const std::uint64_t numLinks = links.size();
  LAMBERT_CHECK(links.start.size() == r.numNodes + 1 && links.formFactor.size() == numLinks &&
                links.uncertainty.size() == numLinks && links.receiverSide.size() == numLinks && links.facing.size() == numLinks &&
                r.openFraction.size() == r.warmStart.size());
  Layout at;
  if (!layout(r.numNodes, r.splits.size(), numLinks, r.warmStart.size(), at))
    return Error{path + ": " + std::to_string(numLinks) + " links over " + std::to_string(r.numNodes) + " nodes are too many to store"};
  std::unique_ptr<unsigned char[]> payload(new unsigned char[at.total]());
  unsigned char* p = payload.get();
  const std::uint64_t preamble[8] = {r.numNodes, r.splits.size(), numLinks, r.warmStart.size(), r.initialLinks, r.clusterLinks,
                                     r.lightSplits, 0};
  for (int k = 0; k < 8; ++k) cachefile::storeLe64(p + 8 * k, preamble[k]);
  copyIn(p + at.splits, r.splits);
  copyIn(p + at.starts, links.start);
  unsigned char* q = copyIn(p + at.links, links.source);
  q = copyIn(q, links.formFactor);
  copyIn(q, links.uncertainty);
  copyIn(p + at.side, links.receiverSide);
  copyIn(p + at.facing, links.facing);
  copyIn(p + at.warm, r.warmStart);
  copyIn(p + at.open, r.openFraction);
  if (Status written = cachefile::writeFile(path, kFormat, key, at.total, std::span<const unsigned char>(p, at.total)); !written)
    return written.error();
  return at.total + cachefile::kHeaderBytes + cachefile::kChecksumBytes;
}

Result<CachedRefinement> loadRefinement(const std::string& path, std::uint64_t key) {
  Result<Payload> payload = readPayload(path, kFormat, key, kPreambleBytes, "links");
  if (!payload) return payload.error();
  const std::uint64_t bytes = payload->bytes;
  const unsigned char* p = payload->data.get();
  std::uint64_t preamble[8];
  for (int k = 0; k < 8; ++k) preamble[k] = cachefile::loadLe64(p + 8 * k);
  CachedRefinement r;
  r.numNodes = preamble[0];
  const std::uint64_t numSplits = preamble[1], numLinks = preamble[2], numLeaves = preamble[3];
  r.initialLinks = preamble[4];
  r.clusterLinks = preamble[5];
  r.lightSplits = preamble[6];
  Layout at;
  if (!layout(r.numNodes, numSplits, numLinks, numLeaves, at) || at.total != bytes || preamble[7] != 0)
    return Error{path + ": its counts (" + std::to_string(r.numNodes) + " nodes, " + std::to_string(numSplits) + " splits, " +
                 std::to_string(numLinks) + " links, " + std::to_string(numLeaves) + " leaves) do not fill its " +
                 std::to_string(bytes) + " payload bytes"};
  auto loaded = std::make_shared<Links>();
  copyOut(r.splits, p + at.splits, numSplits);
  copyOut(loaded->start, p + at.starts, r.numNodes + 1);
  copyOut(loaded->source, p + at.links, numLinks);
  copyOut(loaded->formFactor, p + at.links + 4 * numLinks, numLinks);
  copyOut(loaded->uncertainty, p + at.links + 8 * numLinks, numLinks);
  copyOut(loaded->receiverSide, p + at.side, numLinks);
  copyOut(loaded->facing, p + at.facing, numLinks);
  copyOut(r.warmStart, p + at.warm, numLeaves);
  copyOut(r.openFraction, p + at.open, numLeaves);
  r.links = loaded;

  // The checksum says the bytes are the ones written; these say they make links a solve can use.
  const Links& links = *loaded;
  if (links.start.front() != 0 || links.start.back() != numLinks)
    return Error{path + ": its link rows do not span its " + std::to_string(numLinks) + " links"};
  for (std::uint64_t node = 0; node < r.numNodes; ++node) {
    const std::uint32_t begin = links.start[node], end = links.start[node + 1];
    if (end < begin) return Error{path + ": the links of node " + std::to_string(node) + " end before they start"};
    for (std::uint32_t k = begin; k < end; ++k)
      if (links.source[k] >= r.numNodes || (k > begin && links.source[k] <= links.source[k - 1]) ||
          !std::isfinite(links.formFactor[k]) || !std::isfinite(links.uncertainty[k]) || links.receiverSide[k] > 1 ||
          std::accumulate(links.facing[k].begin(), links.facing[k].end(), 0) > 255)
        return Error{path + ": link " + std::to_string(k) + " (to node " + std::to_string(node) + ") is not a valid link"};
  }
  for (const Rgb& b : r.warmStart)
    if (!std::isfinite(b.r) || !std::isfinite(b.g) || !std::isfinite(b.b)) return Error{path + ": its warm start is not finite"};
  for (double f : r.openFraction)
    if (!(f >= 0 && f <= 1)) return Error{path + ": an open fraction is not in [0, 1]"};
  return r;
}

// Gather visibility files (.lhv), on the same header and checksum:
//   payload   16 bytes  u64 vertices V, entries E
//             4·(V+1)   u32 entry starts per vertex (GatherVisibility::start)
//             4·E       u32 link
//             4·E       u32 source node, top bit: penumbra rays
//             0–7       zero bytes, to a multiple of 8
//             8·E       float64 visibility
namespace {

constexpr cachefile::Format kVisibilityFormat{{'L', 'M', 'B', 'R', 'T', 'H', 'V', '\0'}, 1, "final gather visibility file"};

struct VisibilityLayout {
  std::uint64_t starts = 0, links = 0, sources = 0, seen = 0, total = 0;
};

bool visibilityLayout(std::uint64_t vertices, std::uint64_t entries, VisibilityLayout& out) {
  constexpr std::uint64_t kLimit = std::numeric_limits<std::uint32_t>::max();
  if (vertices >= kLimit || entries >= kLimit) return false;
  out.starts = 16;
  out.links = out.starts + 4 * (vertices + 1);
  out.sources = out.links + 4 * entries;
  out.seen = (out.sources + 4 * entries + 7) / 8 * 8;
  out.total = out.seen + 8 * entries;
  return out.total <= std::numeric_limits<std::size_t>::max() - cachefile::kHeaderBytes - cachefile::kChecksumBytes;
}

}  // namespace

std::string gatherVisibilityPath(const std::string& directory, std::uint64_t key) {
  return cachefile::keyedPath(directory, "links-", key, ".lhv");
}

Result<std::uint64_t> saveGatherVisibility(const std::string& path, std::uint64_t key, const GatherVisibility& v) {
  const std::uint64_t entries = v.size();
  LAMBERT_CHECK(!v.start.empty() && v.start.back() == entries && v.link.size() == entries && v.source.size() == entries);
  VisibilityLayout at;
  if (!visibilityLayout(v.numVertices(), entries, at))
    return Error{path + ": " + std::to_string(entries) + " visibility values are too many to store"};
  std::unique_ptr<unsigned char[]> payload(new unsigned char[at.total]());
  unsigned char* p = payload.get();
  cachefile::storeLe64(p, v.numVertices());
  cachefile::storeLe64(p + 8, entries);
  copyIn(p + at.starts, v.start);
  copyIn(p + at.links, v.link);
  copyIn(p + at.sources, v.source);
  copyIn(p + at.seen, v.seen);
  if (Status written = cachefile::writeFile(path, kVisibilityFormat, key, at.total, std::span<const unsigned char>(p, at.total));
      !written)
    return written.error();
  return at.total + cachefile::kHeaderBytes + cachefile::kChecksumBytes;
}

Result<GatherVisibility> loadGatherVisibility(const std::string& path, std::uint64_t key, std::uint64_t vertexCount,
                                              std::uint64_t numLinks, std::uint64_t numNodes) {
  Result<Payload> payload = readPayload(path, kVisibilityFormat, key, 16, "visibility values");
  if (!payload) return payload.error();
  const std::uint64_t bytes = payload->bytes;
  const unsigned char* p = payload->data.get();
  const std::uint64_t vertices = cachefile::loadLe64(p), entries = cachefile::loadLe64(p + 8);
  VisibilityLayout at;
  if (!visibilityLayout(vertices, entries, at) || at.total != bytes)
    return Error{path + ": its counts (" + std::to_string(vertices) + " vertices, " + std::to_string(entries) +
                 " values) do not fill its " + std::to_string(bytes) + " payload bytes"};
  if (vertices != vertexCount)
    return Error{path + ": it holds " + std::to_string(vertices) + " vertices, the leaf mesh has " + std::to_string(vertexCount)};
  GatherVisibility v;
  copyOut(v.start, p + at.starts, vertices + 1);
  copyOut(v.link, p + at.links, entries);
  copyOut(v.source, p + at.sources, entries);
  copyOut(v.seen, p + at.seen, entries);
  if (v.start.front() != 0 || v.start.back() != entries)
    return Error{path + ": its vertices' entries do not span its " + std::to_string(entries) + " values"};
  for (std::uint64_t vertex = 0; vertex < vertices; ++vertex) {
    const std::uint32_t begin = v.start[vertex], end = v.start[vertex + 1];
    if (end < begin) return Error{path + ": the entries of vertex " + std::to_string(vertex) + " end before they start"};
    for (std::uint32_t e = begin; e < end; ++e) {
      const bool ordered = e == begin || v.link[e] > v.link[e - 1] || (v.link[e] == v.link[e - 1] && v.source[e] > v.source[e - 1]);
      if (!ordered || v.link[e] >= numLinks || (v.source[e] & ~GatherVisibility::kPenumbra) >= numNodes ||
          !(v.seen[e] >= 0 && std::isfinite(v.seen[e])))
        return Error{path + ": value " + std::to_string(e) + " (at vertex " + std::to_string(vertex) + ") is not a valid visibility"};
    }
  }
  return v;
}

// Gather irradiance files (.lhg), on the same header and checksum:
//   payload   16 bytes  u64 input digest (gatherInputDigest), u64 vertices V
//             24·V      float64 r, g, b of each vertex's gathered irradiance
namespace {

constexpr cachefile::Format kIrradianceFormat{{'L', 'M', 'B', 'R', 'T', 'H', 'G', '\0'}, 1, "final gather irradiance file"};
constexpr std::uint64_t kIrradiancePreambleBytes = 16;

}  // namespace

std::string gatherIrradiancePath(const std::string& directory, std::uint64_t key) {
  return cachefile::keyedPath(directory, "links-", key, ".lhg");
}

std::uint64_t gatherVisibilityDigest(const GatherVisibility* visibility) {
  KeyHasher h;
  h.text("lambert gather visibility");
  h.u32(visibility ? 1 : 0);
  if (visibility) {
    h.array(visibility->start);
    h.array(visibility->link);
    h.array(visibility->source);
    h.array(visibility->seen);
  }
  return h.digest();
}

std::uint64_t gatherInputDigest(const std::vector<Rgb>& nodeMeanRadiosity, std::uint64_t visibilityDigest,
                                std::initializer_list<const std::vector<Rgb>*> perVertex) {
  KeyHasher h;
  h.text("lambert gather input");
  h.array(nodeMeanRadiosity);
  h.u64(visibilityDigest);
  for (const std::vector<Rgb>* values : perVertex) h.array(*values);
  return h.digest();
}

Result<std::uint64_t> saveGatherIrradiance(const std::string& path, std::uint64_t key, const CachedGatherIrradiance& gathered) {
  const std::uint64_t vertices = gathered.irradiance.size();
  if (vertices >= std::numeric_limits<std::uint32_t>::max())
    return Error{path + ": " + std::to_string(vertices) + " vertices are too many to store"};
  const std::uint64_t total = kIrradiancePreambleBytes + sizeof(Rgb) * vertices;
  std::unique_ptr<unsigned char[]> payload(new unsigned char[total]());
  unsigned char* p = payload.get();
  cachefile::storeLe64(p, gathered.inputDigest);
  cachefile::storeLe64(p + 8, vertices);
  copyIn(p + kIrradiancePreambleBytes, gathered.irradiance);
  if (Status written = cachefile::writeFile(path, kIrradianceFormat, key, total, std::span<const unsigned char>(p, total)); !written)
    return written.error();
  return total + cachefile::kHeaderBytes + cachefile::kChecksumBytes;
}

Result<CachedGatherIrradiance> loadGatherIrradiance(const std::string& path, std::uint64_t key, std::uint64_t vertexCount) {
  Result<Payload> payload = readPayload(path, kIrradianceFormat, key, kIrradiancePreambleBytes, "gathered irradiance");
  if (!payload) return payload.error();
  const unsigned char* p = payload->data.get();
  CachedGatherIrradiance g;
  g.inputDigest = cachefile::loadLe64(p);
  const std::uint64_t vertices = cachefile::loadLe64(p + 8);
  if (vertices >= std::numeric_limits<std::uint32_t>::max() || kIrradiancePreambleBytes + sizeof(Rgb) * vertices != payload->bytes)
    return Error{path + ": its count (" + std::to_string(vertices) + " vertices) does not fill its " + std::to_string(payload->bytes) +
                 " payload bytes"};
  if (vertices != vertexCount)
    return Error{path + ": it holds " + std::to_string(vertices) + " vertices, the leaf mesh has " + std::to_string(vertexCount)};
  copyOut(g.irradiance, p + kIrradiancePreambleBytes, vertices);
  for (const Rgb& e : g.irradiance)
    if (!std::isfinite(e.r) || !std::isfinite(e.g) || !std::isfinite(e.b)) return Error{path + ": a vertex's irradiance is not finite"};
  return g;
}

}  // namespace lambert
