#pragma once
// Which solver a solve uses, as the solvers (solve/solver.h) and the options (engine/options.h)
// name it.
#include <string>

namespace lambert {

enum class SolverKind {
  Direct,       // Eigen LU of (I − ρF): seed 001's "Gaussian elimination"; dense transport only
  GaussSeidel,  // in-place gathering sweeps (seed 000); any transport
  Jacobi,       // gathering sweeps from the previous iterate, rows in parallel; any transport
  Shooting,     // progressive refinement (Cohen, Chen, Wallace & Greenberg 1988; seed 001); dense only
};

std::string solverName(SolverKind kind);

}  // namespace lambert
