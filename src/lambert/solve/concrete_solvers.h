#pragma once
// The concrete solvers; use makeSolver() rather than naming these.
#include "lambert/solve/solver.h"

namespace lambert {

class DirectSolver final : public Solver {
 public:
  SolveReport solve(const RadiosityProblem& problem, std::vector<Rgb>& radiosity) const override;
};

class GatheringSolver final : public Solver {
 public:
  GatheringSolver(SolveOptions options, bool inPlace) : options_(std::move(options)), inPlace_(inPlace) {}
  SolveReport solve(const RadiosityProblem& problem, std::vector<Rgb>& radiosity) const override;

 private:
  SolveOptions options_;
  bool inPlace_;  // Gauss–Seidel when true, Jacobi when false
};

class ShootingSolver final : public Solver {
 public:
  explicit ShootingSolver(SolveOptions options) : options_(std::move(options)) {}
  SolveReport solve(const RadiosityProblem& problem, std::vector<Rgb>& radiosity) const override;

 private:
  SolveOptions options_;
};

}  // namespace lambert
