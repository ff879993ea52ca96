#pragma once
// Where the power goes in a solved scene: what surfaces emit, what they absorb, and what leaves
// through openings. Computed from one Transport::gather (H = FB), so it works for any transport.
// In a solution (B = E + ρH) the three balance exactly, whatever F is: emitted = absorbed +
// escaped. With a reciprocal F (A_i F_ij = A_j F_ji) escaped is the power lost through rows that
// sum to less than one, Σ A_i B_i (1 − Σ_j F_ij); with one that is not (rows normalised, a
// hemi-cube's or point estimate) escaped also holds the power F makes or loses, and can be
// negative where more arrives than leaves.
#include "lambert/solve/solver.h"

namespace lambert {

// Each figure in watts of the RGB value's luminance (Rgb::luminance; core/photometric.h), so that a
// white source of Φ lm counts Φ/683 W, as its photometry says, whatever its colour.
struct EnergyBalance {
  double emittedWatts = 0;   // Σ A_i E_i: the surfaces' emission and the lights' injected first reflection
  double absorbedWatts = 0;  // Σ A_i (1 − ρ_i) H_i, H_i = Σ_j F_ij B_j
  double escapedWatts = 0;   // Σ A_i B_i − Σ A_i H_i: power leaving surfaces minus power arriving
};

// metresPerUnit converts the problem's areas to m² so the figures are in watts.
EnergyBalance energyBalance(const RadiosityProblem& problem, const std::vector<Rgb>& radiosity, double metresPerUnit);

}  // namespace lambert
