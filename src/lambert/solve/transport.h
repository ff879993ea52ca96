#pragma once
// The light transport between a solution's elements: the linear map from radiosity B (W/m²) to
// the irradiance-like sum H_i = Σ_j F_ij B_j each element gathers (W/m²), so that B = E + ρH.
// Two kinds stand behind one interface, and the solvers, the residual and the energy balance
// read only this:
//   DenseTransport         the full matrix F (uniform and adaptive meshing);
//   HierarchicalTransport  links between element and cluster nodes of a hierarchy, gathered
//                          over the links and pushed and pulled through it (Hanrahan, Salzman &
//                          Aupperle 1991; Smits, Arvo & Greenberg 1994), hierarchical/transport.h.
#include <memory>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/formfactor/matrix.h"

namespace lambert {

// The largest |ΔB| and |B| over the elements and channels of one sweep (W/m²).
struct SweepChange {
  double change = 0;
  double magnitude = 0;
};

class Transport {
 public:
  virtual ~Transport() = default;

  // The number of elements.
  virtual std::size_t size() const = 0;

  // irradiance[i] = Σ_j F_ij radiosity[j] for every element i; irradiance is resized.
  virtual void gather(const std::vector<Rgb>& radiosity, std::vector<Rgb>& irradiance) const = 0;

  // One gathering sweep B_i ← E_i + ρ_i H_i over every element: in place, each new value used as
  // soon as it exists (Gauss–Seidel), or from the previous iterate (Jacobi, in parallel).
  virtual SweepChange sweep(const std::vector<Rgb>& emitted, const std::vector<Rgb>& albedo,
                            std::vector<Rgb>& radiosity, bool inPlace) const = 0;
  // After the last sweep: a transport whose sweeps are spread over ranks (hierarchical/distributed_transport.h),
  // each rank updating its own elements, hands every rank the whole result. Nothing otherwise.
  virtual void completeSweeps(std::vector<Rgb>& /*radiosity*/) const {}

  // The dense matrix when there is one (the direct and shooting solvers need it), else null.
  virtual const FormFactorMatrix* matrix() const { return nullptr; }
};

// F held as a dense matrix, shared with whoever computed or cached it.
class DenseTransport final : public Transport {
 public:
  explicit DenseTransport(std::shared_ptr<const FormFactorMatrix> formFactors);

  std::size_t size() const override;
  void gather(const std::vector<Rgb>& radiosity, std::vector<Rgb>& irradiance) const override;
  SweepChange sweep(const std::vector<Rgb>& emitted, const std::vector<Rgb>& albedo, std::vector<Rgb>& radiosity,
                    bool inPlace) const override;
  const FormFactorMatrix* matrix() const override { return formFactors_.get(); }

 private:
  std::shared_ptr<const FormFactorMatrix> formFactors_;
};

}  // namespace lambert
