#include "lambert/solve/energy.h"

#include "lambert/solve/gather_row.h"

namespace lambert {

EnergyBalance energyBalance(const RadiosityProblem& problem, const std::vector<Rgb>& radiosity, double metresPerUnit) {
  const FormFactorMatrix& F = *problem.transport->matrix();
  const double squareMetres = metresPerUnit * metresPerUnit;
  EnergyBalance balance;
  for (std::size_t i = 0; i < problem.size(); ++i) {
    double area = problem.area[i] * squareMetres;
    Rgb received = gatherRow(F, i, radiosity);
    double rowSum = F.row(static_cast<Eigen::Index>(i)).cast<double>().sum();
    balance.emittedWatts += area * problem.emitted[i].sum();
    balance.absorbedWatts += area * ((Rgb::gray(1) - problem.albedo[i]) * received).sum();
    balance.escapedWatts += area * radiosity[i].sum() * (1 - rowSum);
  }
  return balance;
}

}  // namespace lambert
