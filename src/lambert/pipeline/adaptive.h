#pragma once
// Radiosity on an adaptive quad-tree mesh for moving lights (seed 003). Each update:
//   1. adapts the mesh: a cell is split where a spot's cone edge or a shadow edge crosses it
//      (down to the deepest level), or where its corners' radiosity differs by more than a
//      threshold (one level per update); four sibling leaves are merged back where none of that
//      holds any more, so the mesh stays coarse away from the lights' detail;
//   2. assembles F for the active cells from the master table (new pairs computed, known ones
//      reused, never recomputed);
//   3. injects the lights' direct light and solves, warm-started from the last solution (new
//      cells start from their parent's radiosity, merged ones from their children's average).
#include <memory>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/formfactor/table.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/light/lights.h"
#include "lambert/mesh/quadtree.h"
#include "lambert/solve/solver.h"

namespace lambert {

struct AdaptiveOptions {
  QuadtreeOptions quadtree;
  FormFactorOptions formFactors;
  DirectLightOptions direct;
  bool refineAtSpotEdges = true;
  bool refineAtShadowEdges = true;
  // Split a leaf whose corner radiosities span more than this × the mean radiosity (luminance);
  // 0 turns the criterion off.
  double gradientThreshold = 0.5;
  bool normalizeRows = false;  // seed 003's row normalisation (see normalizeRows)
  double tolerance = 1e-6;     // Gauss–Seidel, per update
};

struct AdaptiveUpdate {
  int refined = 0;
  int coarsened = 0;
  std::size_t activeNodes = 0;
  std::size_t nodes = 0;             // ever created
  std::uint64_t pairsEstimated = 0;  // this update
  std::uint64_t pairsReused = 0;     // this update
  int iterations = 0;
  double adaptSeconds = 0, formFactorSeconds = 0, injectSeconds = 0, solveSeconds = 0;
};

class AdaptiveRadiosity {
 public:
  // Fails (naming the surface) when the scene has surfaces that are not quads.
  static Result<std::unique_ptr<AdaptiveRadiosity>> create(const Scene& scene, const AdaptiveOptions& options);

  AdaptiveUpdate update(const std::vector<Light>& lights);

  const AdaptiveMesh& mesh() const { return mesh_; }
  const RayCaster& caster() const { return *caster_; }
  const FormFactorTable& table() const { return *table_; }
  const RadiosityProblem& problem() const { return problem_; }
  // Per active node (mesh().activeNodes() order), W/m².
  const std::vector<Rgb>& radiosity() const { return radiosity_; }
  const std::vector<Rgb>& injected() const { return injected_; }
  std::vector<Rgb> indirectRadiosity() const;
  // Albedo of each patch of mesh().fineMesh(), for drawing direct light on it.
  std::vector<Rgb> fineAlbedo() const;

  // Whether a spot's cone edge crosses the cell (some of its corners lit and some not, or the
  // beam's axis landing inside it), and whether a light's shadow edge does.
  static bool crossesSpotEdge(const Light& light, const PatchCorners& corners, const Vec3& normal);
  bool crossesShadowEdge(const Light& light, const PatchCorners& corners, const Vec3& normal) const;

 private:
  AdaptiveRadiosity(const Scene& scene, AdaptiveMesh mesh, const AdaptiveOptions& options);
  bool mustSplit(std::uint32_t node, const std::vector<Light>& lights) const;
  void adapt(std::uint32_t node, const std::vector<Light>& lights, const std::vector<char>& steep, AdaptiveUpdate& update);
  void refineNode(std::uint32_t node, AdaptiveUpdate& update);

  Scene scene_;
  AdaptiveOptions options_;
  AdaptiveMesh mesh_;
  Mesh baseMesh_;  // the level-0 cells, for visibility
  std::unique_ptr<RayCaster> caster_;
  std::unique_ptr<FormFactorTable> table_;
  double epsilon_ = 0;
  std::vector<Rgb> nodeRadiosity_;  // last known B per node id, to warm-start from
  std::vector<std::uint32_t> lastActive_;
  RadiosityProblem problem_;
  std::vector<Rgb> radiosity_;
  std::vector<Rgb> injected_;
};

}  // namespace lambert
