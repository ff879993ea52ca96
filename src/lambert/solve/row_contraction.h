#pragma once
// The bound every method keeps its rows of ρF under, so that each gathering sweep is a
// contraction: the flat method's rows (flat/table.h's boundRowSums) and the hierarchy's
// (hierarchical/transport.h) are scaled to it.

namespace lambert {

inline constexpr double kRowContraction = 0.95;
// The bound on ρ·S itself, for a receiver whose albedo's largest channel is ρ: kRowContraction,
// or half way from ρ to 1 where that is higher. A fixed 0.95 leaves rows no room above 1 once
// ρ ≥ 0.95: every noisy row above 1 was cut to 1 while those below stayed, and the gain 1/(1 − ρ)
// = 20 turned that into a room 11% dark (CIE 171 §5.8's cube at ρ = 0.95, the hierarchy's rows up
// to 1.025: 984 of 1536 leaves cut). With (1 + ρ)/2, rows up to 1 + (1 − ρ)/(2ρ) keep their
// noise (1.026 at ρ = 0.95) and ρS ≤ (1 + ρ)/2 < 1 still makes every sweep a contraction.
inline double rowContractionBound(double albedo) { return albedo > 2 * kRowContraction - 1 ? 0.5 * (1 + albedo) : kRowContraction; }

}  // namespace lambert
