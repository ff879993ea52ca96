#include "lambert/hierarchical/method.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "lambert/core/parallel.h"
#include "lambert/core/memory.h"
#include "lambert/core/timer.h"
#include "lambert/geometry/coverage.h"
#include "lambert/geometry/enclosures.h"
#include "lambert/hierarchical/light_edges.h"
#include "lambert/light/emission.h"
#include "lambert/light/many_lights.h"

namespace lambert {
namespace {

std::vector<double> largestChannel(const std::vector<Rgb>& values) {
  std::vector<double> out(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) out[i] = std::fmax(0.0, values[i].maxComponent());
  return out;
}

}  // namespace

std::vector<double> HierarchicalMethod::openFractions(const Mesh& mesh) {
  std::vector<double> out(mesh.numPatches());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = mesh.patches[i].openFraction;
  return out;
}

void HierarchicalMethod::useFaces() {
  Timer leafTimer;
  leaves_ = hierarchy_.leaves(scene_);
  leafMeshNodes_ = hierarchy_.nodes().size();
  leafSeconds_ += leafTimer.seconds();
  Timer bvh;
  caster_ = makeEmbreeRayCaster(leaves_.mesh);
  casterFace_.clear();
  casterFace_.reserve(leaves_.mesh.numPatches());
  for (const Patch& p : leaves_.mesh.patches) casterFace_.push_back(static_cast<std::uint64_t>(p.surface) << 32 | p.face);
  epsilon_ = rayEpsilon(leaves_.mesh);
  bvhSeconds_ += bvh.seconds();
}

HierarchicalMethod::HierarchicalMethod(const Scene& scene, const RadiosityOptions& options)
    : scene_(scene),
      options_(options.hierarchical),
      shadowTolerance_(options.directLight.shadowTolerance),
      memoryLimitBytes_(options.memoryLimitBytes),
      ranks_(options.communicator),
      hierarchy_(scene) {
  buildSeconds_ = created_.seconds();
  useFaces();
  // The inside of closed two-sided objects, before any split: its faces are covered whole (their
  // open fraction 0), so that no cluster hands them light and none is pulled from them.
  Timer enclosures;
  Enclosures found = findEnclosures(leaves_.mesh, *caster_, scene_);
  if (found.wallsLitOnBothSides) {
    // Two-sided walls lit on both sides (a room lit inside under a sky): the clusters again, the
    // walls' outer side apart from everything else (geometry/enclosures.h), and what was made
    // from them.
    std::vector<std::vector<std::uint32_t>> groups(scene_.surfaces.size());
    for (std::size_t s = 0; s < scene_.surfaces.size(); ++s) groups[s].assign(surfaceFaces(scene_.surfaces[s]).size(), 0);
    for (std::size_t l = 0; l < leaves_.mesh.numPatches(); ++l)
      groups[leaves_.mesh.patches[l].surface][leaves_.mesh.patches[l].face] = found.outerSide[l];
    hierarchy_ = ElementHierarchy(scene_, groups);
    useFaces();
    found = findEnclosures(leaves_.mesh, *caster_, scene_);
  }
  hierarchy_.markEnclosedFaces(found.enclosed);
  if (std::find(found.enclosed.begin(), found.enclosed.end(), 1) != found.enclosed.end())
    caster_->setInsideClosedObjects(std::move(found.enclosed));
  coverageSeconds_ += enclosures.seconds();
  // The faces' open fractions are measured by the first refine(), unless the link cache holds them.
  // Until the first refinement, the leaves (the faces) exchange nothing.
  auto none = std::make_shared<Links>();
  none->start.assign(hierarchy_.nodes().size() + 1, 0);
  links_ = none;
  Timer transport;
  transport_ = makeTransport();
  transportSeconds_ += transport.seconds();
  linkCache_.directory = options.cacheDirectory;
  linkCache_.options = options;
}

std::shared_ptr<const HierarchicalTransport> HierarchicalMethod::makeTransport() {
  // Before the first refinement there are no links to share: every rank sweeps alike.
  if (ranks_.assigned()) return ranks_.makeTransport(hierarchy_, links_, openFractions(leaves_.mesh), patchAlbedo(scene_, leaves_.mesh));
  return std::make_shared<HierarchicalTransport>(hierarchy_, links_, openFractions(leaves_.mesh), patchAlbedo(scene_, leaves_.mesh));
}

void HierarchicalMethod::startSolve(const SolveBudget& budget) {
  if (passesDone_ == 0) linkCache_.firstBudget = budget;
}

void HierarchicalMethod::refineAtLightEdges(const std::vector<Light>& lights, double threshold, SolveReport& report) {
  Timer timer;
  const LightEdgeSplits split = splitAtLightEdges(hierarchy_, scene_, leaves_.mesh, lights, *caster_, epsilon_, options_.links, threshold);
  lightSplits_ += split.splits;
  lightSamples_ += split.samples;
  lightEdgeRays_ += split.rays;
  report.refined += static_cast<int>(split.splits);
  rebuildLeaves();
  lightSeconds_ += timer.seconds();
  report.adaptSeconds += timer.seconds();
}

void HierarchicalMethod::closeEnclosedLeaves() {
  const std::vector<std::uint32_t>& leafNodes = hierarchy_.leafNodes();
  for (std::size_t l = 0; l < leafNodes.size(); ++l)
    if (hierarchy_.node(leafNodes[l]).enclosed) leaves_.mesh.patches[l].openFraction = 0;
}

void HierarchicalMethod::rebuildLeaves() {
  // Nodes are only ever added, by splitting a leaf: as many as before, the leaves are the same.
  if (hierarchy_.nodes().size() == leafMeshNodes_) return;
  // A leaf that was a leaf at the same index before keeps its open fraction: its sample points
  // depend on its corners and index only (geometry/coverage.h), so measuring again would repeat
  // its 16 rays exactly. Leaves are numbered in node order, so those before the first split keep
  // their index.
  Timer timer;
  const std::vector<std::uint32_t>& leafNodes = hierarchy_.leafNodes();
  std::vector<std::uint8_t> measure(leafNodes.size(), 1);
  std::vector<double> open(leafNodes.size(), 1.0);
  for (std::size_t l = 0; l < std::min(leafNodes.size(), measuredLeafNodes_.size()); ++l)
    if (leafNodes[l] == measuredLeafNodes_[l]) {
      measure[l] = 0;
      open[l] = leaves_.mesh.patches[l].openFraction;
    }
  leaves_ = hierarchy_.leaves(scene_);
  leafMeshNodes_ = hierarchy_.nodes().size();
  leafSeconds_ += timer.seconds();
  Timer coverage;
  for (std::size_t l = 0; l < open.size(); ++l) leaves_.mesh.patches[l].openFraction = open[l];
  measureOpenFractions(leaves_.mesh, *caster_, measure);
  closeEnclosedLeaves();
  ++leafMeshGeneration_;
  measuredLeafNodes_ = leafNodes;
  coverageSeconds_ += coverage.seconds();
}

Result<bool> HierarchicalMethod::refine(const std::vector<Light>& lights, std::vector<Rgb>& radiosity, SolveReport& report) {
  if (passesDone_ >= options_.refinePasses) return false;
  // Nothing lit (no light, no emitting surface): the solution is black whatever the links, and
  // refinement by a zero power still splits every pair too close to estimate (a 264k-face
  // interior: 25 s, 621 MiB and 42 MB of link cache for a black picture). The faces stay
  // unlinked, and the pass is not counted: lights set later refine as the first solve would.
  if (passesDone_ == 0 && lights.empty() && !anyEmits(scene_)) return false;
  if (passesDone_ == 0) {
    if (!linkCache_.directory.empty() && loadLinks(lights, radiosity)) return true;
    Timer coverage;
    measureOpenFractions(leaves_.mesh, *caster_);
    closeEnclosedLeaves();
    measuredLeafNodes_ = hierarchy_.leafNodes();
    coverageSeconds_ += coverage.seconds();
  }
  // Which node each current leaf is, to hand the new leaves their ancestor's radiosity.
  std::vector<std::uint32_t> oldLeafOfNode(hierarchy_.nodes().size(), kNoNode);
  for (std::size_t l = 0; l < hierarchy_.leafNodes().size(); ++l) oldLeafOfNode[hierarchy_.leafNodes()[l]] = static_cast<std::uint32_t>(l);
  std::vector<Rgb> old = radiosity;

  std::vector<Rgb> estimate = radiosity;
  if (passesDone_ == 0) {
    // Nothing solved yet: the surfaces' emission and the lights' direct light at the centres.
    std::vector<Rgb> emitted = emittedRadiosity(scene_, leaves_.mesh);
    std::vector<Rgb> albedo = patchAlbedo(scene_, leaves_.mesh);
    double power = 0;
    std::vector<Rgb> direct(leaves_.mesh.numPatches());
    // The scene's power sets the light edges' threshold: a sky at its guide directions (a
    // sixteenth) does for it. On a sky-lit helmet (35k elements, a normal each) this estimate at
    // every direction took 6.5 s of a 31 s solve.
    const DirectLighting guide(withGuideSkies(lights), scene_.metresPerUnit, shadowTolerance_);
    parallelFor(0, direct.size(), [&](std::size_t i) {
      const Patch& p = leaves_.mesh.patches[i];
      direct[i] = albedo[i] * guide.irradiance(p.centroid, p.normal, *caster_, epsilon_);
    }, 64);
    for (std::size_t i = 0; i < direct.size(); ++i) power += (emitted[i] + direct[i]).maxComponent() * leaves_.mesh.patches[i].area;
    if (options_.refineAtLights && !lights.empty()) refineAtLightEdges(lights, options_.links.linkError * power, report);
    // Again on the leaves the lights made, each sky at every direction: the links are refined on
    // these values, and a sky's guide directions here moved vertices of the overcast daylit office
    // by up to 1.4%.
    const DirectLighting lighting(lights, scene_.metresPerUnit, shadowTolerance_);
    emitted = emittedRadiosity(scene_, leaves_.mesh);
    albedo = patchAlbedo(scene_, leaves_.mesh);
    // A leaf reflects light on its open part only (its area-averaged B, as the solve has it):
    // the inside of a closed two-sided object (open fraction 0) reflects none. Lit here like the
    // room side, the outer shell of a two-sided room drew half of every cluster link's source
    // samples, by this radiosity, and those links kept half their K: a Blender room lost 37% of
    // its power (docs/hierarchical.md, "Two-sided rooms").
    estimate.assign(leaves_.mesh.numPatches(), Rgb{});
    parallelFor(0, estimate.size(), [&](std::size_t i) {
      const Patch& p = leaves_.mesh.patches[i];
      estimate[i] = emitted[i] + albedo[i] * lighting.irradiance(p.centroid, p.normal, *caster_, epsilon_) * p.openFraction;
    }, 64);
    // Every surface that reflects will be lit by the bounces too: add what each would reflect of
    // the first light spread evenly over the open area and reflected to convergence (Cohen et
    // al. 1988's ambient term), so that links from surfaces lit only indirectly are refined, and
    // not dropped as carrying nothing, in this first pass.
    Rgb firstPower, reflectedArea;
    double openArea = 0;
    for (std::size_t i = 0; i < estimate.size(); ++i) {
      const double a = leaves_.mesh.patches[i].area, open = a * leaves_.mesh.patches[i].openFraction;
      firstPower += estimate[i] * a;
      reflectedArea += albedo[i] * open;
      openArea += open;
    }
    Rgb ambient;
    if (openArea > 0)
      for (int c = 0; c < 3; ++c) ambient[c] = firstPower[c] / openArea / std::fmax(1e-3, 1 - reflectedArea[c] / openArea);
    for (std::size_t i = 0; i < estimate.size(); ++i) estimate[i] += albedo[i] * ambient * leaves_.mesh.patches[i].openFraction;
    old.clear();
    oldLeafOfNode.assign(hierarchy_.nodes().size(), kNoNode);
  }

  RefinementReport pass;
  LinkOptions linkOptions = options_.links;
  linkOptions.memoryLimitBytes = memoryLimitBytes_;
  std::optional<LinkShare> share = ranks_.linkShare(hierarchy_);  // a distributed solve's: this rank's nodes
  const std::size_t nodesBefore = hierarchy_.nodes().size();
  links_ = std::make_shared<Links>(refineLinks(hierarchy_, *caster_, epsilon_, casterFace_, passesDone_ > 0 ? links_.get() : nullptr,
                                               largestChannel(estimate), openFractions(leaves_.mesh), linkOptions, pass,
                                               share ? &*share : nullptr));
  ranks_.refined(hierarchy_, nodesBefore, *links_);
  if (pass.memoryNeeded > 0)
    return Error{memoryExceeded("the hierarchical refinement, unfinished at " + std::to_string(hierarchy_.nodes().size()) + " nodes,",
                                pass.memoryNeeded, memoryLimitBytes_) +
                 "; raise --link-error or --min-area, or --memory-limit to allow more"};
  if (passesDone_ == 0) refinement_.initialLinks = pass.initialLinks;  // later passes start from the links
  refinement_.estimated += pass.estimated;
  refinement_.rays += pass.rays;
  refinement_.elementsSplit += pass.elementsSplit;
  refinement_.clusterLinks = pass.clusterLinks;
  refinement_.seconds += pass.seconds;
  report.refined += static_cast<int>(pass.elementsSplit);
  report.pairsEstimated += pass.estimated;
  report.formFactorSeconds += pass.seconds;

  rebuildLeaves();
  Timer transport;
  transport_ = makeTransport();
  transportSeconds_ += transport.seconds();
  // Warm start: each leaf from the nearest ancestor that was a leaf before (B stays as solved).
  radiosity.assign(hierarchy_.leafNodes().size(), Rgb{});
  if (!old.empty()) {
    oldLeafOfNode.resize(hierarchy_.nodes().size(), kNoNode);
    for (std::size_t l = 0; l < radiosity.size(); ++l) {
      std::uint32_t n = hierarchy_.leafNodes()[l];
      while (n != kNoNode && oldLeafOfNode[n] == kNoNode) n = hierarchy_.node(n).parent;
      if (n != kNoNode) radiosity[l] = old[oldLeafOfNode[n]];
    }
  }
  ++passesDone_;
  if (passesDone_ == options_.refinePasses && !linkCache_.path.empty()) saveLinks(radiosity);
  return true;
}

void HierarchicalMethod::leadRanks(bool leading) { ranks_.lead(leading); }

void HierarchicalMethod::serveRanks(const ElementSolution& solution) {
  ranks_.serve([&] { (void)vertexRadiosity(solution); },
               [&](std::span<const SurfacePoint> points, PointGatherRequest part) { (void)pointGather(solution, points, part); });
}

}  // namespace lambert
