#include "lambert/hierarchical/method.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <unordered_map>

#include "lambert/core/parallel.h"
#include "lambert/core/memory.h"
#include "lambert/core/timer.h"
#include "lambert/core/warning.h"
#include "lambert/hierarchical/final_gather.h"
#include "lambert/hierarchical/link_cache.h"
#include "lambert/engine/point_gather.h"
#include "lambert/core/cache_file.h"
#include "lambert/geometry/coverage.h"
#include "lambert/light/emission.h"
#include "lambert/light/lights.h"
#include "lambert/light/many_lights.h"

namespace lambert {

static_assert(PointGather::kNoLeaf == kNoNode, "a point gather's missing leaf is the hierarchy's missing node");
namespace {

std::vector<double> largestChannel(const std::vector<Rgb>& values) {
  std::vector<double> out(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) out[i] = std::fmax(0.0, values[i].maxComponent());
  return out;
}

std::string mebibytes(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MiB", static_cast<double>(bytes) / (1024.0 * 1024.0));
  return text;
}

std::vector<double> openFractions(const Mesh& mesh) {
  std::vector<double> out(mesh.numPatches());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = mesh.patches[i].openFraction;
  return out;
}

}  // namespace

HierarchicalMethod::HierarchicalMethod(const Scene& scene, const RadiosityOptions& options)
    : scene_(scene),
      options_(options.hierarchical),
      shadowTolerance_(options.directLight.shadowTolerance),
      memoryLimitBytes_(options.memoryLimitBytes),
      communicator_(options.communicator),
      hierarchy_(scene) {
  buildSeconds_ = created_.seconds();
  Timer leafTimer;
  leaves_ = hierarchy_.leaves(scene_);
  leafMeshNodes_ = hierarchy_.nodes().size();
  leafSeconds_ += leafTimer.seconds();
  Timer bvh;
  caster_ = makeEmbreeRayCaster(leaves_.mesh);
  casterFace_.reserve(leaves_.mesh.numPatches());
  for (const Patch& p : leaves_.mesh.patches) casterFace_.push_back(static_cast<std::uint64_t>(p.surface) << 32 | p.face);
  epsilon_ = rayEpsilon(leaves_.mesh);
  bvhSeconds_ = bvh.seconds();
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

std::shared_ptr<HierarchicalTransport> HierarchicalMethod::makeTransport() const {
  auto transport = std::make_shared<HierarchicalTransport>(hierarchy_, links_, openFractions(leaves_.mesh), patchAlbedo(scene_, leaves_.mesh));
  // Before the first refinement there are no links to share: every rank sweeps alike.
  if (communicator_ && !nodeRank_.empty()) {
    transport->distribute(communicator_, nodeRank_);
  }
  return transport;
}

void HierarchicalMethod::assignRanks() {
  // The leaves depth first (the children of a node after it, in the hierarchy's order), so that
  // a rank's run of them fills few subtrees, and each leaf's cost: its share of the area (where
  // the links go: refinement splits the lit area finely) and of the leaves, half and half.
  const std::size_t ranks = static_cast<std::size_t>(communicator_->size());
  std::vector<std::uint32_t> order, stack{0};
  while (!stack.empty()) {
    const std::uint32_t node = stack.back();
    stack.pop_back();
    if (hierarchy_.node(node).isLeaf()) order.push_back(node);
    const std::span<const std::uint32_t> children = hierarchy_.children(node);
    for (std::size_t c = children.size(); c-- > 0;) stack.push_back(children[c]);
  }
  const double totalArea = hierarchy_.totalArea(), count = static_cast<double>(order.size());
  const auto cost = [&](std::uint32_t node) { return 0.5 * hierarchy_.node(node).area / totalArea + 0.5 / count; };
  nodeRank_.assign(hierarchy_.nodes().size(), HierarchicalTransport::kSharedNode);
  // Rank r takes the leaves whose cumulative cost starts in [r/R, (r+1)/R) of the whole.
  double before = 0;
  for (std::uint32_t node : order) {
    nodeRank_[node] = std::min(static_cast<int>(ranks) - 1, static_cast<int>(before * static_cast<double>(ranks) + 1e-9));
    before += cost(node);
  }
  // A node over leaves of one rank alone is that rank's (children have larger indices).
  std::vector<int> below(hierarchy_.nodes().size(), -2);  // -2: nothing yet
  for (std::size_t i = hierarchy_.nodes().size(); i-- > 0;) {
    if (hierarchy_.node(static_cast<std::uint32_t>(i)).isLeaf()) below[i] = nodeRank_[i];
    else nodeRank_[i] = below[i];
    const std::uint32_t parent = hierarchy_.node(static_cast<std::uint32_t>(i)).parent;
    if (parent != kNoNode) below[parent] = below[parent] == -2 || below[parent] == below[i] ? below[i] : HierarchicalTransport::kSharedNode;
  }
}

void HierarchicalMethod::countLinksOverRanks() {
  // A shared node's links are held by every rank under it: the lowest counts them.
  const std::size_t n = hierarchy_.nodes().size();
  std::vector<int> lowest(n);
  for (std::size_t i = 0; i < n; ++i) lowest[i] = nodeRank_[i] == HierarchicalTransport::kSharedNode ? communicator_->size() : nodeRank_[i];
  for (std::size_t i = n; i-- > 1;)
    if (const std::uint32_t parent = hierarchy_.node(static_cast<std::uint32_t>(i)).parent; parent != kNoNode && nodeRank_[parent] == HierarchicalTransport::kSharedNode)
      lowest[parent] = std::min(lowest[parent], lowest[i]);
  double counted = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (lowest[i] == communicator_->rank()) counted += links_->start[i + 1] - links_->start[i];
  const double mine[3] = {static_cast<double>(links_->size()), counted, static_cast<double>(links_->bytes())};
  const auto ranks = static_cast<std::size_t>(communicator_->size());
  std::vector<int> counts(ranks, 3);
  std::vector<double> all(3 * ranks);
  communicator_->allGather<double>(mine, counts, all);
  linksOverRanks_ = {};
  for (std::size_t r = 0; r < ranks; ++r) {
    linksOverRanks_.mostHeld = std::max(linksOverRanks_.mostHeld, all[3 * r]);
    linksOverRanks_.total += all[3 * r + 1];
    linksOverRanks_.mostBytes = std::max(linksOverRanks_.mostBytes, all[3 * r + 2]);
  }
}

LinkShare HierarchicalMethod::linkShare() const {
  // This rank's nodes: its own subtrees, and the shared nodes over them.
  const int me = communicator_->rank();
  LinkShare share{communicator_.get(), std::vector<std::uint8_t>(hierarchy_.nodes().size(), 0)};
  for (std::size_t i = hierarchy_.nodes().size(); i-- > 0;) {
    if (nodeRank_[i] == me) share.mine[i] = 1;
    const std::uint32_t parent = hierarchy_.node(static_cast<std::uint32_t>(i)).parent;
    if (parent != kNoNode && share.mine[i]) share.mine[parent] = 1;
  }
  return share;
}

void HierarchicalMethod::startSolve(const SolveBudget& budget) {
  if (passesDone_ == 0) linkCache_.firstBudget = budget;
}

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

// Splits leaves, breadth first, while the direct light of some light varies across one by more
// than the threshold allows (ρ · (E_max − E_min) · A over its centre and corners, drawn a tenth
// of the way in): a spot's cone edge or a shadow edge crosses it.
void HierarchicalMethod::splitAtLightEdges(const std::vector<Light>& lights, double threshold, SolveCallReport& report) {
  Timer timer;
  const double minArea = minimumElementArea(hierarchy_, options_.links);
  const std::vector<Rgb> albedo = patchAlbedo(scene_, leaves_.mesh);
  std::vector<std::uint32_t> frontier = hierarchy_.leafNodes();
  std::vector<double> frontierAlbedo(frontier.size());
  for (std::size_t i = 0; i < frontier.size(); ++i) frontierAlbedo[i] = albedo[i].maxComponent();
  std::vector<std::uint32_t> next;
  std::vector<double> nextAlbedo;
  const DirectLighting lighting(lights, scene_.metresPerUnit, 0);
  while (!frontier.empty()) {
    std::vector<char> split(frontier.size(), 0);
    std::vector<std::uint32_t> samples(frontier.size(), 0), rays(frontier.size(), 0);  // points × lights evaluated; shadow rays
    parallelFor(0, frontier.size(), [&](std::size_t i) {
      const HierarchyNode& e = hierarchy_.node(frontier[i]);
      if (e.area * 0.25 < minArea) return;
      Vec3 points[5] = {e.centre};
      for (std::size_t k = 0; k < e.numCorners; ++k) points[k + 1] = lerp(e.corners[k], e.centre, 0.1);
      double radius = 0;
      for (std::size_t k = 0; k < e.numCorners; ++k) radius = std::fmax(radius, length(e.corners[k] - e.centre));
      radius *= 1 + 1e-9;
      for (std::size_t l = 0; l < lights.size(); ++l) {
        // First the light's bound over the element's sphere (no evaluation at its points): most
        // of many lights are far, or hold the element outside their cones.
        if (frontierAlbedo[i] * lighting.upperBound(l, e.centre, radius, e.normal).maxComponent() * e.area * (1 + 1e-9) <= threshold) continue;
        samples[i] += e.numCorners + 1u;
        // The light's variation over the points is at most its largest unoccluded value there:
        // where ρ times that times the area cannot exceed the threshold, no shadow ray can make
        // this light split the element, and none is traced (a cull that changes no split; the
        // margin covers the rounding between the precomputed and lights.cpp's evaluation). With
        // many lights most are far or outside their cones from most elements.
        double unoccluded[5] = {}, largest = 0;
        for (std::size_t k = 0; k <= e.numCorners; ++k) {
          unoccluded[k] = lighting.unoccluded(l, points[k], e.normal).maxComponent();
          largest = std::fmax(largest, unoccluded[k]);
        }
        if (frontierAlbedo[i] * largest * e.area * (1 + 1e-9) <= threshold) continue;
        double lo = INFINITY, hi = 0;
        for (std::size_t k = 0; k <= e.numCorners; ++k) {
          double value = 0;
          if (unoccluded[k] > 0) {
            ++rays[i];
            value = irradiance(lights[l], points[k], e.normal, *caster_, epsilon_, scene_.metresPerUnit).maxComponent();
          }
          lo = std::fmin(lo, value);
          hi = std::fmax(hi, value);
        }
        if (frontierAlbedo[i] * (hi - lo) * e.area > threshold) {
          split[i] = 1;
          return;
        }
      }
    }, 16);
    for (std::uint32_t n : rays) lightEdgeRays_ += n;
    for (std::uint32_t n : samples) lightSamples_ += n;
    next.clear();
    nextAlbedo.clear();
    for (std::size_t i = 0; i < frontier.size(); ++i) {
      if (!split[i]) continue;
      hierarchy_.split(frontier[i]);
      ++lightSplits_;
      ++report.refined;
      for (std::uint32_t child : hierarchy_.children(frontier[i])) {
        next.push_back(child);
        nextAlbedo.push_back(frontierAlbedo[i]);
      }
    }
    frontier.swap(next);
    frontierAlbedo.swap(nextAlbedo);
  }
  hierarchy_.numberLeaves();
  rebuildLeaves();
  lightSeconds_ += timer.seconds();
  report.adaptSeconds += timer.seconds();
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
  ++leafMeshGeneration_;
  measuredLeafNodes_ = leafNodes;
  coverageSeconds_ += coverage.seconds();
}

Result<bool> HierarchicalMethod::refine(const std::vector<Light>& lights, std::vector<Rgb>& radiosity, SolveCallReport& report) {
  if (passesDone_ >= options_.refinePasses) return false;
  if (passesDone_ == 0) {
    if (!linkCache_.directory.empty() && loadLinks(lights, radiosity)) return true;
    Timer coverage;
    measureOpenFractions(leaves_.mesh, *caster_);
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
    const DirectLighting lighting(lights, scene_.metresPerUnit, shadowTolerance_);
    parallelFor(0, direct.size(), [&](std::size_t i) {
      const Patch& p = leaves_.mesh.patches[i];
      direct[i] = albedo[i] * lighting.irradiance(p.centroid, p.normal, *caster_, epsilon_);
    }, 64);
    for (std::size_t i = 0; i < direct.size(); ++i) power += (emitted[i] + direct[i]).maxComponent() * leaves_.mesh.patches[i].area;
    if (options_.refineAtLights && !lights.empty()) splitAtLightEdges(lights, options_.links.linkError * power, report);
    // Again on the leaves the lights made.
    emitted = emittedRadiosity(scene_, leaves_.mesh);
    albedo = patchAlbedo(scene_, leaves_.mesh);
    estimate.assign(leaves_.mesh.numPatches(), Rgb{});
    parallelFor(0, estimate.size(), [&](std::size_t i) {
      const Patch& p = leaves_.mesh.patches[i];
      estimate[i] = emitted[i] + albedo[i] * lighting.irradiance(p.centroid, p.normal, *caster_, epsilon_);
    }, 64);
    // Every surface that reflects will be lit by the bounces too: add what each would reflect of
    // the first light spread evenly and reflected to convergence (Cohen et al. 1988's ambient
    // term), so that links from surfaces lit only indirectly are refined, and not dropped as
    // carrying nothing, in this first pass.
    Rgb firstPower, reflectedArea;
    double totalArea = 0;
    for (std::size_t i = 0; i < estimate.size(); ++i) {
      const double a = leaves_.mesh.patches[i].area;
      firstPower += estimate[i] * a;
      reflectedArea += albedo[i] * a;
      totalArea += a;
    }
    Rgb ambient;
    for (int c = 0; c < 3; ++c) ambient[c] = firstPower[c] / totalArea / std::fmax(1e-3, 1 - reflectedArea[c] / totalArea);
    for (std::size_t i = 0; i < estimate.size(); ++i) estimate[i] += albedo[i] * ambient;
    old.clear();
    oldLeafOfNode.assign(hierarchy_.nodes().size(), kNoNode);
  }

  RefinementReport pass;
  LinkOptions linkOptions = options_.links;
  linkOptions.memoryLimitBytes = memoryLimitBytes_;
  std::optional<LinkShare> share;
  if (communicator_) {
    if (nodeRank_.empty()) assignRanks();
    share = linkShare();
  }
  const std::size_t nodesBefore = hierarchy_.nodes().size();
  links_ = std::make_shared<Links>(refineLinks(hierarchy_, *caster_, epsilon_, casterFace_, passesDone_ > 0 ? links_.get() : nullptr,
                                               largestChannel(estimate), openFractions(leaves_.mesh), linkOptions, pass,
                                               share ? &*share : nullptr));
  // The elements split take their parent's rank.
  if (communicator_) {
    nodeRank_.resize(hierarchy_.nodes().size());
    for (std::size_t i = nodesBefore; i < nodeRank_.size(); ++i) nodeRank_[i] = nodeRank_[hierarchy_.node(static_cast<std::uint32_t>(i)).parent];
    countLinksOverRanks();
  }
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
  sweepCommunicationSeconds_ += transport_->sweepCommunicationSeconds();
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

void HierarchicalMethod::leadRanks(bool leading) {
  if (!communicator_ || communicator_->size() < 2 || leading == leading_) return;
  if (!leading) askRanks({Ask::Done, 0, 0}, {});
  leading_ = leading;
}

void HierarchicalMethod::askRanks(const Asked& asked, std::span<const SurfacePoint> points) const {
  if (!leading_ || answering_ > 0) return;  // the other ranks are making the same call already
  (void)communicator_->allGatherVariable<Asked>(std::span<const Asked>(&asked, 1));
  if (asked.ask == Ask::Points) (void)communicator_->allGatherVariable<SurfacePoint>(points);
}

void HierarchicalMethod::serveRanks(const ElementSolution& solution) {
  if (!communicator_ || communicator_->size() < 2) return;
  LAMBERT_CHECK(communicator_->rank() != 0);
  const Answering answering(*this);
  while (true) {
    const std::vector<Asked> asked = communicator_->allGatherVariable<Asked>({});
    LAMBERT_CHECK(asked.size() == 1);
    if (asked[0].ask == Ask::Done) return;
    if (asked[0].ask == Ask::Vertices) {
      const VertexQuantity radiosity = VertexQuantity::Radiosity;
      (void)vertexSolution(solution, std::span<const VertexQuantity>(&radiosity, 1));
      // Rank 0 asked for the gather of the same input (the same solution on every rank).
      LAMBERT_CHECK(acrossRanks_.digest == asked[0].digest);
    } else {
      const std::vector<SurfacePoint> points = communicator_->allGatherVariable<SurfacePoint>({});
      (void)pointGather(solution, points, static_cast<PointGatherPart>(asked[0].part));
    }
  }
}

HierarchicalMethod::SitesByRank HierarchicalMethod::sitesByRank(const std::vector<std::uint32_t>& leaf) const {
  SitesByRank split{std::vector<std::vector<std::uint32_t>>(static_cast<std::size_t>(communicator_->size())),
                    std::vector<std::uint32_t>(leaf.size(), kNoNode)};
  for (std::uint32_t i = 0; i < leaf.size(); ++i) {
    if (leaf[i] == kNoNode) continue;
    const int owner = transport_->rankOfLeaf(leaf[i]);
    split.sites[static_cast<std::size_t>(owner)].push_back(i);
    if (owner == communicator_->rank()) split.mine[i] = leaf[i];
  }
  return split;
}

template <class T>
std::vector<T> HierarchicalMethod::inSiteOrder(const SitesByRank& split, const std::vector<T>& ofMine) const {
  std::vector<T> sent;
  for (std::uint32_t i : split.sites[static_cast<std::size_t>(communicator_->rank())]) sent.push_back(ofMine[i]);
  std::vector<int> counts;
  std::size_t total = 0;
  for (const std::vector<std::uint32_t>& sites : split.sites) {
    counts.push_back(static_cast<int>(sites.size()));
    total += sites.size();
  }
  std::vector<T> all(total), out(ofMine.size());
  communicator_->allGather<T>(sent, counts, all);
  std::size_t k = 0;
  for (const std::vector<std::uint32_t>& sites : split.sites)
    for (std::uint32_t i : sites) out[i] = all[k++];
  return out;
}

std::vector<Rgb> HierarchicalMethod::gatherAcrossRanks(const FinalGather& whole, const std::vector<Rgb>& mean, FinalGatherCounts& counts,
                                                        NearFieldWeights& near) const {
  const std::vector<std::uint32_t>& leaf = whole.gatheringLeaf();
  SitesByRank split = sitesByRank(leaf);
  // The same sites, so that every vertex draws its rays as in one process.
  const FinalGather gather(hierarchy_, leaves_, *links_, *caster_, epsilon_, whole.sites(), std::move(split.mine),
                           options_.links.visibilityRays, options_.links.seed, false);
  NearFieldWeights own;
  const std::vector<Rgb> gathered = gather.irradiance(mean, &counts, nullptr, nullptr, &own);
  struct VertexRecord {
    Rgb gathered, meanPart;
    std::uint32_t entries = 0;
  };
  struct EntryRecord {
    std::uint32_t corner;
    float weight;
  };
  std::vector<VertexRecord> mine(leaf.size());
  std::vector<EntryRecord> sentEntries;
  for (std::uint32_t v : split.sites[static_cast<std::size_t>(communicator_->rank())]) {
    mine[v] = {gathered[v], own.meanPart[v], own.start[v + 1] - own.start[v]};
    for (std::uint32_t k = own.start[v]; k < own.start[v + 1]; ++k) sentEntries.push_back({own.corner[k], own.weight[k]});
  }
  const std::vector<VertexRecord> record = inSiteOrder(split, mine);
  const std::vector<EntryRecord> entries = communicator_->allGatherVariable<EntryRecord>(sentEntries);
  // The weights as compressed rows in vertex order; the entries arrived in rank order.
  std::vector<std::size_t> entryOf(leaf.size(), 0);
  std::size_t entry = 0;
  for (const std::vector<std::uint32_t>& sites : split.sites)
    for (std::uint32_t v : sites) {
      entryOf[v] = entry;
      entry += record[v].entries;
    }
  std::vector<Rgb> out(leaf.size());
  near = {};
  near.meanPart.assign(leaf.size(), Rgb{});
  near.start.assign(leaf.size() + 1, 0);
  for (std::size_t v = 0; v < leaf.size(); ++v) near.start[v + 1] = near.start[v] + record[v].entries;
  near.corner.resize(near.start.back());
  near.weight.resize(near.start.back());
  for (std::size_t v = 0; v < leaf.size(); ++v) {
    out[v] = record[v].gathered;
    near.meanPart[v] = record[v].meanPart;
    for (std::uint32_t k = 0; k < record[v].entries; ++k) {
      near.corner[near.start[v] + k] = entries[entryOf[v] + k].corner;
      near.weight[near.start[v] + k] = entries[entryOf[v] + k].weight;
    }
  }
  return out;
}

std::vector<std::vector<Rgb>> HierarchicalMethod::vertexSolution(const ElementSolution& solution,
                                                                   std::span<const VertexQuantity> quantities) const {
  LAMBERT_CHECK(solution.radiosity.size() == leaves_.mesh.numPatches());
  Timer gatherTimer;
  const FinalGather gather(hierarchy_, leaves_, *links_, *caster_, epsilon_, 1e-4 * sceneDiagonal(scene_),
                           options_.links.visibilityRays, options_.links.seed);
  std::vector<Rgb> mean;
  transport_->pull(solution.radiosity, mean);
  // The visibility and irradiance files (link_cache.h) hold values over the links their key
  // made: the last pass's.
  std::shared_ptr<const GatherVisibility> known;
  std::shared_ptr<const CachedGatherIrradiance> stored;
  std::uint64_t knownDigest = 0;
  std::string recordPath, irradiancePath;
  const bool cached = !linkCache_.path.empty() && passesDone_ == options_.refinePasses;
  if (cached) {
    const std::lock_guard<std::mutex> lock(gatherCacheMutex_);
    if (!gatherCache_.tried) {
      gatherCache_.tried = true;
      Timer timer;
      const std::string path = gatherVisibilityPath(linkCache_.directory, linkCache_.key);
      Result<GatherVisibility> loaded =
          loadGatherVisibility(path, linkCache_.key, leaves_.mesh.numVertices(), links_->size(), hierarchy_.nodes().size());
      if (loaded) {
        std::error_code ec;
        gatherCache_.bytes = std::filesystem::file_size(path, ec);
        gatherCache_.status = "loaded " + path + " (" + std::to_string(loaded->size()) + " values, " + mebibytes(gatherCache_.bytes) + ")";
        gatherCache_.known = std::make_shared<const GatherVisibility>(std::move(*loaded));
      } else {
        // As for the links: no file is the ordinary first run, anything else is reported.
        if (!cachefile::isMissing(path)) warning(loaded.error().message + "; recomputing");
        recordPath = path;
      }
      gatherCache_.knownDigest = gatherVisibilityDigest(gatherCache_.known.get());
      gatherCache_.seconds += timer.seconds();
      Timer irradianceTimer;
      irradiancePath = gatherIrradiancePath(linkCache_.directory, linkCache_.key);
      Result<CachedGatherIrradiance> irradiance = loadGatherIrradiance(irradiancePath, linkCache_.key, leaves_.mesh.numVertices());
      if (irradiance) {
        std::error_code ec;
        gatherCache_.irradianceBytes = std::filesystem::file_size(irradiancePath, ec);
        gatherCache_.irradianceStatus = "loaded " + irradiancePath + " (" + mebibytes(gatherCache_.irradianceBytes) + ")";
        gatherCache_.irradiance = std::make_shared<const CachedGatherIrradiance>(std::move(*irradiance));
      } else {
        if (!cachefile::isMissing(irradiancePath)) warning(irradiance.error().message + "; recomputing");
        gatherCache_.irradianceStatus = "none";
      }
      gatherCache_.irradianceSeconds += irradianceTimer.seconds();
    }
    known = gatherCache_.known;
    knownDigest = gatherCache_.knownDigest;
    stored = gatherCache_.irradiance;
  }
  FinalGatherCounts counts;
  GatherVisibility recorded;
  const std::vector<VertexSite>& sites = gather.sites();
  const std::vector<std::uint32_t>& leaf = gather.gatheringLeaf();
  // The lights' direct irradiance at the vertices: every quantity needs it, through the close
  // sources' corner radiosities if not directly.
  std::vector<Rgb> direct(sites.size()), emitted(sites.size()), albedo(sites.size());
  const DirectLighting lighting(solution.lights, solution.metresPerUnit, shadowTolerance_);
  parallelFor(0, direct.size(), [&](std::size_t v) {
    if (leaf[v] == kNoNode) return;
    emitted[v] = solution.emitted[leaf[v]];
    albedo[v] = solution.albedo[leaf[v]];
    direct[v] = lighting.irradiance(sites[v].point, sites[v].normal, *caster_, epsilon_);
  }, 64);
  NearFieldWeights near;
  int nearIterations = 0;
  std::vector<Rgb> gathered;
  Timer digestTimer;
  // The gather's result with its corners coupled (FinalGather::coupleNearField), which also
  // reads the vertices' direct light, emission and albedo.
  const std::uint64_t inputDigest = cached ? gatherInputDigest(mean, knownDigest, {&direct, &emitted, &albedo}) : 0;
  const double irradianceSeconds = digestTimer.seconds();
  const bool distributed = communicator_ && communicator_->size() > 1;
  const std::uint64_t memoDigest = distributed ? gatherInputDigest(mean, 0, {&direct, &emitted, &albedo}) : 0;
  if (distributed && acrossRanks_.digest == memoDigest && !acrossRanks_.gathered.empty()) {
    const std::lock_guard<std::mutex> lock(gatherCacheMutex_);
    gathered = acrossRanks_.gathered;
    for (std::uint32_t l : gather.gatheringLeaf()) counts.vertices += l != kNoNode;
  } else if (distributed) {
    // Every rank gathers the vertices of its own leaves (through its own links: it holds no
    // others); the results and the close sources' corner weights go to every rank, which couples
    // them as one process would. Rank 0 writing the outputs asks the others to join first.
    askRanks({Ask::Vertices, 0, memoDigest}, {});
    const Answering answering(*this);
    gathered = FinalGather::coupleNearField(gatherAcrossRanks(gather, mean, counts, near), near, emitted, albedo, direct, &nearIterations);
    const std::lock_guard<std::mutex> lock(gatherCacheMutex_);
    acrossRanks_ = {memoDigest, gathered};
  } else if (stored && stored->inputDigest == inputDigest) {
    // The same input as the gather that wrote the file: its result, bit for bit.
    gathered = stored->irradiance;
    for (std::uint32_t l : gather.gatheringLeaf()) counts.vertices += l != kNoNode;
    const std::lock_guard<std::mutex> lock(gatherCacheMutex_);
    ++gatherCache_.irradianceReads;
    gatherCache_.irradianceSeconds += irradianceSeconds;
  } else {
    gathered = FinalGather::coupleNearField(gather.irradiance(mean, &counts, known.get(), recordPath.empty() ? nullptr : &recorded, &near),
                                            near, emitted, albedo, direct, &nearIterations);
    if (!recordPath.empty()) {
      Timer timer;
      Result<std::uint64_t> saved = saveGatherVisibility(recordPath, linkCache_.key, recorded);
      const std::lock_guard<std::mutex> lock(gatherCacheMutex_);
      if (saved) {
        gatherCache_.bytes = *saved;
        gatherCache_.status = "saved " + recordPath + " (" + std::to_string(recorded.size()) + " values, " + mebibytes(*saved) + ")";
      } else {
        warning(saved.error().message + "; final gather visibility not cached");
        gatherCache_.status = "not saved: " + saved.error().message;
      }
      gatherCache_.seconds += timer.seconds();
    }
    if (!irradiancePath.empty()) {
      // Under the visibility values the next process reads: those just recorded, when the file
      // held none.
      Timer timer;
      CachedGatherIrradiance made;
      made.inputDigest =
          recordPath.empty() ? inputDigest : gatherInputDigest(mean, gatherVisibilityDigest(&recorded), {&direct, &emitted, &albedo});
      made.irradiance = gathered;
      Result<std::uint64_t> saved = saveGatherIrradiance(irradiancePath, linkCache_.key, made);
      const std::lock_guard<std::mutex> lock(gatherCacheMutex_);
      if (saved) {
        gatherCache_.irradianceBytes = *saved;
        gatherCache_.irradianceStatus = "saved " + irradiancePath + " (" + mebibytes(*saved) + ")";
      } else {
        warning(saved.error().message + "; final gather irradiance not cached");
        gatherCache_.irradianceStatus = "not saved: " + saved.error().message;
      }
      gatherCache_.irradianceSeconds += irradianceSeconds + timer.seconds();
    } else if (cached) {
      const std::lock_guard<std::mutex> lock(gatherCacheMutex_);
      gatherCache_.irradianceSeconds += irradianceSeconds;
    }
  }
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
      const Rgb received = quantity == VertexQuantity::IndirectRadiosity ? gathered[v] : gathered[v] + direct[v];
      values[v] = quantity == VertexQuantity::Irradiance ? received : emitted[v] + albedo[v] * received;
    }
    // Made on a coarser edge first (a smaller vertex index), so an end that hangs itself is final.
    for (const HangingVertex& h : leaves_.hanging)
      if (!coveredEnd[h.edgeStart] && !coveredEnd[h.edgeEnd]) values[h.vertex] = (values[h.edgeStart] + values[h.edgeEnd]) * 0.5;
    out.push_back(std::move(values));
  }
  const std::lock_guard<std::mutex> lock(gatherMutex_);
  gatherCounts_ = counts;
  nearFieldWeights_ = near.size();
  nearFieldIterations_ = nearIterations;
  gatherSeconds_ = gatherTimer.seconds();
  return out;
}

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
                                                     PointGatherPart part) const {
  if (Status spread = spreadOverRanks(part); !spread) return spread.error();
  if (part != PointGatherPart::Sites) askRanks({Ask::Points, static_cast<std::uint32_t>(part), 0}, points);
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
  if (part != PointGatherPart::Sites) gatherAt(solution, part, true, out);
  return out;
}

Status HierarchicalMethod::spreadOverRanks(PointGatherPart part) const {
  if (!communicator_ || communicator_->size() < 2 || part == PointGatherPart::Sites || part == PointGatherPart::Light) return Ok{};
  return Error{"a distributed solve gathers the light at points, not its weights for later solves (they read every rank's links): "
               "solve in one process to update lightmaps as lights move"};
}

void HierarchicalMethod::gatherAtAcrossRanks(const ElementSolution& solution, bool atPoints, PointGather& out) const {
  const Answering answering(*this);
  // Each site is gathered by the rank of its leaf, through its own links.
  SitesByRank split = sitesByRank(out.leaf);
  const FinalGather gather(hierarchy_, leaves_, *links_, *caster_, epsilon_, out.sites, std::move(split.mine), options_.links.visibilityRays,
                           options_.links.seed, atPoints);
  std::vector<Rgb> mean;
  transport_->pull(solution.radiosity, mean);
  NearFieldWeights near;
  const std::vector<Rgb> gathered = gather.irradiance(mean, nullptr, nullptr, nullptr, &near, nullptr);
  const VertexQuantity radiosity = VertexQuantity::Radiosity;
  out.fromSurfaces =
      inSiteOrder(split, FinalGather::withCorners(gathered, near, vertexSolution(solution, std::span<const VertexQuantity>(&radiosity, 1)).front()));
}

void HierarchicalMethod::gatherAt(const ElementSolution& solution, PointGatherPart part, bool atPoints, PointGather& out) const {
  if (communicator_ && communicator_->size() > 1) return gatherAtAcrossRanks(solution, atPoints, out);
  const bool withWeights = part == PointGatherPart::LightAndWeights || part == PointGatherPart::Weights;
  const FinalGather gather(hierarchy_, leaves_, *links_, *caster_, epsilon_, out.sites, out.leaf, options_.links.visibilityRays,
                           options_.links.seed, atPoints);
  std::vector<Rgb> mean;
  transport_->pull(solution.radiosity, mean);
  const std::vector<Rgb> gathered = gather.irradiance(mean, nullptr, nullptr, nullptr, &out.near, withWeights ? &out.nodes : nullptr);
  if (part == PointGatherPart::Weights) return;
  const VertexQuantity radiosity = VertexQuantity::Radiosity;
  out.fromSurfaces = FinalGather::withCorners(gathered, out.near, vertexSolution(solution, std::span<const VertexQuantity>(&radiosity, 1)).front());
  if (!withWeights) out.near = {};
}

Result<PointGather> HierarchicalMethod::vertexGather(const ElementSolution& solution, std::span<const std::uint32_t> vertices,
                                                      PointGatherPart part) const {
  if (Status spread = spreadOverRanks(part == PointGatherPart::Light ? PointGatherPart::Weights : part); !spread) return spread.error();
  const std::vector<VertexSite> sites = vertexSites(leaves_.mesh, 1e-4 * sceneDiagonal(scene_));
  const std::vector<std::uint32_t> leaf = FinalGather::gatheringLeaves(leaves_.mesh);
  PointGather out;
  out.rayEpsilon = epsilon_;
  for (std::uint32_t v : vertices) {
    if (v >= sites.size()) return Error{"vertex " + std::to_string(v) + ": no such vertex in the solution's vertex mesh"};
    out.sites.push_back(sites[v]);
    out.leaf.push_back(leaf[v]);
  }
  if (part != PointGatherPart::Sites) gatherAt(solution, part, false, out);
  return out;
}

Result<std::vector<Rgb>> HierarchicalMethod::nodeMeanRadiosity(const ElementSolution& solution) const {
  std::vector<Rgb> mean;
  transport_->pull(solution.radiosity, mean);
  return mean;
}

Result<std::vector<Rgb>> HierarchicalMethod::pointIrradiance(const ElementSolution& solution,
                                                              std::span<const SurfacePoint> points) const {
  Result<PointGather> gathered = pointGather(solution, points, PointGatherPart::Light);
  if (!gathered) return gathered.error();
  std::vector<Rgb> irradiance = std::move(gathered->fromSurfaces);
  const std::vector<VertexSite>& sites = gathered->sites;
  if (!solution.lights.empty()) {
    // The lights' share by Ward's adaptive shadow testing (light/many_lights.h): within
    // shadowTolerance_ of the unoccluded light at each point, exact when it is 0.
    const DirectLighting lighting(solution.lights, solution.metresPerUnit, shadowTolerance_);
    parallelFor(0, irradiance.size(), [&](std::size_t i) {
      irradiance[i] += lighting.irradiance(sites[i].point, sites[i].normal, *caster_, epsilon_);
    }, 64);
  }
  return irradiance;
}

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
  if (communicator_) {
    const CommunicationStats& sent = communicator_->stats();
    stats.add("ranks", "ranks (a distributed solve)", static_cast<std::int64_t>(communicator_->size()));
    stats.add("rank_leaves", "leaves this rank (0) sweeps", static_cast<std::int64_t>(transport_->ownLeaves().size()));
    stats.add("exchange_bytes_per_sweep", "bytes a sweep hands this rank (0): the power of the others' nodes its links read",
              static_cast<std::int64_t>(sizeof(Rgb) * transport_->receivedPerSweep()));
    stats.add("exchange_bytes_per_sweep_all_leaves", "bytes a sweep would hand it with every leaf's B",
              static_cast<std::int64_t>(sizeof(Rgb) * (transport_->size() - transport_->ownLeaves().size())));
    stats.add("communication_bytes_received", "bytes this rank received in all", static_cast<std::int64_t>(sent.bytesReceived));
    stats.add("communication_bytes_sent", "bytes this rank sent in all", static_cast<std::int64_t>(sent.bytesSent));
    stats.add("communication_calls", "collective calls", static_cast<std::int64_t>(sent.calls));
    stats.add("communication_seconds", "time in collective calls (waiting for the other ranks included)", sent.seconds, "s");
    stats.add("sweep_communication_seconds", "of which the sweeps' exchanges (every pass)",
              sweepCommunicationSeconds_ + transport_->sweepCommunicationSeconds(), "s");
  }
  stats.add("min_element_area", "minimum element area", minimumElementArea(hierarchy_, options_.links), "scene units²");
  stats.add("refine_passes", "refinement passes", count(passesDone_));
  if (communicator_) {
    stats.add("links", "links (every rank's, each once)", count(linksOverRanks_.total));
    stats.add("rank_links", "links this rank (0) holds", count(links_->size()));
    stats.add("rank_links_most", "links the rank holding most holds", count(linksOverRanks_.mostHeld));
    stats.add("rank_link_bytes_most", "link memory of the rank holding most", linksOverRanks_.mostBytes / (1024.0 * 1024.0), "MiB");
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
  stats.add("link_bytes", communicator_ ? "link memory (this rank, 0)" : "link memory", linkBytes / (1024.0 * 1024.0), "MiB");
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
  if (!linkCache_.directory.empty()) {
    const std::lock_guard<std::mutex> lock(gatherCacheMutex_);
    stats.add("gather_cache", "final gather visibility cache", gatherCache_.status);
    if (gatherCache_.bytes > 0) stats.add("gather_cache_bytes", "final gather visibility file size", static_cast<std::int64_t>(gatherCache_.bytes), "B");
    stats.add("gather_cache_seconds", "final gather visibility cache time (load or save)", gatherCache_.seconds, "s");
    stats.add("gather_irradiance_cache", "final gather irradiance cache", gatherCache_.irradianceStatus);
    if (gatherCache_.irradianceBytes > 0)
      stats.add("gather_irradiance_cache_bytes", "final gather irradiance file size", static_cast<std::int64_t>(gatherCache_.irradianceBytes), "B");
    stats.add("gather_irradiance_reads", "final gathers read from the irradiance cache", count(gatherCache_.irradianceReads));
    stats.add("gather_irradiance_cache_seconds", "final gather irradiance cache time (digest, load or save)", gatherCache_.irradianceSeconds, "s");
  }
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
    stats.add("gather_near_iterations", "final gather: Jacobi steps coupling those corners", count(nearFieldIterations_));
    stats.add("gather_seconds", "final gather time (last: sites, gather, direct light at the vertices)", gatherSeconds_, "s");
  }
}

}  // namespace lambert
