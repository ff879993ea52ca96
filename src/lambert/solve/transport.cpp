// DenseTransport: every row of F gathered in full (gatherRow), O(n²) per sweep.
#include "lambert/solve/transport.h"

#include <cmath>

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/solve/gather_row.h"

namespace lambert {
namespace {

double maxAbsComponent(const Rgb& c) { return std::fmax(std::fabs(c.r), std::fmax(std::fabs(c.g), std::fabs(c.b))); }

}  // namespace

DenseTransport::DenseTransport(std::shared_ptr<const FormFactorMatrix> formFactors) : formFactors_(std::move(formFactors)) {
  LAMBERT_CHECK(formFactors_ && formFactors_->rows() == formFactors_->cols());
}

std::size_t DenseTransport::size() const { return static_cast<std::size_t>(formFactors_->rows()); }

void DenseTransport::gather(const std::vector<Rgb>& radiosity, std::vector<Rgb>& irradiance) const {
  const FormFactorMatrix& F = *formFactors_;
  const std::size_t n = size();
  LAMBERT_CHECK(radiosity.size() == n);
  irradiance.resize(n);
  parallelFor(0, n, [&](std::size_t i) { irradiance[i] = gatherRow(F, i, radiosity); }, 16);
}

SweepChange DenseTransport::sweep(const std::vector<Rgb>& emitted, const std::vector<Rgb>& albedo,
                                  std::vector<Rgb>& radiosity, bool inPlace) const {
  const FormFactorMatrix& F = *formFactors_;
  const std::size_t n = size();
  LAMBERT_CHECK(emitted.size() == n && albedo.size() == n && radiosity.size() == n);
  SweepChange result;
  if (inPlace) {
    for (std::size_t i = 0; i < n; ++i) {
      Rgb updated = emitted[i] + albedo[i] * gatherRow(F, i, radiosity);
      result.change = std::fmax(result.change, maxAbsComponent(updated - radiosity[i]));
      result.magnitude = std::fmax(result.magnitude, updated.maxComponent());
      radiosity[i] = updated;
    }
  } else {
    std::vector<Rgb> next(n);
    std::vector<double> rowChange(n), rowMagnitude(n);
    parallelFor(0, n, [&](std::size_t i) {
      next[i] = emitted[i] + albedo[i] * gatherRow(F, i, radiosity);
      rowChange[i] = maxAbsComponent(next[i] - radiosity[i]);
      rowMagnitude[i] = next[i].maxComponent();
    }, 16);
    radiosity.swap(next);
    for (std::size_t i = 0; i < n; ++i) {
      result.change = std::fmax(result.change, rowChange[i]);
      result.magnitude = std::fmax(result.magnitude, rowMagnitude[i]);
    }
  }
  return result;
}

}  // namespace lambert
