// The close sources' corners (hierarchical/final_gather.h): the irradiance at sites whose close
// leaf sources take their light from their corners' radiosities, and the Jacobi iteration that
// couples those corners at the vertices. Its own file: the near field's one step after the
// gather, which vertex and point outputs alike take.
#include "lambert/hierarchical/final_gather.h"

#include <algorithm>
#include <cmath>

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/hierarchical/final_gather_outputs.h"
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
  // as converged. Bounded, every step is a contraction in the largest row and Jacobi converges.
  std::vector<float> rowScale(n, 1.0f);
  parallelFor(0, n, [&](std::size_t v) {
    double sum = 0;
    for (std::uint32_t k = near.start[v]; k < near.start[v + 1]; ++k) sum += near.weight[k];
    const double rho = albedo[v].maxComponent(), bound = rowContractionBound(rho);
    if (rho * sum > bound) rowScale[v] = static_cast<float>(bound / (rho * sum));
  }, 1024);
  for (float s : rowScale) done.rowsScaled += s < 1.0f;
  std::vector<Rgb> far(n), radiosity(n), next(n);
  parallelFor(0, n, [&](std::size_t v) {
    far[v] = gathered[v] - near.meanPart[v];
    radiosity[v] = emitted[v] + albedo[v] * (gathered[v] + direct[v]);
  }, 1024);
  const auto irradianceAt = [&](std::size_t v, const std::vector<Rgb>& b) {
    Rgb corners;
    for (std::uint32_t k = near.start[v]; k < near.start[v + 1]; ++k) corners += b[near.corner[k]] * near.weight[k];
    return far[v] + corners * rowScale[v];
  };
  if (near.size() > 0) {
    double largest = 0;
    for (const Rgb& b : radiosity) largest = std::fmax(largest, b.maxComponent());
    done.converged = false;
    for (; done.iterations < kNearFieldMaxIterations; ++done.iterations) {
      std::vector<double> change(n, 0.0);
      parallelFor(0, n, [&](std::size_t v) {
        next[v] = near.start[v] == near.start[v + 1] ? radiosity[v] : emitted[v] + albedo[v] * (irradianceAt(v, radiosity) + direct[v]);
        change[v] = std::fmax((next[v] - radiosity[v]).maxComponent(), (radiosity[v] - next[v]).maxComponent());
        if (!std::isfinite(change[v])) change[v] = INFINITY;
      }, 1024);
      radiosity.swap(next);
      const double largestChange = *std::max_element(change.begin(), change.end());
      if (!std::isfinite(largestChange)) break;
      if (!(largestChange > kNearFieldTolerance * largest)) {
        ++done.iterations;
        done.converged = true;
        break;
      }
    }
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

