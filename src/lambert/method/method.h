#pragma once
// The mesh strategies inside the engine (engine/radiosity.h): each owns the elements B is solved
// on, a ray caster over the scene's geometry, and the transport between its elements, and
// turns per-element values into continuous per-vertex values. The engine does the rest (lights,
// emission, solving) the same way for every strategy.
//
//   UniformMethod   longest-edge bisection; the dense matrix is computed (or read
//                    from the .lff cache) once, with any form-factor method (a DenseTransport).
//   AdaptiveMethod  a quad-tree; refine() follows the lights every solve, F is
//                    assembled from the master table (.lft cache), a DenseTransport.
//                    Pair-wise methods only.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/stats.h"
#include "lambert/method/solution.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/mesh/mesh.h"
#include "lambert/scene/scene.h"
#include "lambert/solve/transport.h"

namespace lambert {

struct RadiosityOptions;
struct SolveBudget;
struct SolveReport;
struct PointGather;  // method/point_gather.h
enum class PointGatherRequest;

// The engine's solution per element, for Method::vertexSolution. W/m²; ρ dimensionless.
struct ElementSolution {
  const std::vector<Rgb>& radiosity;  // B
  const std::vector<Rgb>& injected;   // the lights' ρ·E_direct
  const std::vector<Rgb>& skyInjected;  // the skies' part of it (empty before the first injection)
  const std::vector<Rgb>& emitted;    // the surfaces' own emission
  const std::vector<Rgb>& albedo;     // ρ
  const std::vector<Light>& lights;
  double metresPerUnit;
};

// B less the direct light a hybrid image draws per pixel (every light's but a sky's), per element.
std::vector<Rgb> indirectRadiosity(const ElementSolution& solution);

class Method {
 public:
  virtual ~Method() = default;

  virtual const Mesh& elements() const = 0;
  virtual const RayCaster& caster() const = 0;
  virtual std::shared_ptr<const Transport> transport() const = 0;  // between elements()

  // Adapts the elements to the lights and to the last solution (B per current element; empty
  // before the first solve). Returns whether the elements changed; then elements() and
  // transport() describe the new ones and radiosity holds a warm start for them. Adds what it
  // did (cells split and merged, pairs estimated, times) to report. An Error when the refined
  // elements would not fit in the memory the options allow (core/memory.h).
  virtual Result<bool> refine(const std::vector<Light>& lights, std::vector<Rgb>& radiosity, SolveReport& report) = 0;
  // The budget of the solve() about to refine (hierarchical meshing keys its link cache on the
  // budget of the solves between its first refinement passes).
  virtual void startSolve(const SolveBudget& /*budget*/) {}

  virtual const Mesh& vertexMesh() const = 0;
  // Continuous per-vertex values of any per-element quantity, interpolated.
  virtual std::vector<Rgb> vertexValues(const std::vector<Rgb>& perElement) const = 0;
  // The solution at the vertices, one array per quantity asked for. By default the per-element
  // quantity interpolated (vertexValues); hierarchical meshing gathers at the vertices
  // themselves instead (hierarchical/final_gather.h), once for all the quantities.
  // neededVertices (SolutionView::vertexValues): empty, or one flag per vertex, where a method
  // that computes vertex by vertex may compute the flagged ones alone.
  virtual std::vector<std::vector<Rgb>> vertexSolution(const ElementSolution& solution, std::span<const VertexQuantity> quantities,
                                                       std::span<const std::uint8_t> neededVertices = {}) const;

  // pointGather (SolutionView::pointIrradiance's light from the surfaces), vertexGather and
  // nodeMeanRadiosity (engine/solution_internals.h): Errors but for hierarchical meshing.
  virtual Result<PointGather> pointGather(const ElementSolution& solution, std::span<const SurfacePoint> points, PointGatherRequest part) const;
  virtual Result<std::vector<Rgb>> nodeMeanRadiosity(const ElementSolution& solution) const;
  virtual Result<PointGather> vertexGather(const ElementSolution& solution, std::span<const std::uint32_t> vertices, PointGatherRequest part) const;
  // The strategy's figures: mesh, form-factor method, times, cache.
  // A distributed solve's outputs (Radiosity::leadDistributedOutputs): rank 0 leads (true) while
  // it computes them, its final gathers asking the other ranks, waiting in serveRanks, to join
  // in; leadRanks(false) lets them go. Nothing otherwise.
  virtual void leadRanks(bool /*leading*/) {}
  virtual void serveRanks(const ElementSolution& /*solution*/) {}
  virtual void addStats(Stats& stats) const = 0;
  // Writes the cache file if it is out of date (only the adaptive table can be).
  virtual Status saveCache() = 0;
};

// Chooses the strategy options.meshing names; errors say why a combination cannot work.
Result<std::unique_ptr<Method>> makeMethod(const Scene& scene, const RadiosityOptions& options);

}  // namespace lambert
