#pragma once
// One call of Radiosity::solve(): the budget it may spend and the report of what it did. The
// methods (flat/, hierarchical/) fill the report's parts that are theirs.
#include <cstddef>
#include <cstdint>

#include "lambert/core/error.h"
#include "lambert/solve/solver_kind.h"

namespace lambert {

// How much one solve() may do beyond stopping at the tolerance; 0 everywhere: run to the
// tolerance (or maxIterations). Each limit belongs to the solvers that can stop early on it;
// any other is an error from solve().
struct SolveBudget {
  long long maxShots = 0;       // shoot
  int maxSweeps = 0;            // gs, jacobi
  double maxMilliseconds = 0;   // gs, jacobi, shoot (checked between sweeps or every few shots)

  bool unlimited() const { return maxShots == 0 && maxSweeps == 0 && maxMilliseconds == 0; }
};

// Whether a solver can honour the budget: shots are for shoot, sweeps for gs and jacobi, time for
// all three; the direct solver takes none. The Error says which budget fits instead.
Status checkSolveBudget(SolverKind solver, const SolveBudget& budget);

// What one solve() did.
struct SolveReport {
  int lightsInjected = 0;    // lights traced again (moved, new, or every one after refinement)
  // Sweeps (gs, jacobi), shots (shoot) or 1 (direct), summed over every pass of this call (the
  // hierarchy's refinement passes in its first solve, the adaptive mesh's passes). A budget
  // bounds each pass.
  long long iterations = 0;
  bool converged = false;    // the last pass reached the tolerance
  double unshotFraction = 0; // shoot: unshot power left (for a later solve() to shoot)
  // Adaptive meshing, over every pass of this call.
  int refined = 0, coarsened = 0;
  std::uint64_t pairsEstimated = 0, pairsReused = 0, pairsLoaded = 0;
  std::size_t elements = 0;  // after the call
  double adaptSeconds = 0, formFactorSeconds = 0, injectSeconds = 0, solveSeconds = 0;
};

}  // namespace lambert
