// The close sources' corners (hierarchical/final_gather.h): the irradiance at sites whose close
// leaf sources take their light from their corners' radiosities, and the Jacobi iteration that
// couples those corners at the vertices. Its own file: the near field's one step after the
// gather, which vertex and point outputs alike take.
#include "lambert/hierarchical/final_gather.h"

#include <algorithm>

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/hierarchical/final_gather_outputs.h"

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
                                              int* iterations) {
  const std::size_t n = gathered.size();
  LAMBERT_CHECK(near.start.size() == n + 1 && near.meanPart.size() == n && emitted.size() == n && albedo.size() == n &&
                direct.size() == n);
  constexpr int kMaxIterations = 100;
  constexpr double kTolerance = 1e-6;
  std::vector<Rgb> far(n), radiosity(n), next(n);
  parallelFor(0, n, [&](std::size_t v) {
    far[v] = gathered[v] - near.meanPart[v];
    radiosity[v] = emitted[v] + albedo[v] * (gathered[v] + direct[v]);
  }, 1024);
  const auto irradianceAt = [&](std::size_t v, const std::vector<Rgb>& b) {
    Rgb e = far[v];
    for (std::uint32_t k = near.start[v]; k < near.start[v + 1]; ++k) e += b[near.corner[k]] * near.weight[k];
    return e;
  };
  int steps = 0;
  if (near.size() > 0) {
    double largest = 0;
    for (const Rgb& b : radiosity) largest = std::fmax(largest, b.maxComponent());
    for (; steps < kMaxIterations; ++steps) {
      std::vector<double> change(n, 0.0);
      parallelFor(0, n, [&](std::size_t v) {
        next[v] = near.start[v] == near.start[v + 1] ? radiosity[v] : emitted[v] + albedo[v] * (irradianceAt(v, radiosity) + direct[v]);
        change[v] = (next[v] - radiosity[v]).maxComponent();
        change[v] = std::fmax(change[v], (radiosity[v] - next[v]).maxComponent());
      }, 1024);
      radiosity.swap(next);
      if (!(*std::max_element(change.begin(), change.end()) > kTolerance * largest)) {
        ++steps;
        break;
      }
    }
  }
  if (iterations) *iterations = steps;
  return withCorners(gathered, near, radiosity);
}

}  // namespace lambert

