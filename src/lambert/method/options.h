#pragma once
// The options of a solve: what Radiosity::create takes (RadiosityOptions) and every method reads.
// Each method's options have their own header (method/flat_options.h, method/hierarchical_options.h;
// the solvers' solve/solver_kind.h, the lights' DirectLightOptions in light/lights.h); this header
// collects them and chooses the method. They sit here, below the methods, because the engine reads
// them too. The defaults are written here and in those headers only: the CLI's table
// (engine/radiosity_settings.h) starts from RadiosityOptions{}.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "lambert/method/flat_options.h"
#include "lambert/method/hierarchical_options.h"
#include "lambert/light/lights.h"
#include "lambert/solve/solver_kind.h"

namespace lambert {

class Communicator;

enum class MeshStrategy {
  Uniform,   // longest-edge bisection to a patch count or edge length, computed once
  Adaptive,  // quad-tree cells split at spot, shadow and radiosity edges, every solve
  // Element trees under clusters, linked by the BF oracle (Hanrahan, Salzman & Aupperle 1991;
  // Smits, Arvo & Greenberg 1994): near-linear in the number of faces
  Hierarchical,
};

// The defaults are the CLI's (`lambert solve` with no options): hierarchical radiosity with
// clustering at link error 2e-4, Gauss–Seidel to 1e-7, 16 light samples per element. The flat
// methods (Uniform, Adaptive) are asked for by setting meshing; they alone read uniform,
// adaptive, formFactors and normalizeRows, and they alone take the shoot and direct solvers.
struct RadiosityOptions {
  MeshStrategy meshing = MeshStrategy::Hierarchical;
  UniformMeshOptions uniform;    // read only with MeshStrategy::Uniform
  AdaptiveMeshOptions adaptive;  // read only with MeshStrategy::Adaptive
  HierarchicalOptions hierarchical;  // read only with MeshStrategy::Hierarchical
  FormFactorOptions formFactors;     // uniform and adaptive meshing
  bool normalizeRows = false;    // row normalisation (flat/table.h): adds energy
  DirectLightOptions directLight;
  SolverKind solver = SolverKind::GaussSeidel;
  double tolerance = 1e-7;       // relative change (gs, jacobi) or unshot power fraction (shoot)
  int maxIterations = 1000;      // sweeps (gs, jacobi); shots per element (shoot)
  // Where form factors (uniform: the matrix, .lff), the master table (adaptive, .lft) or the
  // hierarchy's links (hierarchical, .lhl: hierarchical/link_cache.h) are read and written; empty:
  // always computed, never saved.
  std::string cacheDirectory;
  // Bytes a solve may use for its large structures (core/memory.h); 0: the machine's available
  // memory. A solve whose estimate exceeds it is refused (create or solve returns the Error).
  double memoryLimitBytes = 0;
  // A distributed solve (docs/distributed.md): every rank of the communicator creates the engine
  // with the same scene and options and makes the same calls; the sweeps are spread over the
  // ranks (hierarchical/distributed_transport.h) and every rank ends each with the whole solution.
  // The hierarchical method only, swept by Jacobi (the solver option is not read), without the
  // link cache. Null: this process alone.
  std::shared_ptr<Communicator> communicator;
};

}  // namespace lambert
