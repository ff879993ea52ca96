// The final gather's outputs at the vertices of the leaf mesh (hierarchical/method.h): the
// solution's vertex values, each vertex gathered (hierarchical/final_gather.h) and T-junctions
// constrained to their edges, the gather at chosen vertices, and the interpolated values. Its own
// file: one of the method's two outputs (point_outputs.cpp gathers at points).
#include "lambert/hierarchical/method.h"

#include <memory>
#include <mutex>

#include "lambert/core/parallel.h"
#include "lambert/core/warning.h"
#include "lambert/method/point_gather.h"
#include "lambert/geometry/coverage.h"
#include "lambert/light/many_lights.h"

namespace lambert {

std::vector<Rgb> HierarchicalMethod::vertexValues(const std::vector<Rgb>& perElement) const {
  std::shared_ptr<const VertexInterpolation> interpolation;
  {
    const std::lock_guard<std::mutex> lock(interpolationMutex_);
    if (!interpolation_ || interpolationGeneration_ != leafMeshGeneration_) {
      interpolation_ = std::make_shared<const VertexInterpolation>(leaves_.mesh);
      interpolationGeneration_ = leafMeshGeneration_;
    }
    interpolation = interpolation_;
  }
  std::vector<Rgb> values = interpolation->apply(perElement);
  constrainHangingVertices(leaves_, values);
  return values;
}

namespace {

// A gather at some vertices alone also gathers their close sources' corners, those corners'
// close corners and so on, this many rings out; the corners beyond take the elements'
// interpolated radiosity. Against a gather at every vertex, at the vertices a 256² picture shows
// (RenderPark's scenes): one ring left vertices 29% off on office1/graz.mgf (stacked binder
// rings, whose close sources chain), two 3.5%, three 0.03% (hospital, office2, soda, classroom
// and the Cornell box 0.08% or less, RMS 0.003% or less).
constexpr int kCornerRings = 3;

// Per vertex, whether vertexSolution gathers it: the vertices asked for and, since a T-junction
// shows the mean of its edge's ends, those ends (an end that hangs itself comes earlier in
// `hanging`: walked backward, its own ends are added after it).
std::vector<std::uint8_t> gatheredVertices(std::span<const std::uint8_t> needed, const std::vector<HangingVertex>& hanging) {
  std::vector<std::uint8_t> wanted(needed.begin(), needed.end());
  for (auto h = hanging.rbegin(); h != hanging.rend(); ++h)
    if (wanted[h->vertex]) wanted[h->edgeStart] = wanted[h->edgeEnd] = 1;
  return wanted;
}

// Per vertex, kNoNode where the vertex is not gathered, else the leaf it gathers through.
std::vector<std::uint32_t> gatheredThrough(std::vector<std::uint32_t> leaf, const std::vector<std::uint8_t>& gathered) {
  for (std::size_t v = 0; v < leaf.size(); ++v)
    if (!gathered[v]) leaf[v] = kNoNode;
  return leaf;
}

// The near-field rows of two gathers at disjoint sets of vertices, as one gather's.
NearFieldWeights mergeRows(const NearFieldWeights& a, const NearFieldWeights& b) {
  NearFieldWeights out;
  const std::size_t n = a.meanPart.size();
  out.start.reserve(n + 1);
  out.start.push_back(0);
  for (std::size_t v = 0; v < n; ++v) {
    const NearFieldWeights& from = a.start[v + 1] > a.start[v] ? a : b;
    out.corner.insert(out.corner.end(), from.corner.begin() + from.start[v], from.corner.begin() + from.start[v + 1]);
    out.weight.insert(out.weight.end(), from.weight.begin() + from.start[v], from.weight.begin() + from.start[v + 1]);
    out.start.push_back(static_cast<std::uint32_t>(out.weight.size()));
  }
  out.meanPart = a.meanPart;
  for (std::size_t v = 0; v < n; ++v) out.meanPart[v] += b.meanPart[v];
  return out;
}

}  // namespace

std::vector<std::vector<Rgb>> HierarchicalMethod::vertexSolution(const ElementSolution& solution,
                                                                   std::span<const VertexQuantity> quantities,
                                                                   std::span<const std::uint8_t> neededVertices) const {
  LAMBERT_CHECK(solution.radiosity.size() == leaves_.mesh.numPatches());
  Timer gatherTimer;
  const FinalGather whole(hierarchy_, leaves_, *links_, *caster_, epsilon_, 1e-4 * sceneDiagonal(scene_),
                          options_.links.visibilityRays, options_.links.seed);
  // Some vertices alone: the others are not gathered (kNoNode). The close sources' corners
  // among them are gathered too, kCornerRings rings out, so that the near field around the
  // vertices asked for is coupled as in a gather at every vertex; the last ring's close corners
  // enter the coupling as known radiosities, the elements' interpolated (an emission with ρ = 0
  // is a row that holds its value) rather than black.
  const bool some = !neededVertices.empty() && !ranks_.acrossRanks();
  const std::vector<std::uint8_t> wanted = some ? gatheredVertices(neededVertices, leaves_.hanging) : std::vector<std::uint8_t>{};
  const FinalGather gather = some ? whole.throughLeaves(gatheredThrough(whole.gatheringLeaf(), wanted)) : whole;
  std::vector<Rgb> mean;
  transport_->pull(solution.radiosity, mean);
  FinalGatherCounts counts;
  const std::vector<VertexSite>& sites = gather.sites();
  const std::vector<std::uint32_t>& allLeaves = whole.gatheringLeaf();
  const std::vector<std::uint32_t>& leaf = gather.gatheringLeaf();
  // The lights' direct irradiance at the vertices: every quantity needs it, through the close
  // sources' corner radiosities if not directly.
  // A sky's apart: IndirectRadiosity keeps it (hybrid images draw every other light per pixel).
  std::vector<Light> skies, pixelLights;
  for (const Light& light : solution.lights) (light.kind == LightKind::Sky ? skies : pixelLights).push_back(light);
  std::vector<Rgb> direct(sites.size()), skyDirect(sites.size()), emitted(sites.size()), albedo(sites.size());
  const DirectLighting pixelLighting(pixelLights, solution.metresPerUnit, shadowTolerance_),
      skyLighting(skies, solution.metresPerUnit, shadowTolerance_);
  const auto lightAtVertices = [&](const std::vector<std::uint32_t>& through) {
    parallelFor(0, direct.size(), [&](std::size_t v) {
      if (through[v] == kNoNode) return;
      emitted[v] = solution.emitted[through[v]];
      albedo[v] = solution.albedo[through[v]];
      skyDirect[v] = skies.empty() ? Rgb{} : skyLighting.irradiance(sites[v].point, sites[v].normal, *caster_, epsilon_);
      direct[v] = skyDirect[v] + (pixelLights.empty() ? Rgb{} : pixelLighting.irradiance(sites[v].point, sites[v].normal, *caster_, epsilon_));
    }, 64);
  };
  if (some) emitted = vertexValues(solution.radiosity);
  lightAtVertices(leaf);
  NearFieldWeights near;
  NearFieldCoupling coupling;
  // The last gather's result where its input is this one's (nothing gathered, as a result read
  // from the irradiance file counts; the coupling it showed). A distributed gather always runs:
  // every rank takes part in its exchanges.
  const std::uint64_t inputDigest = ranks_.acrossRanks() ? 0 : gatherInputDigest(mean, 0, {&direct, &emitted, &albedo});
  std::shared_ptr<const std::vector<Rgb>> result;
  if (!ranks_.acrossRanks()) {
    const std::lock_guard<std::mutex> lock(gatherMutex_);
    const LastVertexGather& last = lastVertexGather_;
    if (last.gathered && last.inputDigest == inputDigest && last.links == links_.get() && last.leafMeshGeneration == leafMeshGeneration_ &&
        last.wanted == wanted) {
      result = last.gathered;
      coupling = nearFieldCoupling_;
      ++gatherReuses_;
    }
  }
  const bool gatheredBefore = result != nullptr;
  if (gatheredBefore) {
    for (std::size_t v = 0; v < allLeaves.size(); ++v) counts.vertices += allLeaves[v] != kNoNode && (!some || wanted[v]);
  } else if (ranks_.acrossRanks()) {
    result = std::make_shared<const std::vector<Rgb>>(ranks_.gatherAtVertices(gather, mean, direct, emitted, albedo, counts, near, &coupling));
  } else if (!some) {
    result = std::make_shared<const std::vector<Rgb>>(gatherAtVertices(gather, mean, direct, emitted, albedo, counts, near, coupling));
  } else {
    std::vector<Rgb> gathered = gather.irradiance(mean, &counts, nullptr, nullptr, &near);
    std::vector<std::uint8_t> done = wanted, last = wanted;
    for (int r = 0; r < kCornerRings; ++r) {
      std::vector<std::uint8_t> ring(wanted.size(), 0);
      std::size_t added = 0;
      for (std::size_t v = 0; v < wanted.size(); ++v) {
        if (!last[v]) continue;
        for (std::uint32_t k = near.start[v]; k < near.start[v + 1]; ++k) {
          const std::uint32_t u = near.corner[k];
          if (!done[u] && allLeaves[u] != kNoNode && !ring[u]) ring[u] = 1, ++added;
        }
      }
      if (added == 0) break;
      const FinalGather ringGather = whole.throughLeaves(gatheredThrough(allLeaves, ring));
      lightAtVertices(ringGather.gatheringLeaf());
      FinalGatherCounts ringCounts;
      NearFieldWeights ringNear;
      const std::vector<Rgb> ringGathered = ringGather.irradiance(mean, &ringCounts, nullptr, nullptr, &ringNear);
      counts.add(ringCounts);
      for (std::size_t v = 0; v < ring.size(); ++v)
        if (ring[v]) gathered[v] = ringGathered[v], done[v] = 1;
      near = mergeRows(near, ringNear);
      last = std::move(ring);
    }
    result = std::make_shared<const std::vector<Rgb>>(FinalGather::coupleNearField(gathered, near, emitted, albedo, direct, &coupling));
  }
  const std::vector<Rgb>& gathered = *result;
  if (!coupling.converged)
    warning("the final gather's close sources did not converge in " + std::to_string(coupling.iterations) +
            " steps: their leaves' means are shown instead of their corners' values");
  // A T-junction's value is interpolated along the edge it lies on (as constrainHangingVertices
  // does), so that both sides of the edge show the same values, except where an end of that edge
  // is covered (under a block standing on the floor): what is gathered there is not light the
  // open side shows, and a Cornell-box floor vertex beside a block's foot, interpolated toward a
  // covered end, showed half its light (0.109 against the path tracer's 0.233; 0.232 gathered at
  // the vertex itself). Such a vertex keeps what it gathered.
  std::vector<char> coveredEnd(gathered.size(), 0);
  for (const HangingVertex& h : leaves_.hanging) coveredEnd[h.edgeStart] = coveredEnd[h.edgeEnd] = 1;
  parallelFor(0, coveredEnd.size(), [&](std::size_t v) {
    if (coveredEnd[v]) coveredEnd[v] = leaf[v] != kNoNode && isCovered(*caster_, sites[v].point, sites[v].normal, epsilon_);
  }, 256);
  std::vector<std::vector<Rgb>> out;
  for (VertexQuantity quantity : quantities) {
    std::vector<Rgb> values(gathered.size());
    for (std::size_t v = 0; v < values.size(); ++v) {
      if (leaf[v] == kNoNode) continue;
      const Rgb received = quantity == VertexQuantity::IndirectRadiosity ? gathered[v] + skyDirect[v] : gathered[v] + direct[v];
      values[v] = quantity == VertexQuantity::Irradiance ? received : emitted[v] + albedo[v] * received;
    }
    // Made on a coarser edge first (a smaller vertex index), so an end that hangs itself is final.
    for (const HangingVertex& h : leaves_.hanging)
      if (!coveredEnd[h.edgeStart] && !coveredEnd[h.edgeEnd]) values[h.vertex] = (values[h.edgeStart] + values[h.edgeEnd]) * 0.5;
    out.push_back(std::move(values));
  }
  const std::lock_guard<std::mutex> lock(gatherMutex_);
  gatherCounts_ = counts;
  if (!gatheredBefore) nearFieldWeights_ = near.size();
  nearFieldCoupling_ = coupling;
  gatherSeconds_ = gatherTimer.seconds();
  // A gather at some vertices does not take the place of one at every vertex (a picture drawn
  // between two exports of the same solution).
  const bool keepWhole = some && lastVertexGather_.gathered && lastVertexGather_.wanted.empty();
  if (!ranks_.acrossRanks() && !keepWhole) lastVertexGather_ = {inputDigest, links_.get(), leafMeshGeneration_, wanted, result};
  return out;
}

std::vector<Rgb> HierarchicalMethod::gatherAtVertices(const FinalGather& gather, const std::vector<Rgb>& mean,
                                                      const std::vector<Rgb>& direct, const std::vector<Rgb>& emitted,
                                                      const std::vector<Rgb>& albedo, FinalGatherCounts& counts,
                                                      NearFieldWeights& near, NearFieldCoupling& coupling) const {
  // The visibility and irradiance files (link_cache.h) hold values over the links their key
  // made: the last pass's.
  const bool cached = !linkCache_.path.empty() && passesDone_ == options_.refinePasses;
  const GatherCacheFiles::Use cache =
      cached ? gatherCache_.open(linkCache_, leaves_.mesh.numVertices(), links_->size(), hierarchy_.nodes().size()) : GatherCacheFiles::Use{};
  Timer digestTimer;
  // The gather's result with its corners coupled (FinalGather::coupleNearField), which also
  // reads the vertices' direct light, emission and albedo.
  const std::uint64_t inputDigest = cached ? gatherInputDigest(mean, cache.knownDigest, {&direct, &emitted, &albedo}) : 0;
  const double irradianceSeconds = digestTimer.seconds();
  if (cache.stored && cache.stored->inputDigest == inputDigest) {
    // The same input as the gather that wrote the file: its result, bit for bit.
    for (std::uint32_t l : gather.gatheringLeaf()) counts.vertices += l != kNoNode;
    gatherCache_.readIrradiance(irradianceSeconds);
    return cache.stored->irradiance;
  }
  GatherVisibility recorded;
  std::vector<Rgb> gathered = FinalGather::coupleNearField(
      gather.irradiance(mean, &counts, cache.known.get(), cache.recordPath.empty() ? nullptr : &recorded, &near), near, emitted,
      albedo, direct, &coupling);
  if (!cache.recordPath.empty()) gatherCache_.saveVisibility(linkCache_, cache.recordPath, recorded);
  if (!cache.irradiancePath.empty()) {
    // Under the visibility values the next process reads: those just recorded, when the file
    // held none.
    CachedGatherIrradiance made;
    made.inputDigest = cache.recordPath.empty() ? inputDigest
                                                : gatherInputDigest(mean, gatherVisibilityDigest(&recorded), {&direct, &emitted, &albedo});
    made.irradiance = gathered;
    gatherCache_.saveIrradiance(linkCache_, cache.irradiancePath, made, irradianceSeconds);
  } else if (cached) {
    gatherCache_.addIrradianceSeconds(irradianceSeconds);
  }
  return gathered;
}

std::vector<Rgb> HierarchicalMethod::vertexRadiosity(const ElementSolution& solution) const {
  const VertexQuantity radiosity = VertexQuantity::Radiosity;
  return vertexSolution(solution, std::span<const VertexQuantity>(&radiosity, 1)).front();
}

Result<PointGather> HierarchicalMethod::vertexGather(const ElementSolution& solution, std::span<const std::uint32_t> vertices,
                                                      PointGatherRequest part) const {
  if (Status spread = ranks_.canGather(part == PointGatherRequest::Light ? PointGatherRequest::Weights : part); !spread) return spread.error();
  const std::vector<VertexSite> sites = vertexSites(leaves_.mesh, 1e-4 * sceneDiagonal(scene_));
  const std::vector<std::uint32_t> leaf = FinalGather::gatheringLeaves(leaves_.mesh);
  PointGather out;
  out.rayEpsilon = epsilon_;
  for (std::uint32_t v : vertices) {
    if (v >= sites.size()) return Error{"vertex " + std::to_string(v) + ": no such vertex in the solution's vertex mesh"};
    out.sites.push_back(sites[v]);
    out.leaf.push_back(leaf[v]);
  }
  if (part != PointGatherRequest::Sites) gatherAt(solution, part, false, out);
  return out;
}

Result<std::vector<Rgb>> HierarchicalMethod::nodeMeanRadiosity(const ElementSolution& solution) const {
  std::vector<Rgb> mean;
  transport_->pull(solution.radiosity, mean);
  return mean;
}

}  // namespace lambert
