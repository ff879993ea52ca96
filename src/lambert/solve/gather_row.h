#pragma once
// DenseTransport's inner loop (solve/transport.cpp): H_i = Σ_j F_ij B_j, the irradiance-like sum
// of what patch i receives (W/m²), over one row of the dense matrix.
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/formfactor/matrix.h"

namespace lambert {

inline Rgb gatherRow(const FormFactorMatrix& F, std::size_t i, const std::vector<Rgb>& radiosity) {
  const float* row = F.data() + i * static_cast<std::size_t>(F.cols());
  double r = 0, g = 0, b = 0;
  for (std::size_t j = 0; j < radiosity.size(); ++j) {
    double f = row[j];
    r += f * radiosity[j].r;
    g += f * radiosity[j].g;
    b += f * radiosity[j].b;
  }
  return {r, g, b};
}

}  // namespace lambert
