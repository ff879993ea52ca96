#include "lambert/flat/adaptive_method.h"

#include <cmath>

#include "lambert/core/memory.h"
#include "lambert/core/timer.h"
#include "lambert/core/warning.h"
#include "lambert/core/cache_file.h"
#include "lambert/light/emission.h"

namespace lambert {
namespace {

// Points just inside the cell's corners: a corner on the surface's border would send shadow rays
// grazing the neighbouring surface.
std::array<Vec3, 4> insetCorners(const PatchCorners& corners) {
  Vec3 centre;
  for (const Vec3& c : corners) centre += c / static_cast<double>(corners.size());
  std::array<Vec3, 4> inset;
  for (std::size_t k = 0; k < corners.size(); ++k) inset[k] = lerp(corners[k], centre, 0.01);
  return inset;
}

bool rayHitsQuad(const Vec3& origin, const Vec3& direction, const PatchCorners& q) {
  for (std::size_t k = 1; k + 1 < q.size(); ++k) {
    Vec3 e1 = q[k] - q[0], e2 = q[k + 1] - q[0], p = cross(direction, e2);
    double det = dot(e1, p);
    if (std::fabs(det) < 1e-300) continue;
    Vec3 s = origin - q[0];
    double u = dot(s, p) / det;
    Vec3 r = cross(s, e1);
    double v = dot(direction, r) / det;
    if (u >= 0 && v >= 0 && u + v <= 1 && dot(e2, r) / det > 0) return true;
  }
  return false;
}

double luminanceRange(std::span<const Rgb> values) {
  double lo = INFINITY, hi = -INFINITY;
  for (const Rgb& v : values) {
    lo = std::fmin(lo, v.luminance());
    hi = std::fmax(hi, v.luminance());
  }
  return hi - lo;
}

}  // namespace

Result<std::unique_ptr<AdaptiveMethod>> AdaptiveMethod::create(const Scene& scene, const RadiosityOptions& options) {
  // The master table is filled a pair at a time; the hemi-cube and hemisphere methods give rows.
  if (!isPairMethod(options.formFactors.method))
    return Error{"adaptive meshing needs a pair-wise form-factor method (mc or point), not '" +
                 formFactorMethodName(options.formFactors.method) + "'"};
  if (options.adaptive.passesPerSolve < 1) return Error{"adaptive meshing needs at least one refine-and-solve pass"};
  QuadtreeOptions quadtree = options.adaptive.quadtree;
  if (quadtree.baseEdgeLength <= 0) quadtree.baseEdgeLength = sceneDiagonal(scene) / 6;
  Result<AdaptiveMesh> mesh = AdaptiveMesh::build(scene, quadtree);
  if (!mesh) return mesh.error();
  return std::unique_ptr<AdaptiveMethod>(new AdaptiveMethod(scene, std::move(*mesh), options));
}

AdaptiveMethod::AdaptiveMethod(const Scene& scene, AdaptiveMesh mesh, const RadiosityOptions& options)
    : scene_(scene),
      options_(options.adaptive),
      memoryLimitBytes_(options.memoryLimitBytes),
      formFactorOptions_(options.formFactors),
      normalizeRows_(options.normalizeRows),
      cacheDirectory_(options.cacheDirectory),
      mesh_(std::move(mesh)),
      baseMesh_(mesh_.activeMesh()) {
  options_.quadtree = mesh_.options();
  // Pairs are estimated many small batches at a time, so a progress bar would only flicker.
  formFactorOptions_.showProgress = false;
  caster_ = makeEmbreeRayCaster(baseMesh_);
  // Addresses, not ids, name cells in the table's file: ids depend on the order of refinement.
  table_ = std::make_unique<FormFactorTable>(mesh_.nodeMesh(), *caster_, formFactorOptions_,
                                             [this](std::uint32_t id) { return mesh_.address(id); });
  epsilon_ = rayEpsilon(baseMesh_);
  activeMesh_ = baseMesh_;
  if (!cacheDirectory_.empty()) loadTable();
}

void AdaptiveMethod::loadTable() {
  tableKey_ = formFactorTableKey(scene_, options_.quadtree, formFactorOptions_);
  tableFile_.path = formFactorTablePath(cacheDirectory_, tableKey_);
  Timer timer;
  Result<std::size_t> loaded = table_->load(tableFile_.path, tableKey_);
  tableFile_.loadSeconds = timer.seconds();
  if (loaded) {
    tableFile_.loaded = true;
    tableFile_.pairsInFile = *loaded;
    fileCurrent_ = true;
    estimatedAtFile_ = table_->pairsEstimated();
    return;
  }
  // No file is the ordinary first run; anything else (unreadable, damaged, stale) is reported and
  // ignored: the table starts empty and saveCache() replaces the file.
  if (!cachefile::isMissing(tableFile_.path)) warning(loaded.error().message + "; recomputing");
}

Status AdaptiveMethod::saveCache() {
  if (tableFile_.path.empty()) return Ok{};
  if (fileCurrent_ && table_->pairsEstimated() == estimatedAtFile_) return Ok{};
  Timer timer;
  Result<std::size_t> saved = table_->save(tableFile_.path, tableKey_);
  tableFile_.saveSeconds += timer.seconds();
  if (!saved) {
    warning(saved.error().message + "; form-factor table not cached");
    return saved.error();
  }
  tableFile_.saved = true;
  tableFile_.pairsSaved = *saved;
  fileCurrent_ = true;
  estimatedAtFile_ = table_->pairsEstimated();
  return Ok{};
}

bool AdaptiveMethod::crossesSpotEdge(const Light& light, const PatchCorners& corners, const Vec3& normal) {
  if (light.kind != LightKind::Spot) return false;
  int lit = 0, facing = 0;
  for (const Vec3& c : insetCorners(corners)) {
    if (dot(light.position - c, normal) <= 0) continue;
    ++facing;
    lit += spotFalloff(light, c - light.position) > 0;
  }
  if (facing == 0) return false;
  if (lit > 0 && lit < static_cast<int>(corners.size())) return true;
  // A beam narrower than the cell can land inside it with every corner dark.
  return lit == 0 && dot(light.direction, normal) < 0 && rayHitsQuad(light.position, light.direction, corners);
}

bool AdaptiveMethod::crossesShadowEdge(const Light& light, const PatchCorners& corners, const Vec3& normal) const {
  int tested = 0, visible = 0;
  for (const Vec3& c : insetCorners(corners)) {
    if (unshadowedIrradiance(light, c, normal, scene_.metresPerUnit).maxComponent() <= 0) continue;
    ++tested;
    visible += irradiance(light, c, normal, *caster_, epsilon_, scene_.metresPerUnit).maxComponent() > 0;
  }
  return visible > 0 && visible < tested;
}

bool AdaptiveMethod::mustSplit(std::uint32_t node, const std::vector<Light>& lights) const {
  if (mesh_.node(node).level >= options_.quadtree.maxLevel) return false;
  PatchCorners corners = mesh_.nodeMesh().corners(node);
  const Vec3& normal = mesh_.nodeMesh().patches[node].normal;
  for (const Light& light : lights) {
    if (options_.refineAtSpotEdges && crossesSpotEdge(light, corners, normal)) return true;
    if (options_.refineAtShadowEdges && crossesShadowEdge(light, corners, normal)) return true;
  }
  return false;
}

void AdaptiveMethod::refineNode(std::uint32_t node, SolveReport& report) {
  if (!mesh_.refine(node)) return;
  ++report.refined;
  nodeRadiosity_.resize(mesh_.numNodes());
  const auto first = static_cast<std::uint32_t>(mesh_.node(node).firstChild);
  for (std::uint32_t k = 0; k < 4; ++k) nodeRadiosity_[first + k] = nodeRadiosity_[node];
}

void AdaptiveMethod::adapt(std::uint32_t node, const std::vector<Light>& lights, const std::vector<char>& steep,
                            SolveReport& report) {
  // Nodes created during this refine have no solution yet, so they are never steep.
  auto isSteep = [&](std::uint32_t id) { return id < steep.size() && steep[id]; };
  const QuadNode n = mesh_.node(node);
  if (mustSplit(node, lights)) {
    if (n.active) refineNode(node, report);
    const auto first = static_cast<std::uint32_t>(mesh_.node(node).firstChild);
    for (std::uint32_t k = 0; k < 4; ++k) adapt(first + k, lights, steep, report);
    return;
  }
  if (!n.active) {
    const auto first = static_cast<std::uint32_t>(n.firstChild);
    for (std::uint32_t k = 0; k < 4; ++k) adapt(first + k, lights, steep, report);
    // Merge four leaves that no criterion holds apart (half the threshold: hysteresis).
    bool leaves = true;
    Rgb children[4];
    double area = 0;
    Rgb weighted;
    for (std::uint32_t k = 0; k < 4; ++k) {
      leaves &= mesh_.node(first + k).active && !isSteep(first + k);
      children[k] = nodeRadiosity_[first + k];
      double a = mesh_.nodeMesh().patches[first + k].area;
      weighted += children[k] * a;
      area += a;
    }
    double mean = 0;
    for (const Rgb& c : children) mean += c.luminance() / 4;
    bool similar = options_.gradientThreshold <= 0 ||
                   luminanceRange(children) <= 0.5 * options_.gradientThreshold * std::fmax(mean, 1e-300);
    if (leaves && similar) {
      mesh_.coarsen(node);
      nodeRadiosity_[node] = weighted / area;
      ++report.coarsened;
    }
    return;
  }
  if (isSteep(node)) refineNode(node, report);
}

// Leaves whose corner radiosity spans more than the threshold × the mean, judged on the last
// solution (one value per active node); none before the first solve.
std::vector<char> AdaptiveMethod::steepLeaves(const std::vector<Rgb>& radiosity) const {
  std::vector<char> steep(mesh_.numNodes(), 0);
  if (options_.gradientThreshold <= 0 || radiosity.size() != mesh_.activeNodes().size()) return steep;
  double meanLuminance = 0, totalArea = 0;
  for (std::size_t k = 0; k < radiosity.size(); ++k) {
    double a = activeMesh_.patches[k].area;
    meanLuminance += radiosity[k].luminance() * a;
    totalArea += a;
  }
  meanLuminance /= totalArea;
  std::vector<std::array<Rgb, 4>> corners = mesh_.cornerRadiosity(radiosity);
  for (std::size_t k = 0; k < corners.size(); ++k)
    steep[mesh_.activeNodes()[k]] = luminanceRange(corners[k]) > options_.gradientThreshold * meanLuminance;
  return steep;
}

Result<bool> AdaptiveMethod::refine(const std::vector<Light>& lights, std::vector<Rgb>& radiosity, SolveReport& report) {
  Timer adaptTimer;
  nodeRadiosity_.resize(mesh_.numNodes());
  if (radiosity.size() == mesh_.activeNodes().size())
    for (std::size_t k = 0; k < radiosity.size(); ++k) nodeRadiosity_[mesh_.activeNodes()[k]] = radiosity[k];
  const std::vector<char> steep = steepLeaves(radiosity);
  for (std::uint32_t id = 0, base = static_cast<std::uint32_t>(mesh_.numNodes()); id < base; ++id)
    if (mesh_.node(id).parent < 0) adapt(id, lights, steep, report);
  report.adaptSeconds += adaptTimer.seconds();

  const std::vector<std::uint32_t>& active = mesh_.activeNodes();
  const bool changed = active != lastActive_ || !transport_;
  if (changed) {
    Timer ffTimer;
    const std::uint64_t estimatedBefore = table_->pairsEstimated(), reusedBefore = table_->pairsReused(),
                        loadedBefore = table_->pairsLoaded();
    // The active set's dense matrix is assembled whole, and its new pairs join the master table.
    const double bytes = table_->assemblyBytes(active.size());
    if (const double budget = memoryBudgetBytes(memoryLimitBytes_); budget > 0 && bytes > budget)
      return Error{memoryExceeded("the form-factor matrix and new table pairs of " + std::to_string(active.size()) + " active cells", bytes, memoryLimitBytes_) +
                   "; lower --max-level, raise --base-edge or --gradient-threshold, or --memory-limit to allow more"};
    auto F = std::make_shared<FormFactorMatrix>(table_->matrix(active));
    if (normalizeRows_) normalizeRows(*F);
    activeMesh_ = mesh_.activeMesh();
    rowsBounded_ = boundRowSums(*F, patchAlbedo(scene_, activeMesh_));
    report.pairsEstimated += table_->pairsEstimated() - estimatedBefore;
    report.pairsReused += table_->pairsReused() - reusedBefore;
    report.pairsLoaded += table_->pairsLoaded() - loadedBefore;
    transport_ = std::make_shared<DenseTransport>(std::move(F));
    lastActive_ = active;
    report.formFactorSeconds += ffTimer.seconds();
  }
  radiosity.resize(active.size());
  for (std::size_t k = 0; k < active.size(); ++k) radiosity[k] = nodeRadiosity_[active[k]];
  return changed;
}

std::vector<Rgb> AdaptiveMethod::vertexValues(const std::vector<Rgb>& perElement) const {
  return mesh_.fineVertexRadiosity(perElement);
}

void AdaptiveMethod::addStats(Stats& stats) const {
  stats.add("mesh", "mesh", std::string("adaptive quad-tree"));
  stats.add("base_edge_length", "coarsest cell edge", options_.quadtree.baseEdgeLength, "scene units");
  stats.add("max_level", "deepest level", static_cast<std::int64_t>(options_.quadtree.maxLevel));
  stats.add("patches", "active cells (patches)", static_cast<std::int64_t>(mesh_.activeNodes().size()));
  stats.add("cells_created", "cells ever created", static_cast<std::int64_t>(mesh_.numNodes()));
  stats.add("formfactor_method", "form-factor method", formFactorMethodName(formFactorOptions_.method));
  stats.add("pairs_estimated", "cell pairs estimated (master table)", static_cast<std::int64_t>(table_->pairsEstimated()));
  stats.add("pairs_reused", "cell pairs reused from the table", static_cast<std::int64_t>(table_->pairsReused()));
  stats.add("pairs_loaded", "cell pairs loaded from the table file", static_cast<std::int64_t>(table_->pairsLoaded()));
  stats.add("rows_bounded", "form-factor rows scaled down to sum 1 (last matrix)", static_cast<std::int64_t>(rowsBounded_));
  std::string cache;
  if (tableFile_.path.empty()) {
    cache = "off";
  } else {
    if (tableFile_.loaded) cache = "loaded " + tableFile_.path + " (" + std::to_string(tableFile_.pairsInFile) + " pairs)";
    if (tableFile_.saved)
      cache += (cache.empty() ? "" : "; ") + ("saved " + tableFile_.path + " (" + std::to_string(tableFile_.pairsSaved) + " pairs)");
    if (cache.empty()) cache = "not saved: " + tableFile_.path;
  }
  stats.add("formfactor_cache", "form-factor table file", cache);
  stats.add("formfactor_cache_seconds", "table file load + save time", tableFile_.loadSeconds + tableFile_.saveSeconds, "s");
}

}  // namespace lambert
