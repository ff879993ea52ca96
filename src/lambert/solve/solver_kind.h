#pragma once
// Which solver a solve uses, as the solvers (solve/solver.h) and the options (method/options.h)
// name it.
#include <string>

namespace lambert {

enum class SolverKind {
  Direct,       // Eigen LU of (I − ρF): Gaussian elimination; dense transport only
  GaussSeidel,  // in-place gathering sweeps; any transport
  Jacobi,       // gathering sweeps from the previous iterate, rows in parallel; any transport
  Shooting,     // progressive refinement (Cohen, Chen, Wallace & Greenberg 1988); dense only
};

std::string solverName(SolverKind kind);

}  // namespace lambert
