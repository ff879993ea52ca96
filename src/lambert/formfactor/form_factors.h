#pragma once
// The form-factor matrix F of a mesh: F(i, j) is the fraction of the power leaving patch i that
// arrives at patch j. Each unordered pair is estimated once; reciprocity A_i F_ij = A_j F_ji
// fills the other half.
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "lambert/geometry/ray_caster.h"
#include "lambert/mesh/mesh.h"

namespace lambert {

// Row-major so that a gather over row i (Gauss–Seidel, shooting via reciprocity) reads contiguous
// memory; single precision halves the bandwidth those sweeps are bound by.
using FormFactorMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

enum class FormFactorMethod {
  // Seed 000: one kernel evaluation and one visibility ray between the patches' incircle centres.
  PointToPoint,
  // Area-to-area Monte Carlo: low-discrepancy sample points x_k on patch i, each paired with a point
  // y_k on patch j; F_ij ≈ 1/N Σ_k F(x_k → P_j) V(x_k, y_k) with the analytic point-to-polygon
  // factor, so adjacent patches stay finite and exact when unoccluded (Wallace, Elmquist & Haines
  // 1989 use the same split of kernel and visibility).
  AreaMonteCarlo,
};

std::string formFactorMethodName(FormFactorMethod method);

struct FormFactorOptions {
  FormFactorMethod method = FormFactorMethod::AreaMonteCarlo;
  int samplePairs = 16;        // per patch pair, AreaMonteCarlo only; powers of two stratify best
  int nearFieldBoost = 16;     // sample multiplier for pairs closer than twice their size
  std::uint64_t seed = 1;      // results depend on (seed, pair), never on thread count
  bool showProgress = true;    // a progress line when stderr is a terminal
};

struct FormFactorStats {
  std::uint64_t pairsEvaluated = 0;  // unordered pairs that could see each other
  std::uint64_t pairsCulled = 0;     // unordered pairs facing away (coplanar, behind): F = 0
  std::uint64_t visibilityRays = 0;
  double seconds = 0;
};

FormFactorMatrix computeFormFactors(const Mesh& mesh, const RayCaster& caster, const FormFactorOptions& options,
                                    FormFactorStats* stats = nullptr);

}  // namespace lambert
