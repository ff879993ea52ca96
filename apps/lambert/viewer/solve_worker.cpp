#include "viewer/solve_worker.h"

#include <algorithm>
#include <cmath>

#include "lambert/core/parallel.h"
#include "lambert/core/timer.h"
#include "lambert/light/emission.h"
#include "lambert/light/lights.h"
#include "lambert/mesh/vertex_radiosity.h"
#include "lambert/render/solution_image.h"
#include "lambert/render/tonemap.h"

namespace lambert::viewer {
namespace {

void put(float (&out)[3], const Vec3& v) {
  out[0] = static_cast<float>(v.x), out[1] = static_cast<float>(v.y), out[2] = static_cast<float>(v.z);
}
void put(float (&out)[3], const Rgb& c) {
  out[0] = static_cast<float>(c.r), out[1] = static_cast<float>(c.g), out[2] = static_cast<float>(c.b);
}

// The corners of every element's triangles (a quad's fan), as element and corner index.
template <class Corner>
std::vector<Corner> triangleCorners(const Mesh& mesh) {
  std::vector<Corner> corners;
  corners.reserve(mesh.numPatches() * 6);
  for (std::uint32_t p = 0; p < mesh.numPatches(); ++p) {
    const Patch& patch = mesh.patches[p];
    for (std::uint32_t t = 0; t + 2 < patch.numCorners; ++t)
      for (std::uint32_t k : {0u, t + 1, t + 2}) corners.push_back({p, patch.vertices[k]});
  }
  return corners;
}

// Whether `light` is visible from `origin` (a point lifted off a surface of normal n at x), as the
// software renderer's shadow ray decides (light/lights.cpp: irradiance). Where the light gives
// the point nothing anyway (outside a spot's cone, or behind the surface) it counts as visible:
// no ray is needed there, and no shadow edge is drawn finer where it cannot be seen.
float lightVisibility(const Light& light, const Vec3& x, const Vec3& n, const Vec3& origin, const RayCaster& caster) {
  // A sky is not one direction: the pixel shader cannot draw it (it has no power there, see
  // mesh_renderer.cpp), so there is no visibility to trace.
  if (light.kind == LightKind::Sky) return 1.0f;
  if (unshadowedIrradiance(light, x, n, 1.0).maxComponent() <= 0) return 1.0f;
  Ray shadow = light.kind == LightKind::Directional ? Ray{origin, -normalize(light.direction), 0, INFINITY}
                                                    : Ray{origin, light.position - origin, 0, 1 - 1e-7};
  return caster.occluded(shadow) ? 0.0f : 1.0f;
}

// The visibility of each light from each vertex, traced as the software renderer's shadow ray is
// (lights.cpp: irradiance), from the vertex moved a little toward its patches (mesh/
// vertex_radiosity.h: vertexSites), so that a vertex on a crease does not see through the wall
// it touches. Vertices are never shared across surfaces, so one normal per vertex serves.
std::vector<float> traceVisibility(const Mesh& mesh, const std::vector<Light>& lights, const RayCaster& caster) {
  const std::size_t lightCount = std::min<std::size_t>(lights.size(), kMaxPixelLights);
  const double epsilon = rayEpsilon(mesh);
  const std::vector<VertexSite> sites = vertexSites(mesh, 10 * epsilon);
  std::vector<float> visibility(sites.size() * kMaxPixelLights, 1.0f);
  parallelFor(0, sites.size(), [&](std::size_t v) {
    const Vec3 origin = sites[v].point + sites[v].normal * epsilon;
    for (std::size_t l = 0; l < lightCount; ++l)
      visibility[v * kMaxPixelLights + l] = lightVisibility(lights[l], sites[v].point, sites[v].normal, origin, caster);
  }, 256);
  return visibility;
}

// Shadow edges drawn finer than the mesh: a triangle whose corners disagree on a light's
// visibility is split at its edge midpoints, and again, kShadowLevels times, with the visibility
// traced at every new corner and the radiosity interpolated linearly, so a shadow's edge steps by
// an eighth of an element instead of a whole one (the software renderer traces every pixel).
constexpr int kShadowLevels = 3;

bool visibilityDiffers(const DrawVertex& a, const DrawVertex& b, const DrawVertex& c, std::size_t lightCount) {
  for (std::size_t l = 0; l < lightCount; ++l)
    if (a.visibility[l] != b.visibility[l] || a.visibility[l] != c.visibility[l]) return true;
  return false;
}

struct ShadowTracer {
  const std::vector<Light>& lights;
  const RayCaster& caster;
  double epsilon;
  std::size_t lightCount;

  Vec3 at(const float (&p)[3]) const { return {p[0], p[1], p[2]}; }

  // The corner halfway between a and b, seen from inside the triangle (toward `centre`, as
  // vertexSites does, so a midpoint on a crease does not look through the wall it touches).
  DrawVertex midpoint(const DrawVertex& a, const DrawVertex& b, const Vec3& centre) const {
    DrawVertex m = a;
    for (int k = 0; k < 3; ++k) {
      m.position[k] = 0.5f * (a.position[k] + b.position[k]);
      m.indirect[k] = 0.5f * (a.indirect[k] + b.indirect[k]);
      m.emitted[k] = 0.5f * (a.emitted[k] + b.emitted[k]);
    }
    const Vec3 x = at(m.position), n = at(m.normal);
    const Vec3 toCentre = centre - x;
    const double distance = length(toCentre);
    const Vec3 origin = (distance > 0 ? x + toCentre * (std::fmin(10 * epsilon, 0.5 * distance) / distance) : x) + n * epsilon;
    for (std::size_t l = 0; l < lightCount; ++l) m.visibility[l] = lightVisibility(lights[l], x, n, origin, caster);
    return m;
  }

  void split(const DrawVertex& a, const DrawVertex& b, const DrawVertex& c, int level, std::vector<DrawVertex>& out) const {
    if (level == 0 || !visibilityDiffers(a, b, c, lightCount)) {
      out.insert(out.end(), {a, b, c});
      return;
    }
    const Vec3 centre = (at(a.position) + at(b.position) + at(c.position)) / 3.0;
    const DrawVertex ab = midpoint(a, b, centre), bc = midpoint(b, c, centre), ca = midpoint(c, a, centre);
    split(a, ab, ca, level - 1, out);
    split(ab, b, bc, level - 1, out);
    split(ca, bc, c, level - 1, out);
    split(ab, bc, ca, level - 1, out);
  }
};

// Splits the triangles a shadow edge crosses (see kShadowLevels); the others stay as they are.
std::vector<DrawVertex> refineShadowEdges(std::vector<DrawVertex> triangles, const std::vector<Light>& lights, const RayCaster& caster,
                                          double epsilon) {
  const std::size_t lightCount = std::min<std::size_t>(lights.size(), kMaxPixelLights);
  const std::size_t count = triangles.size() / 3;
  std::vector<std::uint32_t> crossed;
  for (std::size_t t = 0; t < count; ++t)
    if (visibilityDiffers(triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2], lightCount)) crossed.push_back(static_cast<std::uint32_t>(t));
  if (crossed.empty()) return triangles;
  const ShadowTracer tracer{lights, caster, epsilon, lightCount};
  std::vector<std::vector<DrawVertex>> refined(crossed.size());
  parallelFor(0, crossed.size(), [&](std::size_t i) {
    const std::size_t t = crossed[i];
    tracer.split(triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2], kShadowLevels, refined[i]);
  }, 16);
  std::vector<DrawVertex> result;
  std::size_t size = triangles.size();
  for (const std::vector<DrawVertex>& r : refined) size += r.size();
  result.reserve(size);
  std::size_t next = 0;
  for (std::size_t t = 0; t < count; ++t) {
    if (next < crossed.size() && crossed[next] == t) {
      result.insert(result.end(), refined[next].begin(), refined[next].end());
      ++next;
    } else {
      result.insert(result.end(), triangles.begin() + static_cast<std::ptrdiff_t>(3 * t), triangles.begin() + static_cast<std::ptrdiff_t>(3 * t + 3));
    }
  }
  return result;
}

double percentileLuminance(const std::vector<Rgb>& values, double fraction) {
  if (values.empty()) return 0;
  std::vector<double> luminance(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) luminance[i] = values[i].luminance();
  std::size_t k = std::min(values.size() - 1, static_cast<std::size_t>(fraction * static_cast<double>(values.size())));
  std::nth_element(luminance.begin(), luminance.begin() + static_cast<std::ptrdiff_t>(k), luminance.end());
  return luminance[k];
}

}  // namespace

double steadyClockSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::vector<Light> LightAnimation::lightsAt(double clock) const {
  const double t = secondsAt(clock);
  std::vector<Light> lights;
  for (const Light& light : base) lights.push_back(t != 0 ? lightAtTime(light, t) : light);
  return lights;
}

std::shared_ptr<const Snapshot> previewSnapshot(const Scene& scene) {
  auto snapshot = std::make_shared<Snapshot>();
  auto edges = std::make_shared<std::vector<float>>();
  snapshot->preview = true;
  for (const Surface& surface : scene.surfaces) {
    const Rgb albedo = scene.materials.at(static_cast<std::size_t>(surface.material)).albedo;
    const Rgb emitted = meanEmittedRadiance(scene, surface) * kPi;
    for (const std::vector<std::uint32_t>& face : surfaceFaces(surface)) {
      std::vector<Vec3> corners = facePositions(surface, face);
      if (corners.size() < 3) continue;
      const Vec3 normal = normalize(cross(corners[1] - corners[0], corners[2] - corners[0]));
      for (std::size_t t = 1; t + 1 < corners.size(); ++t)
        for (std::size_t k : {std::size_t{0}, t, t + 1}) {
          DrawVertex v{};
          put(v.position, corners[k]);
          put(v.normal, normal);
          put(v.albedo, albedo);
          put(v.emitted, emitted);
          put(v.indirect, emitted);
          v.twinned = surface.twin >= 0 ? 1.0f : 0.0f;
          std::fill_n(v.visibility, kMaxPixelLights, 1.0f);
          snapshot->triangles.push_back(v);
        }
      for (std::size_t k = 0; k < corners.size(); ++k)
        for (const Vec3& x : {corners[k], corners[(k + 1) % corners.size()]})
          edges->insert(edges->end(), {static_cast<float>(x.x), static_cast<float>(x.y), static_cast<float>(x.z)});
    }
  }
  snapshot->edges = std::move(edges);
  snapshot->lights = scene.lights;
  return snapshot;
}

SolveWorker::SolveWorker(Scene scene, RadiosityOptions options, UpdateBudget budget, bool flat, BakeSettings bake)
    : scene_(std::move(scene)), options_(std::move(options)), budget_(budget), startTime_(steadyClockSeconds()), flat_(flat),
      bake_(std::move(bake)) {
  bake_.probeOptions.showProgress = false;  // the panel shows progress
  animation_.base = scene_.lights;
  thread_ = std::thread([this] { run(); });
}

SolveWorker::~SolveWorker() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void SolveWorker::setAnimation(LightAnimation animation) {
  {
    std::lock_guard lock(mutex_);
    animation_ = std::move(animation);
  }
  wake_.notify_all();
}

void SolveWorker::setFlat(bool flat) {
  {
    std::lock_guard lock(mutex_);
    if (flat_ == flat) return;
    flat_ = flat;
    flatChanged_ = true;
  }
  wake_.notify_all();
}

void SolveWorker::setBaking(bool lightmaps, bool probes) {
  {
    std::lock_guard lock(mutex_);
    if (bake_.lightmaps == lightmaps && bake_.probes == probes) return;
    bake_.lightmaps = lightmaps;
    bake_.probes = probes;
  }
  wake_.notify_all();
}

std::shared_ptr<const LightmapFrame> SolveWorker::latestLightmaps() const {
  std::lock_guard lock(mutex_);
  return lightmaps_;
}

std::shared_ptr<const ProbeFrame> SolveWorker::latestProbes() const {
  std::lock_guard lock(mutex_);
  return probes_;
}

std::string SolveWorker::baking() const {
  std::lock_guard lock(mutex_);
  return baking_;
}

bool SolveWorker::bakeDue() const {
  const std::vector<Light>& lights = engine_->lights();
  return (bake_.lightmaps && (!lightmaps_ || lightmaps_->lights != lights)) || (bake_.probes && (!probes_ || probes_->lights != lights));
}

Result<std::vector<Image>> SolveWorker::refreshLightmaps(const SolutionView& view) {
  // After the first bake, the lightmaps follow each re-solve through the updater (one sparse
  // product over the solution's change, bake/lightmap_updates.h) instead of a new bake; where it
  // cannot (the hierarchy was refined again), a bake starts it afresh.
  if (updater_ && updater_->update(view)) return updater_->lightmaps();
  LightmapBakeOptions options;
  options.uvs = bake_.uvs;
  options.showProgress = false;
  Result<BakedLightmaps> baked = bakeLightmaps(view, *uvs_, options);
  if (!baked) return baked.error();
  Result<LightmapUpdater> updater = LightmapUpdater::create(view, *baked);
  if (!updater) return updater.error();
  updater_ = std::make_unique<LightmapUpdater>(std::move(*updater));
  return std::move(baked->irradiance);
}

bool SolveWorker::bake() {
  const SolutionView& view = engine_->solution();
  bool lightmaps, probes;
  {
    std::lock_guard lock(mutex_);
    lightmaps = bake_.lightmaps && (!lightmaps_ || lightmaps_->lights != engine_->lights());
    probes = bake_.probes && (!probes_ || probes_->lights != engine_->lights());
  }
  auto fail = [&](const std::string& message) {
    std::lock_guard lock(mutex_);
    error_ = message;
    baking_.clear();
    return false;
  };
  if (lightmaps) {
    {
      std::lock_guard lock(mutex_);
      baking_ = "baking lightmaps...";
    }
    Timer timer;
    if (!uvs_) {
      Result<LightmapUvs> uvs = lightmapUvs(scene_, bake_.uvs);
      if (!uvs) return fail("lightmaps: " + uvs.error().message);
      uvs_ = std::make_shared<const LightmapUvs>(std::move(*uvs));
    }
    Result<std::vector<Image>> irradiance = refreshLightmaps(view);
    if (!irradiance) return fail("lightmaps: " + irradiance.error().message);
    auto frame = std::make_shared<LightmapFrame>();
    frame->lights = engine_->lights();
    frame->uvs = uvs_;
    frame->irradiance = std::move(*irradiance);
    frame->seconds = timer.seconds();
    std::lock_guard lock(mutex_);
    frame->version = ++bakeVersion_;
    figures_.lightmapBakes += 1;
    figures_.lightmapSeconds += frame->seconds;
    lightmaps_ = std::move(frame);
  }
  if (probes) {
    {
      std::lock_guard lock(mutex_);
      baking_ = "baking light probes...";
    }
    Timer timer;
    Result<ProbeVolume> volume = bakeProbes(view, bake_.probeOptions);
    if (!volume) return fail("probes: " + volume.error().message);
    auto frame = std::make_shared<ProbeFrame>();
    frame->lights = engine_->lights();
    frame->volume = std::move(*volume);
    std::lock_guard lock(mutex_);
    frame->version = ++bakeVersion_;
    figures_.probeBakes += 1;
    figures_.probeSeconds += timer.seconds();
    probes_ = std::move(frame);
  }
  std::lock_guard lock(mutex_);
  baking_.clear();
  return true;
}

std::shared_ptr<const Snapshot> SolveWorker::latest() const {
  std::lock_guard lock(mutex_);
  return latest_;
}

std::string SolveWorker::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

double SolveWorker::secondsSinceStart() const { return steadyClockSeconds() - startTime_; }

Stats SolveWorker::finish(WorkerFigures& figures) {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  figures = figures_;
  return engine_ ? engine_->stats() : Stats{};
}

void SolveWorker::run() {
  Result<std::unique_ptr<Radiosity>> created = Radiosity::create(scene_, options_);
  if (!created) {
    std::lock_guard lock(mutex_);
    error_ = created.error().message;
    return;
  }
  engine_ = std::move(*created);
  ready_ = true;

  // The hierarchical method's vertex solution is a final gather at every vertex: it waits until
  // the solution has converged and the lights have stopped (meanwhile the elements' values are
  // interpolated), then comes as an update of its own.
  const bool gathersAtVertices = options_.meshing == MeshStrategy::Hierarchical;
  bool needsSolve = true, meshStale = true, gatherPending = false;
  SolveReport last;
  double lastUpdate = 0;
  while (true) {
    bool lightsChanged = false, republish = false;
    {
      std::unique_lock lock(mutex_);
      // Asleep while converged, until the lights, the animation or the shading change.
      // Lightmaps and probes are baked from each converged solution before the next lights are
      // taken (points gather over the links, not at the vertices, so the vertex gather need not
      // come first): moves that come during a bake are taken together by the next solve, which
      // is baked in turn once it converges, so the baked light follows a moving light.
      const bool converged = !needsSolve && last.converged;
      wake_.wait(lock, [&] {
        return stop_ || flatChanged_ || needsSolve || gatherPending || animation_.playing ||
               animation_.lightsAt(steadyClockSeconds()) != engine_->lights() || (converged && bakeDue());
      });
      if (stop_) return;
      if (converged && bakeDue()) {
        lock.unlock();
        if (!bake()) return;
        continue;
      }
      if (animation_.playing && budget_.maxUpdatesPerSecond > 0) {
        const double wait = lastUpdate + 1 / budget_.maxUpdatesPerSecond - steadyClockSeconds();
        if (wait > 0 && wake_.wait_for(lock, std::chrono::duration<double>(wait), [&] { return stop_; })) return;
      }
      lastUpdate = steadyClockSeconds();
      if (std::vector<Light> lights = animation_.lightsAt(steadyClockSeconds()); lights != engine_->lights()) {
        engine_->setLights(std::move(lights));
        lightsChanged = needsSolve = true;
        gatherPending = false;
        iterationsForLights_ = 0;
      }
      if (flatChanged_) {
        flatChanged_ = false;
        meshStale = republish = true;
      }
    }
    Timer update;
    double solveSeconds = 0;
    bool gathered = !gathersAtVertices;
    if (needsSolve) {
      const std::size_t elementsBefore = engine_->solution().mesh().numPatches();
      Result<SolveReport> report = engine_->solve(budget_.solve);
      if (!report) {
        std::lock_guard lock(mutex_);
        error_ = report.error().message;
        return;
      }
      last = *report;
      solveSeconds = update.seconds();
      iterationsForLights_ += report->iterations;
      needsSolve = !report->converged;
      gatherPending = gathersAtVertices && report->converged;
      // Refinement (hierarchical in its first solve, adaptive in every one) changes the elements.
      if (report->elements != elementsBefore || options_.meshing == MeshStrategy::Adaptive) meshStale = true;
    } else if (gatherPending) {
      gathered = true;
      gatherPending = false;
    } else if (!republish) {
      continue;
    } else {
      gathered = gathered || last.converged;
    }
    Timer snapshot;
    publish(*engine_, last, meshStale, meshStale || lightsChanged, gathered);
    meshStale = false;
    std::lock_guard lock(mutex_);
    figures_.updates += 1;
    figures_.solveSeconds += solveSeconds;
    figures_.snapshotSeconds += snapshot.seconds();
    figures_.maxUpdateSeconds = std::max(figures_.maxUpdateSeconds, update.seconds());
    if (lightsChanged) {
      figures_.lightUpdates += 1;
      figures_.lightUpdateSeconds += update.seconds();
    }
  }
}

void SolveWorker::publish(const Radiosity& engine, const SolveReport& report, bool meshStale, bool visibilityStale, bool gathered) {
  const SolutionView& view = engine.solution();
  bool flat;
  {
    std::lock_guard lock(mutex_);
    flat = flat_;
  }
  auto snapshot = std::make_shared<Snapshot>();
  snapshot->flat = flat;
  const Mesh& mesh = flat ? view.mesh() : view.vertexMesh();
  // Flat: each element in its own value. Gouraud: the continuous vertex values every consumer
  // reads (the hierarchical method's final gather), so the picture is the exported solution.
  // The vertex solution itself, or (before the hierarchical method's final gather) the elements'
  // values interpolated.
  std::vector<Rgb> indirect = flat       ? view.indirectRadiosity()
                              : gathered ? view.vertexValues(VertexQuantity::IndirectRadiosity)
                                         : view.vertexValues(view.indirectRadiosity());
  const std::vector<Rgb>& albedo = flat ? view.albedo() : view.vertexMeshAlbedo();
  if (meshStale) {
    corners_ = triangleCorners<Corner>(mesh);
    emitted_ = flat ? view.emitted() : view.vertexValues(view.emitted());
    auto edges = std::make_shared<std::vector<float>>();
    edges->reserve(mesh.numPatches() * 24);
    for (std::size_t p = 0; p < mesh.numPatches(); ++p) {
      const Patch& patch = mesh.patches[p];
      for (std::uint32_t k = 0; k < patch.numCorners; ++k)
        for (std::uint32_t end : {k, (k + 1) % patch.numCorners}) {
          const Vec3& x = mesh.positions[patch.vertices[end]];
          edges->insert(edges->end(), {static_cast<float>(x.x), static_cast<float>(x.y), static_cast<float>(x.z)});
        }
    }
    edges_ = std::move(edges);
  }
  const std::vector<Corner>& corners = corners_;
  const std::vector<Rgb>& emitted = emitted_;
  if (visibilityStale) visibility_ = traceVisibility(mesh, view.lights(), view.caster());
  snapshot->triangles.resize(corners.size());
  parallelFor(0, corners.size(), [&](std::size_t i) {
    const Corner& c = corners[i];
    const Patch& patch = mesh.patches[c.patch];
    const std::size_t value = flat ? c.patch : c.vertex;
    DrawVertex& v = snapshot->triangles[i];
    put(v.position, mesh.positions[c.vertex]);
    put(v.normal, patch.normal);
    put(v.albedo, albedo[c.patch]);
    put(v.indirect, indirect[value]);
    put(v.emitted, emitted[value]);
    v.twinned = patch.twinned ? 1.0f : 0.0f;
    std::copy_n(visibility_.begin() + static_cast<std::ptrdiff_t>(c.vertex * kMaxPixelLights), kMaxPixelLights, v.visibility);
  }, 1024);
  snapshot->triangles = refineShadowEdges(std::move(snapshot->triangles), view.lights(), view.caster(), rayEpsilon(mesh));
  snapshot->edges = edges_;
  snapshot->lights = view.lights();
  snapshot->ambient = view.ambientRadiosity();
  snapshot->maxRadiosity = percentileLuminance(view.radiosity(), 0.99);
  snapshot->unshotFraction = report.unshotFraction;
  snapshot->converged = report.converged;
  snapshot->settled = report.converged && (gathered || flat);
  snapshot->elements = view.mesh().numPatches();
  snapshot->iterations = iterationsForLights_;
  // Measured on a small flat-shaded image (the exposure hardly depends on the shading), at most
  // a few times a second while the solve runs and once more when it converges.
  const double now = steadyClockSeconds();
  if (!scene_.exposureStops && (report.converged || autoExposureAt_ < 0 || now - autoExposureAt_ > 0.25)) {
    SolutionImageOptions small;
    small.width = 96;
    small.height = 54;
    small.supersample = 1;
    small.shading = Shading::Flat;
    small.camera = scene_.camera;
    autoExposureStops_ = autoExposureStops(renderSolution(view, small));
    autoExposureAt_ = now;
  }
  snapshot->autoExposureStops = autoExposureStops_;
  std::lock_guard lock(mutex_);
  snapshot->version = ++version_;
  latest_ = std::move(snapshot);
}

}  // namespace lambert::viewer
