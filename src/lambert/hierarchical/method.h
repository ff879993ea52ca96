#pragma once
// Hierarchical radiosity with clustering inside the engine (hierarchical/element_hierarchy.h,
// hierarchical/links.h, hierarchical/transport.h). The first solve() runs refinePasses
// refine-then-solve cycles (Hanrahan, Salzman & Aupperle 1991, §5):
//   1. (first pass) elements are split where a light's direct irradiance varies across them by
//      more than the link error allows: at a spot's cone edge and at shadow edges
//      (hierarchical/light_edges.h);
//   2. links are refined by the BF oracle from the root cluster down (hierarchical/refiner.h), with
//      the radiosity known so far (emission and direct light at first, then the last solution),
//      each later pass refining the existing links further where their sources turned out brighter;
//   3. new leaves start from their parent's radiosity.
// Later solve() calls (lights moved) re-inject the lights on the existing leaves and re-solve
// warm over the existing links, without refining: the dynamic-light path.
// With a cache directory, the first solve loads what its passes would make (the splits, the
// links and the last pass's warm start) from a file keyed on everything they read, or saves it
// after computing it (hierarchical/link_cache.h).
//
// The method's files: method.cpp (creation, the refinement passes, the engine's calls),
// method_cache.cpp (its cache files), vertex_outputs.cpp and point_outputs.cpp (the final
// gather at the vertices and at points), method_stats.cpp (its figures); a distributed solve's
// ranks stay behind hierarchical/distributed_ranks.h.
#include <memory>
#include <mutex>
#include <vector>

#include "lambert/core/timer.h"
#include "lambert/method/method.h"
#include "lambert/method/options.h"
#include "lambert/method/solve_call.h"
#include "lambert/hierarchical/distributed_ranks.h"
#include "lambert/hierarchical/element_hierarchy.h"
#include "lambert/hierarchical/final_gather.h"
#include "lambert/hierarchical/links.h"
#include "lambert/hierarchical/method_cache.h"
#include "lambert/hierarchical/refiner.h"
#include "lambert/hierarchical/transport.h"

namespace lambert {

class HierarchicalMethod final : public Method {
 public:
  HierarchicalMethod(const Scene& scene, const RadiosityOptions& options);

  const Mesh& elements() const override { return leaves_.mesh; }
  const RayCaster& caster() const override { return *caster_; }
  std::shared_ptr<const Transport> transport() const override { return transport_; }
  void startSolve(const SolveBudget& budget) override;
  Result<bool> refine(const std::vector<Light>& lights, std::vector<Rgb>& radiosity, SolveReport& report) override;
  Status saveCache() override { return Ok{}; }  // the link cache is written as soon as the links are made

  const Mesh& vertexMesh() const override { return leaves_.mesh; }
  std::vector<Rgb> vertexValues(const std::vector<Rgb>& perElement) const override;
  // The final gather (hierarchical/final_gather.h) at every vertex, with the lights' direct light
  // evaluated there too; T-junction vertices are then constrained to their edges. With
  // neededVertices, at those, the ends of the edges they hang on and their close sources' corners
  // alone (not across ranks: every rank gathers its own share of every vertex); the corners' own
  // close corners outside these take the elements' interpolated radiosity (vertexValues).
  std::vector<std::vector<Rgb>> vertexSolution(const ElementSolution& solution, std::span<const VertexQuantity> quantities,
                                               std::span<const std::uint8_t> neededVertices = {}) const override;
  Result<PointGather> pointGather(const ElementSolution& solution, std::span<const SurfacePoint> points, PointGatherRequest part) const override;
  Result<std::vector<Rgb>> nodeMeanRadiosity(const ElementSolution& solution) const override;
  Result<PointGather> vertexGather(const ElementSolution& solution, std::span<const std::uint32_t> vertices, PointGatherRequest part) const override;
  void leadRanks(bool leading) override;
  void serveRanks(const ElementSolution& solution) override;
  void addStats(Stats& stats) const override;

  const ElementHierarchy& hierarchy() const { return hierarchy_; }
  const Links& links() const { return *links_; }

 private:
  // The refinement (method.cpp).
  void refineAtLightEdges(const std::vector<Light>& lights, double threshold, SolveReport& report);
  // Sets the open fraction of every leaf inside a closed two-sided object to 0 (after measuring).
  void closeEnclosedLeaves();
  void rebuildLeaves();
  // The transport over the current hierarchy and links, spread over the ranks once they share
  // the hierarchy.
  std::shared_ptr<const HierarchicalTransport> makeTransport();
  static std::vector<double> openFractions(const Mesh& mesh);
  // The link cache (method_cache.cpp): loadLinks takes every pass from the file when it holds
  // them (returns whether it did), saveLinks writes them after the last pass.
  bool loadLinks(const std::vector<Light>& lights, std::vector<Rgb>& radiosity);
  void saveLinks(const std::vector<Rgb>& warmStart);

  // The outputs (vertex_outputs.cpp, point_outputs.cpp).
  // The gather at every vertex with its close sources' corners coupled, in one process: read
  // from the gather's irradiance file where it holds this input's, else computed.
  std::vector<Rgb> gatherAtVertices(const FinalGather& gather, const std::vector<Rgb>& mean, const std::vector<Rgb>& direct,
                                    const std::vector<Rgb>& emitted, const std::vector<Rgb>& albedo, FinalGatherCounts& counts,
                                    NearFieldWeights& near, NearFieldCoupling& coupling) const;
  // The radiosity at every vertex (vertexSolution's), whose values the close sources' corner
  // weights read.
  std::vector<Rgb> vertexRadiosity(const ElementSolution& solution) const;
  // PointGather's light (and weights) at its sites, each through its leaf.
  // atPoints: sites anywhere on the leaves (pointGather), else the vertices (vertexGather), gathered
  // as vertexValues gathers them (FinalGather's resolveClusterVisibility).
  void gatherAt(const ElementSolution& solution, PointGatherRequest part, bool atPoints, PointGather& out) const;

  const Scene& scene_;  // the engine's, which owns this strategy
  HierarchicalOptions options_;
  double shadowTolerance_ = 0;  // DirectLightOptions::shadowTolerance: Ward's τ at every point lit here
  double memoryLimitBytes_ = 0;  // RadiosityOptions::memoryLimitBytes
  // RadiosityOptions::communicator's ranks: the links, the sweeps and the outputs' gathers spread
  // over them (without a communicator, one process: no ranks).
  HierarchyRanks ranks_;
  Timer created_;  // started before the hierarchy is built
  ElementHierarchy hierarchy_;
  ElementHierarchy::LeafMesh leaves_;
  // The leaves as they are at the start (the hierarchy's faces), their ray caster and its faces.
  void useFaces();
  std::size_t leafMeshNodes_ = 0;  // the hierarchy's nodes when leaves_ was made
  std::vector<std::uint32_t> measuredLeafNodes_;  // per leaf, its node when its open fraction was measured
  std::unique_ptr<RayCaster> caster_;  // over the faces: elements only split them
  double epsilon_ = 0;
  std::shared_ptr<const Links> links_;
  std::vector<std::uint64_t> casterFace_;  // per patch of the mesh caster_ was built from: surface << 32 | face
  std::shared_ptr<const HierarchicalTransport> transport_;
  int passesDone_ = 0;
  RefinementReport refinement_;
  std::uint64_t lightSplits_ = 0, lightSamples_ = 0, lightEdgeRays_ = 0;
  double buildSeconds_ = 0, bvhSeconds_ = 0, lightSeconds_ = 0, leafSeconds_ = 0, coverageSeconds_ = 0, transportSeconds_ = 0;
  LinkCacheFile linkCache_;
  mutable GatherCacheFiles gatherCache_;
  // The last final gather's work (vertexSolution is const and may run on any thread).
  mutable std::mutex gatherMutex_;
  mutable FinalGatherCounts gatherCounts_;
  mutable std::size_t nearFieldWeights_ = 0;
  mutable NearFieldCoupling nearFieldCoupling_;
  mutable double gatherSeconds_ = 0;
  // The last vertex gather's coupled result and its input's digest (the node means, the vertices'
  // direct light, emission and albedo, the leaf mesh and links it ran over): a later call with
  // the same input in this process (Python's vertex_radiance then vertex_values, a picture then
  // its glb) reuses it instead of gathering again.
  struct LastVertexGather {
    std::uint64_t inputDigest = 0;
    const Links* links = nullptr;
    int leafMeshGeneration = -1;
    std::vector<std::uint8_t> wanted;  // the vertices gathered (vertexSolution); empty: every one
    std::shared_ptr<const std::vector<Rgb>> gathered;
  };
  mutable LastVertexGather lastVertexGather_;
  mutable std::uint64_t gatherReuses_ = 0;  // vertex outputs answered by it
  // vertexValues' interpolation over the leaf mesh, made once per leaf mesh (lightmap updates
  // call it every frame): leafMeshGeneration_ counts the leaf meshes (and their open fractions).
  int leafMeshGeneration_ = 0;
  mutable std::mutex interpolationMutex_;
  mutable std::shared_ptr<const VertexInterpolation> interpolation_;
  mutable int interpolationGeneration_ = -1;
};

}  // namespace lambert
