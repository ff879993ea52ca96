// The close sources' corners (hierarchical/final_gather.h): the irradiance at sites whose close
// leaf sources take their light from their corners' radiosities, and the linear system that
// couples those corners at the vertices (solve/krylov.h). Its own file: the near field's one step
// after the gather, which vertex and point outputs alike take.
#include "lambert/hierarchical/final_gather.h"

#include <algorithm>
#include <cmath>

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/hierarchical/final_gather_outputs.h"
#include "lambert/solve/krylov.h"
#include "lambert/solve/row_contraction.h"

namespace lambert {

std::vector<Rgb> FinalGather::withCorners(const std::vector<Rgb>& gathered, const NearFieldWeights& near,
                                         const std::vector<Rgb>& cornerRadiosity) {
  LAMBERT_CHECK(near.start.size() == gathered.size() + 1 && near.meanPart.size() == gathered.size());
  std::vector<Rgb> out(gathered.size());
  parallelFor(0, gathered.size(), [&](std::size_t v) {
    Rgb e = gathered[v] - near.meanPart[v];
    for (std::uint32_t k = near.start[v]; k < near.start[v + 1]; ++k) e += cornerRadiosity[near.corner[k]] * near.weight[k];
    out[v] = nonNegative(e);
  }, 1024);
  return out;
}

std::vector<Rgb> FinalGather::coupleNearField(const std::vector<Rgb>& gathered, const NearFieldWeights& near,
                                              std::span<const Rgb> emitted, std::span<const Rgb> albedo, std::span<const Rgb> direct,
                                              NearFieldCoupling* report) {
  const std::size_t n = gathered.size();
  LAMBERT_CHECK(near.start.size() == n + 1 && near.meanPart.size() == n && emitted.size() == n && albedo.size() == n &&
                direct.size() == n);
  NearFieldCoupling done;
  // Each row's ρ Σ w bounded as the solve bounds its rows (solve/row_contraction.h): Σ w is the
  // close sources' share of the vertex's hemisphere, at most 1 where they do not overlap, but
  // sources seen through one another (faces interpenetrating, coincident or stacked, as game
  // maps and converted scenes have them) can sum to more, and a loop of such rows above 1 grew
  // without bound: 10⁸ W/(m²·sr) at the 100-step cap on a sun- and sky-lit interior, published
  // as converged. Bounded, the system is a contraction in the largest row and has one solution.
  std::vector<float> rowScale(n, 1.0f);
  parallelFor(0, n, [&](std::size_t v) {
    double sum = 0;
    for (std::uint32_t k = near.start[v]; k < near.start[v + 1]; ++k) sum += near.weight[k];
    const double rho = albedo[v].maxComponent(), bound = rowContractionBound(rho);
    if (rho * sum > bound) rowScale[v] = static_cast<float>(bound / (rho * sum));
  }, 1024);
  for (float s : rowScale) done.rowsScaled += s < 1.0f;
  std::vector<Rgb> far(n);
  parallelFor(0, n, [&](std::size_t v) { far[v] = gathered[v] - near.meanPart[v]; }, 1024);
  const auto irradianceAt = [&](std::size_t v, const Eigen::VectorXd& b) {
    Rgb corners;
    for (std::uint32_t k = near.start[v]; k < near.start[v + 1]; ++k) {
      const double* c = b.data() + 3 * static_cast<std::size_t>(near.corner[k]);
      corners += Rgb{c[0], c[1], c[2]} * near.weight[k];
    }
    return far[v] + corners * rowScale[v];
  };
  // B = e + ρ (far + direct + s W B): (I − ρ s W) B = e + ρ (far + direct), started from every
  // close source at its mean. Stationary steps converge at the rate of the largest loop gain,
  // which reaches (1 + ρ)/2 where ρ is near 1 (RenderPark's hospital repairs rd = 1 to 0.999: its
  // Jacobi steps were still 10⁻⁶ away after 1,000, and the uncoupled gather was shown); a Krylov
  // method takes the few slow directions out in a few steps each.
  Eigen::VectorXd rhs(3 * n), start(3 * n);
  std::vector<double> scale(3 * n);
  for (std::size_t v = 0; v < n; ++v) {
    const Rgb b = emitted[v] + albedo[v] * (far[v] + direct[v]), initial = emitted[v] + albedo[v] * (gathered[v] + direct[v]);
    const double channels[3][3] = {{b.r, initial.r, albedo[v].r}, {b.g, initial.g, albedo[v].g}, {b.b, initial.b, albedo[v].b}};
    for (int c = 0; c < 3; ++c) {
      rhs[3 * v + c] = channels[c][0];
      start[3 * v + c] = channels[c][1];
      scale[3 * v + c] = channels[c][2] * rowScale[v];
    }
  }
  Eigen::VectorXd radiosity = start;
  if (near.size() > 0) {
    // M x = D W x over the three channels stacked (x[3v + c]), D per row and channel ρ times the
    // row's contraction scale.
    const auto applyM = [&](const double* x, double* y) {
      parallelFor(0, n, [&](std::size_t v) {
        double sum[3] = {0, 0, 0};
        for (std::uint32_t k = near.start[v]; k < near.start[v + 1]; ++k) {
          const double* b = x + 3 * static_cast<std::size_t>(near.corner[k]);
          const double w = near.weight[k];
          for (int c = 0; c < 3; ++c) sum[c] += w * b[c];
        }
        for (int c = 0; c < 3; ++c) y[3 * v + c] = scale[3 * v + c] * sum[c];
      }, 1024);
    };
    // The residual's norm within kNearFieldTolerance of the right-hand side's.
    const KrylovReport krylov = solveIdentityMinus(applyM, rhs, radiosity, kNearFieldTolerance * rhs.norm(), kNearFieldMaxIterations);
    done.iterations = krylov.iterations;
    done.converged = krylov.converged;
  }
  if (report) *report = done;
  // Not converged (weights no bound can tame: not finite), the uncoupled gather, each close
  // source at its mean, rather than values still on their way.
  if (!done.converged) return gathered;
  std::vector<Rgb> out(n);
  parallelFor(0, n, [&](std::size_t v) { out[v] = nonNegative(irradianceAt(v, radiosity)); }, 1024);
  return out;
}

}  // namespace lambert
