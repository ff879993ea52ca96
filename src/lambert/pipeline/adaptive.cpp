#include "lambert/pipeline/adaptive.h"

#include <cmath>
#include <cstdio>

#include "lambert/core/timer.h"
#include "lambert/formfactor/cache_file.h"
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

Result<std::unique_ptr<AdaptiveRadiosity>> AdaptiveRadiosity::create(const Scene& scene, const AdaptiveOptions& options) {
  // The master table is filled a pair at a time; the hemi-cube and hemisphere methods give rows.
  if (!isPairMethod(options.formFactors.method))
    return Error{"adaptive meshing needs a pair-wise form-factor method (mc or point), not '" +
                 formFactorMethodName(options.formFactors.method) + "'"};
  Result<AdaptiveMesh> mesh = AdaptiveMesh::build(scene, options.quadtree);
  if (!mesh) return mesh.error();
  return std::unique_ptr<AdaptiveRadiosity>(new AdaptiveRadiosity(scene, std::move(*mesh), options));
}

AdaptiveRadiosity::AdaptiveRadiosity(const Scene& scene, AdaptiveMesh mesh, const AdaptiveOptions& options)
    : scene_(scene), options_(options), mesh_(std::move(mesh)), baseMesh_(mesh_.activeMesh()) {
  caster_ = makeEmbreeRayCaster(baseMesh_);
  // Addresses, not ids, name cells in the table's file: ids depend on the order of refinement.
  table_ = std::make_unique<FormFactorTable>(mesh_.nodeMesh(), *caster_, options.formFactors,
                                             [this](std::uint32_t id) { return mesh_.address(id); });
  epsilon_ = rayEpsilon(baseMesh_);
  if (!options.cacheDirectory.empty()) loadTable();
}

void AdaptiveRadiosity::warnAboutTable(const std::string& line) {
  std::fprintf(stderr, "lambert: warning: %s\n", line.c_str());
  if (!tableFile_.warning.empty()) tableFile_.warning += '\n';
  tableFile_.warning += line;
}

void AdaptiveRadiosity::loadTable() {
  tableKey_ = formFactorTableKey(scene_, options_.quadtree, options_.formFactors);
  tableFile_.path = formFactorTablePath(options_.cacheDirectory, tableKey_);
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
  // ignored: the table starts empty and saveTable() replaces the file.
  if (!cachefile::isMissing(tableFile_.path)) warnAboutTable(loaded.error().message + "; recomputing");
}

Status AdaptiveRadiosity::saveTable() {
  if (tableFile_.path.empty()) return Ok{};
  if (fileCurrent_ && table_->pairsEstimated() == estimatedAtFile_) return Ok{};
  Timer timer;
  Result<std::size_t> saved = table_->save(tableFile_.path, tableKey_);
  tableFile_.saveSeconds += timer.seconds();
  if (!saved) {
    warnAboutTable(saved.error().message + "; form-factor table not cached");
    return saved.error();
  }
  tableFile_.saved = true;
  tableFile_.pairsSaved = *saved;
  fileCurrent_ = true;
  estimatedAtFile_ = table_->pairsEstimated();
  return Ok{};
}

bool AdaptiveRadiosity::crossesSpotEdge(const Light& light, const PatchCorners& corners, const Vec3& normal) {
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

bool AdaptiveRadiosity::crossesShadowEdge(const Light& light, const PatchCorners& corners, const Vec3& normal) const {
  int tested = 0, visible = 0;
  for (const Vec3& c : insetCorners(corners)) {
    if (unshadowedIrradiance(light, c, normal, scene_.metresPerUnit).maxComponent() <= 0) continue;
    ++tested;
    visible += irradiance(light, c, normal, *caster_, epsilon_, scene_.metresPerUnit).maxComponent() > 0;
  }
  return visible > 0 && visible < tested;
}

bool AdaptiveRadiosity::mustSplit(std::uint32_t node, const std::vector<Light>& lights) const {
  if (mesh_.node(node).level >= options_.quadtree.maxLevel) return false;
  PatchCorners corners = mesh_.nodeMesh().corners(node);
  const Vec3& normal = mesh_.nodeMesh().patches[node].normal;
  for (const Light& light : lights) {
    if (options_.refineAtSpotEdges && crossesSpotEdge(light, corners, normal)) return true;
    if (options_.refineAtShadowEdges && crossesShadowEdge(light, corners, normal)) return true;
  }
  return false;
}

void AdaptiveRadiosity::refineNode(std::uint32_t node, AdaptiveUpdate& update) {
  if (!mesh_.refine(node)) return;
  ++update.refined;
  nodeRadiosity_.resize(mesh_.numNodes());
  const auto first = static_cast<std::uint32_t>(mesh_.node(node).firstChild);
  for (std::uint32_t k = 0; k < 4; ++k) nodeRadiosity_[first + k] = nodeRadiosity_[node];
}

void AdaptiveRadiosity::adapt(std::uint32_t node, const std::vector<Light>& lights, const std::vector<char>& steep,
                              AdaptiveUpdate& update) {
  // Nodes created during this update have no solution yet, so they are never steep.
  auto isSteep = [&](std::uint32_t id) { return id < steep.size() && steep[id]; };
  const QuadNode n = mesh_.node(node);
  if (mustSplit(node, lights)) {
    if (n.active) refineNode(node, update);
    const auto first = static_cast<std::uint32_t>(mesh_.node(node).firstChild);
    for (std::uint32_t k = 0; k < 4; ++k) adapt(first + k, lights, steep, update);
    return;
  }
  if (!n.active) {
    const auto first = static_cast<std::uint32_t>(n.firstChild);
    for (std::uint32_t k = 0; k < 4; ++k) adapt(first + k, lights, steep, update);
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
    bool similar = options_.gradientThreshold <= 0 || luminanceRange(children) <= 0.5 * options_.gradientThreshold * std::fmax(mean, 1e-300);
    if (leaves && similar) {
      mesh_.coarsen(node);
      nodeRadiosity_[node] = weighted / area;
      ++update.coarsened;
    }
    return;
  }
  if (isSteep(node)) refineNode(node, update);
}

AdaptiveUpdate AdaptiveRadiosity::update(const std::vector<Light>& lights) {
  AdaptiveUpdate update;
  Timer adaptTimer;
  nodeRadiosity_.resize(mesh_.numNodes());
  // Leaves whose corner radiosity spans more than the threshold, from the last solution.
  std::vector<char> steep(mesh_.numNodes(), 0);
  if (options_.gradientThreshold > 0 && radiosity_.size() == mesh_.activeNodes().size()) {
    double meanLuminance = 0, totalArea = 0;
    for (std::size_t k = 0; k < radiosity_.size(); ++k) {
      double a = problem_.area[k];
      meanLuminance += radiosity_[k].luminance() * a;
      totalArea += a;
    }
    meanLuminance /= totalArea;
    std::vector<std::array<Rgb, 4>> corners = mesh_.cornerRadiosity(radiosity_);
    for (std::size_t k = 0; k < corners.size(); ++k)
      steep[mesh_.activeNodes()[k]] = luminanceRange(corners[k]) > options_.gradientThreshold * meanLuminance;
  }
  for (std::uint32_t id = 0, base = static_cast<std::uint32_t>(mesh_.numNodes()); id < base; ++id)
    if (mesh_.node(id).parent < 0) adapt(id, lights, steep, update);
  update.adaptSeconds = adaptTimer.seconds();

  const std::vector<std::uint32_t>& active = mesh_.activeNodes();
  Mesh activeMesh = mesh_.activeMesh();
  if (active != lastActive_ || !problem_.formFactors) {
    Timer ffTimer;
    std::uint64_t estimatedBefore = table_->pairsEstimated(), reusedBefore = table_->pairsReused(),
                  loadedBefore = table_->pairsLoaded();
    auto F = std::make_shared<FormFactorMatrix>(table_->matrix(active));
    if (options_.normalizeRows) normalizeRows(*F);
    update.pairsEstimated = table_->pairsEstimated() - estimatedBefore;
    update.pairsReused = table_->pairsReused() - reusedBefore;
    update.pairsLoaded = table_->pairsLoaded() - loadedBefore;
    problem_.formFactors = std::move(F);
    problem_.albedo = patchAlbedo(scene_, activeMesh);
    problem_.area.resize(active.size());
    for (std::size_t k = 0; k < active.size(); ++k) problem_.area[k] = activeMesh.patches[k].area;
    lastActive_ = active;
    update.formFactorSeconds = ffTimer.seconds();
  }

  Timer injectTimer;
  problem_.emitted = emittedRadiosity(scene_, activeMesh);
  injected_.assign(active.size(), Rgb{});
  for (const Light& light : lights) {
    std::vector<Rgb> in = injectedRadiosity(activeMesh, problem_.albedo,
                                            patchIrradiance(activeMesh, *caster_, light, scene_.metresPerUnit, options_.direct));
    for (std::size_t k = 0; k < active.size(); ++k) injected_[k] += in[k];
  }
  for (std::size_t k = 0; k < active.size(); ++k) problem_.emitted[k] += injected_[k];
  update.injectSeconds = injectTimer.seconds();

  Timer solveTimer;
  radiosity_.resize(active.size());
  for (std::size_t k = 0; k < active.size(); ++k) radiosity_[k] = nodeRadiosity_[active[k]];
  SolveOptions solve;
  solve.tolerance = options_.tolerance;
  update.iterations = makeSolver(SolverKind::GaussSeidel, solve)->solve(problem_, radiosity_).iterations;
  for (std::size_t k = 0; k < active.size(); ++k) nodeRadiosity_[active[k]] = radiosity_[k];
  update.solveSeconds = solveTimer.seconds();
  update.activeNodes = active.size();
  update.nodes = mesh_.numNodes();
  return update;
}

std::vector<Rgb> AdaptiveRadiosity::indirectRadiosity() const {
  std::vector<Rgb> indirect = radiosity_;
  for (std::size_t k = 0; k < indirect.size(); ++k) indirect[k] -= injected_[k];
  return indirect;
}

std::vector<Rgb> AdaptiveRadiosity::fineAlbedo() const { return patchAlbedo(scene_, mesh_.fineMesh()); }

}  // namespace lambert
