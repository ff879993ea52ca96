#pragma once
// The concrete solvers; use makeSolver() rather than naming these.
#include "lambert/solve/solver.h"

namespace lambert {

class DirectSolver final : public Solver {
 public:
  explicit DirectSolver(bool measureResidual) : measureResidual_(measureResidual) {}
  SolverReport solve(const RadiosityProblem& problem, std::vector<Rgb>& radiosity) const override;

 private:
  bool measureResidual_;  // SolverOptions::measureResidual; the direct solver reads no other option
};

class GatheringSolver final : public Solver {
 public:
  GatheringSolver(SolverOptions options, bool inPlace) : options_(std::move(options)), inPlace_(inPlace) {}
  SolverReport solve(const RadiosityProblem& problem, std::vector<Rgb>& radiosity) const override;

 private:
  SolverOptions options_;
  bool inPlace_;  // Gauss–Seidel when true, Jacobi when false
};

class ShootingSolver final : public Solver {
 public:
  explicit ShootingSolver(SolverOptions options) : options_(std::move(options)) {}
  SolverReport solve(const RadiosityProblem& problem, std::vector<Rgb>& radiosity) const override;

 private:
  SolverOptions options_;
};

}  // namespace lambert
