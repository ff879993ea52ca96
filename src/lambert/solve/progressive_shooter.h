#pragma once
// Progressive refinement radiosity (Cohen, Chen, Wallace & Greenberg, "A Progressive Refinement
// Approach to Fast Radiosity Image Generation", SIGGRAPH 1988) with its state kept
// between calls: the radiosity B and the unshot radiosity ΔB. Repeatedly the patch with the most
// unshot power ΔB_i A_i is shot to every patch j,
//   ΔB_j += ρ_j ΔB_i F_ji,  F_ji = F_ij A_i / A_j (reciprocity, so row i is all that is read).
// When emission changes (a light moved), the difference is added to B and to ΔB and shot like any
// other power, negative where light went away (Chen 1990, "Incremental Radiosity"): a frame costs
// the shots its change needs, not a new solve.
// It reads rows of the dense matrix, so the problem's transport must have one
// (Transport::matrix(), a DenseTransport); one without is a failed check at construction.
#include <vector>

#include "lambert/solve/solver.h"

namespace lambert {

class ProgressiveShooter {
 public:
  // Starts from B = ΔB = E. problem.transport->matrix() must not be null.
  explicit ProgressiveShooter(const RadiosityProblem& problem);

  // Starts from a guess B₀ instead: its residual r₀ = E + ρFB₀ − B₀ (one gather over F) is added
  // to B₀ and left to shoot, since B = B₀ + X with X = r₀ + ρFX.
  void warmStart(const std::vector<Rgb>& radiosity);

  // Replaces the emitted radiosity E; the difference joins B and the unshot radiosity.
  void setEmitted(const std::vector<Rgb>& emitted);

  // Shoots until the unshot power is at most tolerance × the total power, or maxShots are spent.
  // Returns the number of shots.
  long long shoot(long long maxShots, double tolerance);
  // The same within a wall-clock limit too (checked every 32 shots; 0: none). converged: it
  // stopped at the tolerance, not at a limit.
  struct Outcome {
    long long shots = 0;
    bool converged = false;
  };
  Outcome shoot(long long maxShots, double tolerance, double maxSeconds);

  const std::vector<Rgb>& radiosity() const { return radiosity_; }
  const std::vector<Rgb>& unshot() const { return unshot_; }
  const std::vector<Rgb>& emitted() const { return problem_.emitted; }
  // Σ|ΔB_i|A_i / Σ B_i A_i over channels: how far from converged.
  double unshotFraction() const;
  // B plus the ambient term, the estimate to display mid-solve (Cohen et al. 1988).
  std::vector<Rgb> displayRadiosity() const;

 private:
  RadiosityProblem problem_;
  std::vector<Rgb> radiosity_;
  std::vector<Rgb> unshot_;
};

}  // namespace lambert
