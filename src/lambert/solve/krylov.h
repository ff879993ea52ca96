#pragma once
// (I − M) x = b by BiCGSTAB (van der Vorst 1992, Eigen's), M given only by its action y = M x:
// the radiosity systems' gathering operators (a transport's gather times ρ, the final gather's
// near-field weights) are applied, never stored. Stationary sweeps shrink the error by the
// largest loop gain each step, which nears 1 in a pocket of near-white faces; a Krylov method
// takes such slow directions out in a few steps each.
#include <functional>

#include <Eigen/Core>

namespace lambert {

struct KrylovReport {
  int iterations = 0;  // BiCGSTAB iterations (two applications of M each)
  bool converged = false;
};

// Solves (I − M) x = b from the guess x (overwritten), until ‖(I − M) x − b‖₂ ≤ tolerance, or
// maxIterations. applyM(x, y) writes y = M x for vectors of b.size() doubles. Not converged
// (or not finite): x holds where the solver stopped.
KrylovReport solveIdentityMinus(const std::function<void(const double* x, double* y)>& applyM, const Eigen::VectorXd& b,
                                Eigen::VectorXd& x, double tolerance, int maxIterations);

}  // namespace lambert
