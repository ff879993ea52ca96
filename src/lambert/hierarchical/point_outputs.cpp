// The final gather's outputs at points on the surfaces (hierarchical/method.h): each point's
// leaf found down its face's elements, and the light from the surfaces (and weights) gathered
// there; the engine adds the lights' direct light (SolutionView::pointIrradiance). Its own file: one of the method's two outputs (vertex_outputs.cpp gathers
// at the vertices); gatherAt serves both.
#include "lambert/hierarchical/method.h"

#include <cmath>
#include <string>
#include <unordered_map>

#include "lambert/core/parallel.h"
#include "lambert/method/point_gather.h"

namespace lambert {

static_assert(PointGather::kNoLeaf == kNoNode, "a point gather's missing leaf is the hierarchy's missing node");

namespace {

// How far inside a convex polygon p lies, projected on its plane: the least signed distance to
// its edges (negative outside).
double insideness(const HierarchyNode& node, const Vec3& p) {
  const std::span<const Vec3> corners = node.polygon();
  double least = INFINITY;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const Vec3 edge = corners[(k + 1) % corners.size()] - corners[k];
    const Vec3 inward = cross(node.normal, edge);
    const double size = length(inward);
    if (size > 0) least = std::fmin(least, dot(p - corners[k], inward) / size);
  }
  return least;
}

}  // namespace

Result<PointGather> HierarchicalMethod::pointGather(const ElementSolution& solution, std::span<const SurfacePoint> points,
                                                     PointGatherRequest part) const {
  if (Status spread = ranks_.canGather(part); !spread) return spread.error();
  if (part != PointGatherRequest::Sites) ranks_.askForPoints(part, points);
  // Each face's root elements (one, or its triangle fan's), then down to the leaf that holds the
  // point (the child it lies deepest inside: points on an edge go either way alike).
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> roots;
  const auto faceKey = [](std::uint32_t surface, std::uint32_t face) { return (static_cast<std::uint64_t>(surface) << 32) | face; };
  for (std::uint32_t i = 0; i < hierarchy_.nodes().size(); ++i) {
    const HierarchyNode& n = hierarchy_.node(i);
    if (!n.isCluster() && n.parent != kNoNode && hierarchy_.node(n.parent).isCluster()) roots[faceKey(n.surface, n.face)].push_back(i);
  }
  PointGather out;
  out.rayEpsilon = epsilon_;
  out.sites.resize(points.size());
  std::vector<std::uint32_t> leafOfSite(points.size(), kNoNode);
  const double nudge = 1e-4 * sceneDiagonal(scene_);
  for (std::size_t i = 0; i < points.size(); ++i)
    if (roots.find(faceKey(points[i].surface, points[i].face)) == roots.end())
      return Error{"surface " + std::to_string(points[i].surface) + " face " + std::to_string(points[i].face) +
                   ": no such face in the solved scene (a point asked for on it)"};
  parallelFor(0, points.size(), [&](std::size_t i) {
    const SurfacePoint& q = points[i];
    const std::vector<std::uint32_t>& candidates = roots.at(faceKey(q.surface, q.face));
    std::uint32_t node = candidates.front();
    double best = insideness(hierarchy_.node(node), q.point);
    for (std::uint32_t r : candidates)
      if (const double d = insideness(hierarchy_.node(r), q.point); d > best) best = d, node = r;
    while (!hierarchy_.node(node).isLeaf()) {
      std::uint32_t next = kNoNode;
      best = -INFINITY;
      for (std::uint32_t c : hierarchy_.children(node))
        if (const double d = insideness(hierarchy_.node(c), q.point); d > best) best = d, next = c;
      node = next;
    }
    const HierarchyNode& leaf = hierarchy_.node(node);
    // Off the leaf's edges by the vertices' nudge, toward its centre, on its plane.
    const Vec3 onPlane = q.point - leaf.normal * dot(q.point - leaf.centre, leaf.normal);
    const Vec3 inward = leaf.centre - onPlane;
    const double distance = length(inward);
    out.sites[i].point = distance > nudge ? onPlane + inward * (nudge / distance) : leaf.centre;
    out.sites[i].normal = leaf.normal;
    leafOfSite[i] = leaf.leaf;
  }, 256);
  out.leaf = std::move(leafOfSite);
  if (part != PointGatherRequest::Sites) gatherAt(solution, part, true, out);
  return out;
}

void HierarchicalMethod::gatherAt(const ElementSolution& solution, PointGatherRequest part, bool atPoints, PointGather& out) const {
  const FinalGather gather(hierarchy_, leaves_, *links_, *caster_, epsilon_, out.sites, out.leaf, options_.links.visibilityRays,
                           options_.links.seed, atPoints);
  std::vector<Rgb> mean;
  transport_->pull(solution.radiosity, mean);
  if (ranks_.acrossRanks()) {
    out.fromSurfaces = ranks_.gatherAtSites(gather, mean, [&] { return vertexRadiosity(solution); });
    return;
  }
  const bool withWeights = part == PointGatherRequest::LightAndWeights || part == PointGatherRequest::Weights;
  const std::vector<Rgb> gathered = gather.irradiance(mean, nullptr, nullptr, nullptr, &out.near, withWeights ? &out.nodes : nullptr);
  if (part == PointGatherRequest::Weights) return;
  out.fromSurfaces = FinalGather::withCorners(gathered, out.near, vertexRadiosity(solution));
  if (!withWeights) out.near = {};
}

}  // namespace lambert
