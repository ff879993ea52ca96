#include "lambert/formfactor/form_factors.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <numeric>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/core/progress.h"
#include "lambert/core/rng.h"
#include "lambert/core/timer.h"
#include "lambert/formfactor/kernels.h"

namespace lambert {

std::string formFactorMethodName(FormFactorMethod method) {
  switch (method) {
    case FormFactorMethod::PointToPoint: return "point";
    case FormFactorMethod::AreaMonteCarlo: return "mc";
  }
  return "?";
}

namespace {

// Whether any part of patch b lies strictly in front of patch a's plane.
bool anyCornerInFront(const Mesh& mesh, std::size_t a, std::size_t b, double epsilon) {
  const Patch& pa = mesh.patches[a];
  for (std::uint32_t v : mesh.patches[b].vertices)
    if (dot(mesh.positions[v] - pa.centroid, pa.normal) > epsilon) return true;
  return false;
}

// Pairs that cannot exchange light: on one plane, or either one wholly behind the other.
bool facesAway(const Mesh& mesh, std::size_t i, std::size_t j, double epsilon) {
  return !anyCornerInFront(mesh, i, j, epsilon) || !anyCornerInFront(mesh, j, i, epsilon);
}

// N-rooks (Latin hypercube) points in the unit square: one per row and column stratum.
void nRooks(Pcg32& rng, int n, std::vector<double>& u, std::vector<double>& v, std::vector<int>& permutation) {
  u.resize(n);
  v.resize(n);
  permutation.resize(n);
  std::iota(permutation.begin(), permutation.end(), 0);
  for (int k = n - 1; k > 0; --k) std::swap(permutation[k], permutation[rng.nextBelow(static_cast<std::uint32_t>(k + 1))]);
  for (int k = 0; k < n; ++k) {
    u[k] = (k + rng.nextDouble()) / n;
    v[k] = (permutation[k] + rng.nextDouble()) / n;
  }
}

class PairEstimator {
 public:
  PairEstimator(const Mesh& mesh, const RayCaster& caster, const FormFactorOptions& options)
      : mesh_(mesh), caster_(caster), options_(options), epsilon_(rayEpsilon(mesh)) {}

  // F_ij, the fraction of power leaving i that reaches j.
  double estimate(std::size_t i, std::size_t j) {
    return options_.method == FormFactorMethod::PointToPoint ? pointToPoint(i, j) : areaMonteCarlo(i, j);
  }

 private:
  Ray segment(const Vec3& x, const Vec3& xNormal, const Vec3& y, const Vec3& yNormal) const {
    Vec3 from = x + xNormal * epsilon_, to = y + yNormal * epsilon_;
    return Ray{from, to - from, 0, 1};
  }

  double pointToPoint(std::size_t i, std::size_t j) {
    const Patch& pi = mesh_.patches[i];
    const Patch& pj = mesh_.patches[j];
    Vec3 x = incenter(mesh_.corners(i)), y = incenter(mesh_.corners(j));
    double kernel = pointToPointKernel(x, pi.normal, y, pj.normal);
    if (kernel == 0 || caster_.occluded(segment(x, pi.normal, y, pj.normal))) return 0;
    return kernel * pj.area;
  }

  double areaMonteCarlo(std::size_t i, std::size_t j) {
    const Patch& pi = mesh_.patches[i];
    const Patch& pj = mesh_.patches[j];
    const int n = options_.samplePairs;
    Pcg32 rng(options_.seed, static_cast<std::uint64_t>(i) * mesh_.numPatches() + j);
    nRooks(rng, n, u_, v_, permutation_);
    xs_.resize(n);
    for (int k = 0; k < n; ++k) xs_[k] = sampleTriangle(mesh_.corners(i), u_[k], v_[k]);
    nRooks(rng, n, u_, v_, permutation_);
    auto targetCorners = mesh_.corners(j);

    rays_.clear();
    kernels_.clear();
    for (int k = 0; k < n; ++k) {
      double f = pointToPolygonFormFactor(xs_[k], pi.normal, targetCorners, pj.normal);
      if (f <= 0) continue;
      Vec3 y = sampleTriangle(targetCorners, u_[k], v_[k]);
      kernels_.push_back(f);
      rays_.push_back(segment(xs_[k], pi.normal, y, pj.normal));
    }
    if (occludedCapacity_ < rays_.size()) {
      occludedCapacity_ = rays_.size();
      occluded_ = std::make_unique<bool[]>(occludedCapacity_);
    }
    caster_.occluded(rays_, std::span<bool>(occluded_.get(), rays_.size()));
    double sum = 0;
    for (std::size_t k = 0; k < rays_.size(); ++k)
      if (!occluded_[k]) sum += kernels_[k];
    return sum / n;
  }

  const Mesh& mesh_;
  const RayCaster& caster_;
  const FormFactorOptions& options_;
  double epsilon_;
  // Scratch, reused across pairs by one thread.
  std::vector<double> u_, v_, kernels_;
  std::vector<int> permutation_;
  std::vector<Vec3> xs_;
  std::vector<Ray> rays_;
  std::unique_ptr<bool[]> occluded_;  // not vector<bool>: the caster writes plain bools
  std::size_t occludedCapacity_ = 0;
};

}  // namespace

FormFactorMatrix computeFormFactors(const Mesh& mesh, const RayCaster& caster, const FormFactorOptions& options,
                                    FormFactorStats* stats) {
  LAMBERT_CHECK(options.samplePairs >= 1);
  Timer timer;
  const std::size_t n = mesh.numPatches();
  FormFactorMatrix F = FormFactorMatrix::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  const double epsilon = rayEpsilon(mesh);
  const std::uint64_t raysBefore = caster.raysCast();
  std::atomic<std::uint64_t> evaluated{0}, culled{0};
  Progress progress("form factors", n * (n - 1) / 2, options.showProgress);

  tbb::enumerable_thread_specific<PairEstimator> estimators([&] { return PairEstimator(mesh, caster, options); });
  parallelFor(0, n, [&](std::size_t i) {
    PairEstimator& estimator = estimators.local();
    std::uint64_t rowEvaluated = 0, rowCulled = 0;
    for (std::size_t j = i + 1; j < n; ++j) {
      if (mesh.patches[i].surface == mesh.patches[j].surface || facesAway(mesh, i, j, epsilon)) {
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
