#pragma once
// The radiosity system B = E + ρFB of a mesh, from numbers: what each patch emits and reflects
// (light/emission.h computes them from a scene's materials) and the transport between its
// patches (solve/transport.h; std::make_shared<DenseTransport>(F) for a dense matrix F).
#include <memory>
#include <vector>

#include "lambert/mesh/mesh.h"
#include "lambert/solve/solver.h"

namespace lambert {

// emitted: E_i in W/m², albedo: ρ_i, one per patch of mesh (whose areas the problem takes);
// transport, when not null, must be of mesh's patches (size() == mesh.numPatches()).
RadiosityProblem makeRadiosityProblem(const Mesh& mesh, std::vector<Rgb> emitted, std::vector<Rgb> albedo,
                                      std::shared_ptr<const Transport> transport);

}  // namespace lambert
