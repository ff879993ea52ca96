#include "lambert/engine/final_gather.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"
#include "lambert/formfactor/kernels.h"

namespace lambert {
namespace {

// A source node whose bounding sphere is wider than this share of its distance from the vertex
// is gathered from its children instead.
constexpr double kOpeningRatio = 0.5;

}  // namespace

FinalGather::FinalGather(const ElementHierarchy& hierarchy, const ElementHierarchy::LeafMesh& leaves, const Links& links,
                         const RayCaster& caster, double rayEpsilon, double nudge, int visibilityRays, std::uint64_t seed)
    : hierarchy_(hierarchy),
      links_(links),
      caster_(caster),
      epsilon_(rayEpsilon),
      rays_(std::max(1, visibilityRays)),
      seed_(seed),
      sites_(vertexSites(leaves.mesh, nudge)) {
  const Mesh& mesh = leaves.mesh;
  LAMBERT_CHECK(mesh.numPatches() == hierarchy.leafNodes().size());
  leaf_.assign(mesh.numVertices(), kNoNode);
  for (std::uint32_t p = 0; p < mesh.numPatches(); ++p) {
    const Patch& patch = mesh.patches[p];
    for (std::uint32_t v : mesh.cornerIndices(p)) {
      const std::uint32_t current = leaf_[v];
      if (current == kNoNode) {
        leaf_[v] = p;
        continue;
      }
      const Patch& other = mesh.patches[current];
      if (patch.openFraction > other.openFraction || (patch.openFraction == other.openFraction && patch.area < other.area))
        leaf_[v] = p;
    }
  }
}

double FinalGather::visibility(std::uint32_t vertex, std::uint32_t link, const HierarchyNode& source,
                               std::uint32_t& raysCast) const {
  const VertexSite& site = sites_[vertex];
  Pcg32 rng(seed_, (static_cast<std::uint64_t>(vertex) << 32) ^ link);
  const std::uint32_t su = rng.nextUint(), sv = rng.nextUint();
  int open = 0, facing = 0;
  const Vec3 from = site.point + site.normal * epsilon_;
  for (int i = 0; i < rays_; ++i) {
    auto [u, v] = scrambledZeroTwo(static_cast<std::uint32_t>(i), su, sv);
    const Vec3 y = sampleConvexPolygon(source.polygon(), u, v);
    if (!(pointToPointKernel(site.point, site.normal, y, source.normal) > 0)) continue;
    ++facing;
    ++raysCast;
    const Vec3 to = y + source.normal * epsilon_;
    open += !caster_.occluded(Ray{from, to - from, 0, 1});
  }
  // No ray pair faces (a source seen edge-on from here): keep what the link measured.
  if (facing == 0) return links_.uncertainty[link] > 0 ? links_.formFactor[link] / links_.uncertainty[link] : 0.0;
  return static_cast<double>(open) / facing;
}

std::vector<Rgb> FinalGather::irradiance(const std::vector<Rgb>& mean, FinalGatherCounts* counts) const {
  LAMBERT_CHECK(mean.size() == hierarchy_.nodes().size());
  std::vector<Rgb> out(sites_.size());
  // Per vertex: sources gathered, sources opened, visibility rays.
  std::vector<std::array<std::uint32_t, 3>> work(counts ? sites_.size() : 0, {0, 0, 0});
  const std::vector<std::uint32_t>& leafNodes = hierarchy_.leafNodes();
  parallelFor(0, sites_.size(), [&](std::size_t v) {
    if (leaf_[v] == kNoNode) return;
    const VertexSite& site = sites_[v];
    std::vector<std::uint32_t> open;  // the link's source and its descendants still to gather
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
          const double distance = length(source.centre - site.point);
          // A source seen from close by, for its size, shows the vertex more than its mean: the
          // floor next to a block's base is in the block's shadow while the floor element the
          // link reached is lit further out. Its children's means, already pulled, say how it
          // varies (Barnes–Hut's opening criterion on the source's bounding sphere).
          if (!source.isLeaf() && source.radius > kOpeningRatio * distance) {
            if (counts) ++work[v][1];
            for (std::uint32_t child : hierarchy_.children(s)) open.push_back(child);
            continue;
          }
          if (counts) ++work[v][0];
          double factor = 0;
          if (!source.isCluster()) {
            factor = pointToPolygonFormFactor(site.point, site.normal, source.polygon(), source.normal);
          } else {
            const Vec3 w = (source.centre - site.point) / distance;
            factor = source.projectedArea(-w) * std::fmax(0.0, dot(site.normal, w)) / (kPi * distance * distance);
          }
          if (!(factor > 0)) continue;
          double seen = linkVisibility;
          if (!allVisible && !source.isCluster() && !clusterReceiver) {
            std::uint32_t raysCast = 0;
            seen = visibility(static_cast<std::uint32_t>(v), k, source, raysCast);
            if (counts) work[v][2] += raysCast;
          }
          sum += mean[s] * (factor * seen);
        }
      }
    }
    out[v] = sum;
  }, 64);
  if (counts) {
    *counts = {};
    for (std::size_t v = 0; v < work.size(); ++v) {
      if (leaf_[v] == kNoNode) continue;
      ++counts->vertices;
      counts->sourcesGathered += work[v][0];
      counts->sourcesOpened += work[v][1];
      counts->visibilityRays += work[v][2];
      counts->maxSourcesGathered = std::max<std::uint64_t>(counts->maxSourcesGathered, work[v][0]);
      counts->maxVisibilityRays = std::max<std::uint64_t>(counts->maxVisibilityRays, work[v][2]);
    }
  }
  return out;
}

}  // namespace lambert
