#pragma once
// The options of a solve, as plain structs and enums: what Radiosity::create takes
// (RadiosityOptions) and each part of it. Public (installed) without the internals that read
// them: the link refinement, the element hierarchy, the quad-tree, the form-factor matrix and the
// solvers include this header, not the other way round. The CLI's names for them, with its
// defaults and checks, are engine/solve_settings.h.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "lambert/light/lights.h"

namespace lambert {

class Communicator;

enum class FormFactorMethod {
  // Seed 000: one kernel evaluation and one visibility ray between the patches' incircle centres.
  PointToPoint,
  // Area-to-area Monte Carlo: low-discrepancy sample points x_k on patch i, each paired with a point
  // y_k on patch j; F_ij ≈ 1/N Σ_k F(x_k → P_j) V(x_k, y_k) with the analytic point-to-polygon
  // factor, so adjacent patches stay finite and exact when unoccluded (Wallace, Elmquist & Haines
  // 1989 use the same split of kernel and visibility).
  AreaMonteCarlo,
  // Cohen & Greenberg's hemi-cube at each patch's centroid (formfactor/hemicube.h): a row at a time.
  Hemicube,
  // Cosine-distributed rays from points over each patch: a row at a time.
  HemisphereRays,
};

std::string formFactorMethodName(FormFactorMethod method);

struct FormFactorOptions {
  FormFactorMethod method = FormFactorMethod::AreaMonteCarlo;
  int samplePairs = 16;        // per patch pair, AreaMonteCarlo only; powers of two stratify best
  int nearFieldBoost = 16;     // sample multiplier for pairs closer than twice their size
  int hemicubeResolution = 256;  // Hemicube: pixels along the top face (even)
  int hemisphereRays = 1024;     // HemisphereRays: rays per patch
  std::uint64_t seed = 1;      // results depend on (seed, pair), never on thread count
  bool showProgress = true;    // a progress line when stderr is a terminal
};

struct LinkOptions {
  double linkError = 2e-4;     // relative power a link may carry unrefined
  double minElementArea = 0;   // scene units²; 0: the scene's area × 1e-5
  int visibilityRays = 8;      // per link
  bool clusters = true;        // false: start from every pair of faces (no cluster links)
  std::uint64_t seed = 1;
  bool showProgress = false;
  double memoryLimitBytes = 0;  // core/memory.h: refinement stops when its links would not fit
};

struct QuadtreeOptions {
  double baseEdgeLength = 100;  // scene units: level-0 cells are no longer than this
  int maxLevel = 3;             // deepest level; each level halves a cell's sides
};

enum class SolverKind {
  Direct,       // Eigen LU of (I − ρF): seed 001's "Gaussian elimination"; dense transport only
  GaussSeidel,  // in-place gathering sweeps (seed 000); any transport
  Jacobi,       // gathering sweeps from the previous iterate, rows in parallel; any transport
  Shooting,     // progressive refinement (Cohen, Chen, Wallace & Greenberg 1988; seed 001); dense only
};

std::string solverName(SolverKind kind);

enum class MeshStrategy {
  Uniform,   // longest-edge bisection to a patch count or edge length (seed 000), computed once
  Adaptive,  // quad-tree cells split at spot, shadow and radiosity edges (seed 003), every solve
  // Element trees under clusters, linked by the BF oracle (Hanrahan, Salzman & Aupperle 1991;
  // Smits, Arvo & Greenberg 1994): near-linear in the number of faces
  Hierarchical,
};

struct UniformMeshOptions {
  std::size_t targetPatches = 784;  // used when maxEdgeLength is 0
  double maxEdgeLength = 0;         // scene units; 0 picks it from targetPatches
};

struct AdaptiveMeshOptions {
  // baseEdgeLength 0: a sixth of the scene's diagonal.
  QuadtreeOptions quadtree{0, 3};
  bool refineAtSpotEdges = true;
  bool refineAtShadowEdges = true;
  // Split a leaf whose corner radiosities span more than this × the mean radiosity (luminance);
  // 0 turns the criterion off. Leaves merge back below half of it.
  double gradientThreshold = 0.5;
  // Refine-and-solve passes in each solve(): the gradient criterion judges the previous pass.
  int passesPerSolve = 1;
};

struct HierarchicalOptions {
  LinkOptions links;         // link error, minimum element area, visibility rays, clustering
  int refinePasses = 2;      // refine-then-solve cycles in the first solve()
  bool refineAtLights = true;  // split elements at spot-cone and shadow edges first
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
  bool normalizeRows = false;    // seed 003's row normalisation (formfactor/table.h): adds energy
  DirectLightOptions directLight;
  SolverKind solver = SolverKind::GaussSeidel;
  double tolerance = 1e-7;       // relative change (gs, jacobi) or unshot power fraction (shoot)
  int maxIterations = 1000;      // sweeps (gs, jacobi); shots per element (shoot)
  // Where form factors (uniform: the matrix, .lff), the master table (adaptive, .lft) or the
  // hierarchy's links (hierarchical, .lhl: engine/link_cache.h) are read and written; empty:
  // always computed, never saved.
  std::string cacheDirectory;
  // Bytes a solve may use for its large structures (core/memory.h); 0: the machine's available
  // memory. A solve whose estimate exceeds it is refused (create or solve returns the Error).
  double memoryLimitBytes = 0;
  // A distributed solve (docs/distributed.md): every rank of the communicator creates the engine
  // with the same scene and options and makes the same calls; the sweeps are spread over the
  // ranks (HierarchicalTransport::distribute) and every rank ends each with the whole solution.
  // The hierarchical method only, swept by Jacobi (the solver option is not read), without the
  // link cache. Null: this process alone.
  std::shared_ptr<Communicator> communicator;
};

}  // namespace lambert
