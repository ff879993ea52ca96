#include "lambert/flat/form_factors.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <optional>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/core/progress.h"
#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"
#include "lambert/core/timer.h"
#include "lambert/flat/hemicube.h"
#include "lambert/formfactor/kernels.h"

namespace lambert {

std::string formFactorMethodName(FormFactorMethod method) {
  switch (method) {
    case FormFactorMethod::PointToPoint: return "point";
    case FormFactorMethod::AreaMonteCarlo: return "mc";
    case FormFactorMethod::Hemicube: return "hemicube";
    case FormFactorMethod::HemisphereRays: return "hemisphere";
  }
  return "?";
}

bool isPairMethod(FormFactorMethod method) {
  return method == FormFactorMethod::PointToPoint || method == FormFactorMethod::AreaMonteCarlo;
}

namespace {

// Whether any part of patch b lies strictly in front of patch a's plane.
bool anyCornerInFront(const Mesh& mesh, std::size_t a, std::size_t b, double epsilon) {
  const Patch& pa = mesh.patches[a];
  for (std::uint32_t v : mesh.cornerIndices(b))
    if (dot(mesh.positions[v] - pa.centroid, pa.normal) > epsilon) return true;
  return false;
}

double longestEdge(const Mesh& mesh, std::size_t patch) {
  PatchCorners c = mesh.corners(patch);
  double longest = 0;
  for (std::size_t k = 0; k < c.size(); ++k) longest = std::fmax(longest, lengthSquared(c[(k + 1) % c.size()] - c[k]));
  return std::sqrt(longest);
}

}  // namespace

PairFormFactors::PairFormFactors(const Mesh& mesh, const RayCaster& caster, const FormFactorOptions& options)
    : mesh_(mesh), caster_(caster), options_(options), epsilon_(rayEpsilon(mesh)) {
  LAMBERT_CHECK(options.samplePairs >= 1 && isPairMethod(options.method));
}

bool PairFormFactors::culled(std::size_t i, std::size_t j) const {
  return mesh_.patches[i].surface == mesh_.patches[j].surface || !anyCornerInFront(mesh_, i, j, epsilon_) ||
         !anyCornerInFront(mesh_, j, i, epsilon_);
}

double PairFormFactors::estimate(std::size_t i, std::size_t j) {
  return options_.method == FormFactorMethod::PointToPoint ? pointToPoint(i, j) : areaMonteCarlo(i, j);
}

Ray PairFormFactors::segment(const Vec3& x, const Vec3& xNormal, const Vec3& y, const Vec3& yNormal) const {
  Vec3 from = x + xNormal * epsilon_, to = y + yNormal * epsilon_;
  return Ray{from, to - from, 0, 1};
}

// Patches closer than twice their size: the kernel varies fastest across them, so their
// estimates carry most of the error (and the rows of F their sums' error).
bool PairFormFactors::nearField(std::size_t i, std::size_t j) const {
  double size = std::fmax(longestEdge(mesh_, i), longestEdge(mesh_, j));
  return lengthSquared(mesh_.patches[i].centroid - mesh_.patches[j].centroid) < 4 * size * size;
}

// The point-to-point method samples a triangle at its incircle centre; a quad has no incircle, so its centroid.
Vec3 PairFormFactors::seedSamplePoint(std::size_t patch) const {
  PatchCorners c = mesh_.corners(patch);
  return c.size() == 3 ? incenter({c[0], c[1], c[2]}) : mesh_.patches[patch].centroid;
}

double PairFormFactors::pointToPoint(std::size_t i, std::size_t j) {
  const Patch& pi = mesh_.patches[i];
  const Patch& pj = mesh_.patches[j];
  Vec3 x = seedSamplePoint(i), y = seedSamplePoint(j);
  double kernel = pointToPointKernel(x, pi.normal, y, pj.normal);
  if (kernel == 0 || caster_.occluded(segment(x, pi.normal, y, pj.normal))) return 0;
  return kernel * pj.area;
}

// F_ij ≈ F̄ · V̄: F̄ averages the analytic factor F(x_k → P_j) over K points x_k on i, and V̄ is
// the kernel-weighted visible fraction over the first M of them, each paired with a point y_k on
// j. Far pairs use K = M, where this is exactly 1/M Σ F(x_k → P_j) V(x_k, y_k); near pairs
// integrate the fast-varying kernel with nearFieldBoost × more points but trace no more rays.
double PairFormFactors::areaMonteCarlo(std::size_t i, std::size_t j) {
  const Patch& pi = mesh_.patches[i];
  const Patch& pj = mesh_.patches[j];
  const int rayCount = options_.samplePairs;
  const int kernelCount = rayCount * (nearField(i, j) ? options_.nearFieldBoost : 1);
  // Independent scrambles for the points on i and on j, paired through a shuffled index.
  Pcg32 rng(options_.seed, (static_cast<std::uint64_t>(i) << 32) | j);
  const std::uint32_t su = rng.nextUint(), sv = rng.nextUint(), tu = rng.nextUint(), tv = rng.nextUint(),
                      pairing = rng.nextUint();
  const auto sourceCorners = mesh_.corners(i), targetCorners = mesh_.corners(j);

  rays_.clear();
  kernels_.clear();
  double kernelSum = 0;
  const Vec3 targetPoint = targetCorners[0];
  const std::span<const Vec3> target = targetCorners;
  for (int k = 0; k < kernelCount; ++k) {
    auto [u, v] = scrambledZeroTwo(static_cast<std::uint32_t>(k), su, sv);
    Vec3 x = sampleConvexPolygon(sourceCorners, u, v);
    if (dot(x - targetPoint, pj.normal) <= 0) continue;  // behind j: j's front cannot reach x
    // The part of j above x's horizon: both the kernel and the visibility points live there, so
    // what the horizon hides is not counted again as occluded.
    Vec3 visible[5];
    std::size_t count = clipAbovePlane(target, x, pi.normal, visible);
    if (count < 3) continue;
    std::span<const Vec3> visiblePart(visible, count);
    double f = contourFormFactor(x, pi.normal, visiblePart);
    kernelSum += f;
    if (k >= rayCount || f <= 0) continue;
    auto [s, t] = scrambledZeroTwo(shuffledIndex(static_cast<std::uint32_t>(k), pairing), tu, tv);
    kernels_.push_back(f);
    rays_.push_back(segment(x, pi.normal, sampleConvexPolygon(visiblePart, s, t), pj.normal));
  }
  if (rays_.empty()) return 0;
  if (occludedCapacity_ < rays_.size()) {
    occludedCapacity_ = rays_.size();
    occluded_ = std::make_unique<bool[]>(occludedCapacity_);
  }
  caster_.occluded(rays_, std::span<bool>(occluded_.get(), rays_.size()));
  double tracedSum = 0, visibleSum = 0;
  for (std::size_t k = 0; k < rays_.size(); ++k) {
    tracedSum += kernels_[k];
    if (!occluded_[k]) visibleSum += kernels_[k];
  }
  return kernelSum / kernelCount * (visibleSum / tracedSum);
}


FormFactorMatrix computeFormFactors(const Mesh& mesh, const RayCaster& caster, const FormFactorOptions& options,
                                    FormFactorStats* stats) {
  Timer timer;
  const std::size_t n = mesh.numPatches();
  FormFactorMatrix F = FormFactorMatrix::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  const std::uint64_t raysBefore = caster.raysCast();
  std::atomic<std::uint64_t> evaluated{0}, culled{0};

  if (!isPairMethod(options.method)) {
    // Whole rows from each patch; no reciprocity fill (the rows are what the method measures).
    Progress progress("form factors", n, options.showProgress);
    std::optional<Hemicube> hemicube;
    if (options.method == FormFactorMethod::Hemicube) hemicube.emplace(options.hemicubeResolution);
    tbb::enumerable_thread_specific<Hemicube::Scratch> scratch;
    parallelFor(0, n, [&](std::size_t i) {
      float* row = F.data() + i * n;
      if (hemicube)
        hemicube->row(mesh, i, scratch.local(), row);
      else
        hemisphereRow(mesh, caster, i, options.hemisphereRays, options.seed, row);
      progress.advance();
    });
    progress.finish();
    if (stats) {
      stats->pairsEvaluated = n * (n - 1);
      stats->visibilityRays = caster.raysCast() - raysBefore;
      stats->seconds = timer.seconds();
    }
    return F;
  }

  Progress progress("form factors", n * (n - 1) / 2, options.showProgress);

  tbb::enumerable_thread_specific<PairFormFactors> estimators([&] { return PairFormFactors(mesh, caster, options); });
  parallelFor(0, n, [&](std::size_t i) {
    PairFormFactors& estimator = estimators.local();
    std::uint64_t rowEvaluated = 0, rowCulled = 0;
    for (std::size_t j = i + 1; j < n; ++j) {
      if (estimator.culled(i, j)) {
        ++rowCulled;
        continue;
      }
      ++rowEvaluated;
      double fij = estimator.estimate(i, j);
      F(i, j) = static_cast<float>(fij);
      F(j, i) = static_cast<float>(fij * mesh.patches[i].area / mesh.patches[j].area);
    }
    evaluated += rowEvaluated;
    culled += rowCulled;
    progress.advance(n - 1 - i);
  });
  progress.finish();

  if (stats) {
    stats->pairsEvaluated = evaluated;
    stats->pairsCulled = culled;
    stats->visibilityRays = caster.raysCast() - raysBefore;
    stats->seconds = timer.seconds();
  }
  return F;
}

}  // namespace lambert
