#pragma once
// The flat method's options: the uniform mesh, the adaptive quad-tree and the form factors
// between their elements (flat/form_factors.h). Collected by method/options.h.
#include <cstddef>
#include <cstdint>
#include <string>

namespace lambert {

enum class FormFactorMethod {
  // One kernel evaluation and one visibility ray between the patches' incircle centres.
  PointToPoint,
  // Area-to-area Monte Carlo: low-discrepancy sample points x_k on patch i, each paired with a point
  // y_k on patch j; F_ij ≈ 1/N Σ_k F(x_k → P_j) V(x_k, y_k) with the analytic point-to-polygon
  // factor, so adjacent patches stay finite and exact when unoccluded (Wallace, Elmquist & Haines
  // 1989 use the same split of kernel and visibility).
  AreaMonteCarlo,
  // Cohen & Greenberg's hemi-cube at each patch's centroid (flat/hemicube.h): a row at a time.
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

struct QuadtreeOptions {
  double baseEdgeLength = 100;  // scene units: level-0 cells are no longer than this
  int maxLevel = 3;             // deepest level; each level halves a cell's sides
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
  int passesPerSolve = 3;
};

}  // namespace lambert
