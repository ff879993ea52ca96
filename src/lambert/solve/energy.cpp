#include "lambert/solve/energy.h"

#include "lambert/core/error.h"

namespace lambert {

EnergyBalance energyBalance(const RadiosityProblem& problem, const std::vector<Rgb>& radiosity, double metresPerUnit) {
  LAMBERT_CHECK(problem.transport && radiosity.size() == problem.size());
  std::vector<Rgb> irradiance;
  problem.transport->gather(radiosity, irradiance);
  const double squareMetres = metresPerUnit * metresPerUnit;
  EnergyBalance balance;
  double leaving = 0, arriving = 0;
  for (std::size_t i = 0; i < problem.size(); ++i) {
    const double area = problem.area[i] * squareMetres;
    balance.emittedWatts += area * problem.emitted[i].luminance();
    balance.absorbedWatts += area * ((Rgb::gray(1) - problem.albedo[i]) * irradiance[i]).luminance();
    leaving += area * radiosity[i].luminance();
    arriving += area * irradiance[i].luminance();
  }
  balance.escapedWatts = leaving - arriving;
  return balance;
}

}  // namespace lambert
