#pragma once
// Where the power goes in a solved scene: what surfaces emit, what they absorb, and what leaves
// through openings (rows of F that sum to less than one). In a solution these balance.
#include "lambert/solve/solver.h"

namespace lambert {

struct EnergyBalance {
  double emittedWatts = 0;   // Σ A_i E_i, summed over RGB channels
  double absorbedWatts = 0;  // Σ A_i (1 − ρ_i) H_i, H_i = Σ_j F_ij B_j
  double escapedWatts = 0;   // Σ A_i B_i (1 − Σ_j F_ij)
};

// metresPerUnit converts the problem's areas to m² so the figures are in watts.
EnergyBalance energyBalance(const RadiosityProblem& problem, const std::vector<Rgb>& radiosity, double metresPerUnit);

}  // namespace lambert
