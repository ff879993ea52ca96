// The final gather's visibility (hierarchical/final_gather.h): the share of rays from a site to a
// source that get through, and the values an earlier gather recorded. Its own file: the gather's
// one use of the ray caster, beside the traversal (final_gather.cpp) that asks it.
#include "lambert/hierarchical/final_gather.h"

#include <algorithm>
#include <bit>

#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"
#include "lambert/formfactor/kernels.h"

namespace lambert {
namespace {

// Rays from a vertex to a source, as a multiple of the link's, where the first ones disagree.
constexpr int kPenumbraRays = 4;

}  // namespace

const double* GatherVisibility::find(std::uint32_t vertex, std::uint32_t k, std::uint32_t flaggedSource) const {
  if (vertex + 1 >= start.size()) return nullptr;
  const auto first = link.begin() + start[vertex], last = link.begin() + start[vertex + 1];
  // Entries are few per vertex (a few links' rays disagree): a linear scan.
  for (auto it = first; it != last; ++it) {
    const std::size_t e = static_cast<std::size_t>(it - link.begin());
    if (*it == k && source[e] == flaggedSource) return &seen[e];
  }
  return nullptr;
}

namespace {

// A point's bits mixed into one key.
std::uint64_t placeKey(const Vec3& p) {
  return mixBits(std::bit_cast<std::uint64_t>(p.x) ^ mixBits(std::bit_cast<std::uint64_t>(p.y) ^ mixBits(std::bit_cast<std::uint64_t>(p.z)))) << 1;
}

}  // namespace

double FinalGather::visibility(std::uint32_t vertex, std::uint32_t link, std::uint32_t s, std::uint32_t& raysCast,
                               bool penumbraRays) const {
  const VertexSite& site = sites_[vertex];
  // Seeded by the nodes, not the link's index: a distributed solve's ranks each hold their own
  // links, numbered apart, and must draw the rays one process draws. A vertex's stream is its
  // index; a point's is its place, so that its light does not depend on which other points were
  // gathered with it (a lightmap's adaptive passes ask for texels in batches that differ from
  // one bake to the next, bake/adaptive_texels.h).
  const std::uint64_t where = resolveClusterVisibility_ ? placeKey(site.point) : static_cast<std::uint64_t>(vertex) << 32;
  Pcg32 rng(seed_ ^ (links_.source[link] * 0x9e3779b97f4a7c15ull), where ^ s);
  const std::uint32_t su = rng.nextUint(), sv = rng.nextUint();
  // Each ray counts with the point-to-point kernel at its end: the visibility the factor needs is
  // ∫ k V dA / ∫ k dA over the source, not the share of its area in view. Counted by area, a
  // vertex that sees only the near strip of a source (a floor corner beside a block, the lamp
  // through a gap) is given that strip's share of the whole factor, far below the strip's own.
  // With penumbraRays, where the first rays disagree, kPenumbraRays times as many in all,
  // continuing the same (0,2)-sequence so that they stay stratified.
  // A cluster (a far one, seen from a point: final_gather.cpp) takes half the rays first, and the
  // other half only where those disagree: most points see a far cluster's faces all or none, and
  // its rays were 70% of the 10⁵-face building's lightmap bake.
  const bool cluster = hierarchy_.node(s).isCluster();
  const int first = cluster && !penumbraRays ? std::max(1, rays_ / 2) : rays_;
  double open = 0, facing = 0;
  const Vec3 from = site.point + site.normal * epsilon_;
  for (int i = 0; i < (penumbraRays ? kPenumbraRays : 1) * rays_; ++i) {
    if (i == first && !(open > 0 && open < facing)) break;
    auto [u, v] = scrambledZeroTwo(static_cast<std::uint32_t>(i), su, sv);
    // On a cluster, a point of the faces inside it: down through the children in proportion to
    // their areas, u picking the child and rescaled within it, to an element.
    std::uint32_t on = s;
    while (hierarchy_.node(on).isCluster()) {
      const std::span<const std::uint32_t> children = hierarchy_.children(on);
      if (children.empty()) break;
      double total = 0;
      for (std::uint32_t c : children) total += hierarchy_.node(c).area;
      double pick = u * total;
      std::uint32_t next = children.back();
      for (std::uint32_t c : children) {
        const double area = hierarchy_.node(c).area;
        if (pick < area) {
          next = c;
          u = std::clamp(pick / area, 0.0, 1.0 - 1e-12);
          break;
        }
        pick -= area;
      }
      on = next;
    }
    const HierarchyNode& element = hierarchy_.node(on);
    if (element.isCluster()) continue;
    const Vec3 y = sampleConvexPolygon(element.polygon(), u, v);
    const double kernel = pointToPointKernel(site.point, site.normal, y, element.normal);
    if (!(kernel > 0)) continue;
    facing += kernel;
    ++raysCast;
    const Vec3 to = y + element.normal * epsilon_;
    if (!caster_.occluded(Ray{from, to - from, 0, 1})) open += kernel;
  }
  // No ray pair faces (a source seen edge-on from here): keep what the link measured.
  if (!(facing > 0)) return links_.uncertainty[link] > 0 ? links_.formFactor[link] / links_.uncertainty[link] : 0.0;
  return open / facing;
}
}  // namespace lambert
