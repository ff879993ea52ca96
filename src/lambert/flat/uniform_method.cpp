#include "lambert/flat/uniform_method.h"


#include "lambert/core/memory.h"
#include "lambert/core/timer.h"
#include "lambert/flat/form_factor_cache.h"
#include "lambert/flat/table.h"
#include "lambert/geometry/coverage.h"
#include "lambert/light/emission.h"
#include "lambert/mesh/vertex_radiosity.h"

namespace lambert {

namespace {

double maxEdgeLength(const Scene& scene, const UniformMeshOptions& options) {
  return options.maxEdgeLength > 0 ? options.maxEdgeLength : edgeLengthForPatchCount(scene, options.targetPatches);
}

}  // namespace

Mesh uniformMesh(const Scene& scene, const UniformMeshOptions& options) {
  return subdivideScene(scene, maxEdgeLength(scene, options));
}

Result<std::unique_ptr<UniformMethod>> UniformMethod::create(const Scene& scene, const RadiosityOptions& options) {
  Timer meshTimer;
  const double maxEdge = maxEdgeLength(scene, options.uniform);
  Mesh mesh = subdivideScene(scene, maxEdge);
  // The n×n float matrix, which computing or loading it fills at once.
  const double n = static_cast<double>(mesh.numPatches()), bytes = n * n * sizeof(float);
  if (const double budget = memoryBudgetBytes(options.memoryLimitBytes); budget > 0 && bytes > budget)
    return Error{memoryExceeded("the dense form-factor matrix of " + std::to_string(mesh.numPatches()) + " patches", bytes,
                                options.memoryLimitBytes) +
                 "; use the hierarchical method (--method hierarchical: memory near-linear in the faces), fewer patches, or "
                 "--memory-limit to allow more"};
  return std::make_unique<UniformMethod>(scene, std::move(mesh), maxEdge, meshTimer.seconds(), options);
}

UniformMethod::UniformMethod(const Scene& scene, Mesh mesh, double maxEdge, double meshSeconds, const RadiosityOptions& options) : mesh_(std::move(mesh)) {
  const FormFactorOptions& ff = options.formFactors;
  stats_.add("mesh", "mesh", std::string("uniform bisection"));
  stats_.add("patches", "patches", static_cast<std::int64_t>(mesh_.numPatches()));
  stats_.add("vertices", "vertices", static_cast<std::int64_t>(mesh_.numVertices()));
  stats_.add("max_edge_length", "max edge length", maxEdge, "scene units");
  stats_.add("mesh_seconds", "mesh time", meshSeconds, "s");

  Timer bvhTimer;
  caster_ = makeEmbreeRayCaster(mesh_);
  stats_.add("bvh_seconds", "BVH build time", bvhTimer.seconds(), "s");
  measureOpenFractions(mesh_, *caster_);
  interpolation_ = std::make_unique<VertexInterpolation>(mesh_);  // after the open fractions it weighs by

  FormFactorStats ffStats;
  CachedFormFactors cached = cachedFormFactors(mesh_, *caster_, ff, options.cacheDirectory, &ffStats);
  auto F = std::make_shared<FormFactorMatrix>(std::move(cached.matrix));
  if (options.normalizeRows) normalizeRows(*F);
  const std::size_t rowsBounded = boundRowSums(*F, patchAlbedo(scene, mesh_));
  transport_ = std::make_shared<DenseTransport>(std::move(F));
  stats_.add("formfactor_method", "form-factor method", formFactorMethodName(ff.method));
  stats_.add("formfactor_cache", "form-factor cache",
             options.cacheDirectory.empty() ? std::string("off") : (cached.fromCache ? "loaded " : "saved ") + cached.path);
  if (ff.method == FormFactorMethod::AreaMonteCarlo)
    stats_.add("sample_pairs", "sample pairs per patch pair", static_cast<std::int64_t>(ff.samplePairs));
  if (ff.method == FormFactorMethod::Hemicube)
    stats_.add("hemicube_resolution", "hemi-cube resolution", static_cast<std::int64_t>(ff.hemicubeResolution), "px");
  if (ff.method == FormFactorMethod::HemisphereRays)
    stats_.add("hemisphere_rays", "rays per patch", static_cast<std::int64_t>(ff.hemisphereRays));
  stats_.add("pairs_evaluated", "patch pairs evaluated", static_cast<std::int64_t>(ffStats.pairsEvaluated));
  stats_.add("pairs_culled", "patch pairs culled", static_cast<std::int64_t>(ffStats.pairsCulled));
  stats_.add("rows_bounded", "form-factor rows scaled down to sum 1", static_cast<std::int64_t>(rowsBounded));
  stats_.add("visibility_rays", "visibility rays", static_cast<std::int64_t>(ffStats.visibilityRays));
  stats_.add("formfactor_seconds", "form-factor time", ffStats.seconds, "s");
  stats_.add("rays_per_second", "visibility rays per second",
             ffStats.seconds > 0 ? static_cast<double>(ffStats.visibilityRays) / ffStats.seconds : 0.0, "rays/s");
}

std::vector<Rgb> UniformMethod::vertexValues(const std::vector<Rgb>& perElement) const {
  return interpolation_->apply(perElement);
}

}  // namespace lambert
