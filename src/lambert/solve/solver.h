#pragma once
// Solvers for the radiosity system B = E + ρ F B, each RGB channel on its own, behind one
// interface. All start from (and so can warm-start with) the radiosity they are handed.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/solve/transport.h"
#include "lambert/solve/solver_kind.h"

namespace lambert {

struct RadiosityProblem {
  std::shared_ptr<const Transport> transport;  // F: B ↦ H = FB
  std::vector<Rgb> emitted;                    // E_i, W/m²
  std::vector<Rgb> albedo;                     // ρ_i
  std::vector<double> area;                    // A_i, scene units²

  std::size_t size() const { return emitted.size(); }
};



struct SolverOptions {
  // Stop when the relative change (sweeps) or the unshot power fraction (shooting) falls below.
  double tolerance = 1e-7;
  // Sweeps for Gauss–Seidel and Jacobi; shots for shooting are limited to this many per patch.
  int maxIterations = 1000;
  // Wall-clock limit in seconds, checked between sweeps (every 32 shots for shooting); 0: none.
  double maxSeconds = 0;
  // Called every progressEvery iterations with the displayable estimate (for shooting, radiosity
  // plus the ambient term); 0 turns it off.
  int progressEvery = 0;
  bool displayAmbient = true;  // shooting: add the ambient term to what onProgress sees
  // Whether SolverReport::residual is measured: one more gather over the whole transport after the
  // last iteration (for a warm one-sweep update of the hierarchical method, about as long as the
  // sweep). Off, the report's residual is NaN.
  bool measureResidual = true;
  std::function<void(int iteration, const std::vector<Rgb>& estimate)> onProgress;
};

struct SolverReport {
  std::string solver;
  int iterations = 0;     // sweeps (Gauss–Seidel's BiCGSTAB finish: two per iteration), shots for shooting, 1 for direct
  double residual = 0;    // max |E + ρFB − B| / max |B|, over patches and channels; NaN if not measured
  double seconds = 0;
  bool converged = false;
};

class Solver {
 public:
  virtual ~Solver() = default;
  // Solves in place: radiosity holds the starting guess (any size other than the problem's
  // means "start from E") and receives B_i in W/m².
  virtual SolverReport solve(const RadiosityProblem& problem, std::vector<Rgb>& radiosity) const = 0;
};

// Gauss–Seidel and Jacobi read the problem's transport only through Transport::sweep, so they
// solve any kind. Direct and Shooting need the dense matrix (Transport::matrix()): handed a
// problem whose transport has none, their solve() stops with a failed LAMBERT_CHECK, so callers
// (the engine) must refuse those combinations before solving.
std::unique_ptr<Solver> makeSolver(SolverKind kind, SolverOptions options = {});

// max_i,c |E + ρFB − B| / max_i,c |B|, with FB from one Transport::gather.
double relativeResidual(const RadiosityProblem& problem, const std::vector<Rgb>& radiosity);

// Where a solution cannot be right: the first element whose radiosity is not finite, or (when
// all are) the one holding the most power if the total exceeds what the emission can give,
// Σ B_i A_i ≤ Σ E_i A_i / (1 − ρ_max) for a transport whose rows sum to at most 1, with half
// again as slack for estimated form factors. Such a solution comes from a system that diverged
// (a transport that makes energy) or from non-finite input; empty when neither.
// `earlierEmittedPower` (Σ E_i A_i of earlier solves warm-started into this one) counts with a
// millionth: light removed by negative shooting leaves rounding behind, not divergence.
struct SolutionFault {
  std::size_t element = 0;
  std::string what;  // "is not finite", "… more power than …"
};
std::optional<SolutionFault> findSolutionFault(const RadiosityProblem& problem, const std::vector<Rgb>& radiosity,
                                               double earlierEmittedPower = 0);
// Σ E_i A_i over channels, as findSolutionFault counts power.
double emittedPower(const RadiosityProblem& problem);

// Cohen et al. 1988's ambient radiosity for display during shooting: the unshot power spread
// uniformly and reflected to convergence, R·Σ ΔB_j A_j / Σ A_j with R = 1 / (1 − ρ_avg).
Rgb ambientRadiosity(const RadiosityProblem& problem, const std::vector<Rgb>& unshot);

}  // namespace lambert
