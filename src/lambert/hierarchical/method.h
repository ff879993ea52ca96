#pragma once
// Hierarchical radiosity with clustering inside the engine (hierarchical/element_hierarchy.h,
// hierarchical/links.h, hierarchical/transport.h). The first solve() runs refinePasses
// refine-then-solve cycles (Hanrahan, Salzman & Aupperle 1991, §5):
//   1. (first pass) elements are split where a light's direct irradiance varies across them by
//      more than the link error allows: at a spot's cone edge and at shadow edges;
//   2. links are refined by the BF oracle from the root cluster down, with the radiosity known so
//      far (emission and direct light at first, then the last solution), each later pass
//      refining the existing links further where their sources turned out brighter;
//   3. new leaves start from their parent's radiosity.
// Later solve() calls (lights moved) re-inject the lights on the existing leaves and re-solve
// warm over the existing links, without refining: the dynamic-light path.
// With a cache directory, the first solve loads what its passes would make (the splits, the
// links and the last pass's warm start) from a file keyed on everything they read, or saves it
// after computing it (hierarchical/link_cache.h).
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "lambert/core/timer.h"
#include "lambert/hierarchical/final_gather.h"
#include "lambert/hierarchical/link_cache.h"
#include "lambert/engine/method.h"
#include "lambert/engine/options.h"
#include "lambert/engine/solve_call.h"
#include "lambert/hierarchical/links.h"
#include "lambert/hierarchical/element_hierarchy.h"
#include "lambert/hierarchical/transport.h"

namespace lambert {

class HierarchicalMethod final : public Method {
 public:
  HierarchicalMethod(const Scene& scene, const RadiosityOptions& options);

  const Mesh& elements() const override { return leaves_.mesh; }
  const RayCaster& caster() const override { return *caster_; }
  std::shared_ptr<const Transport> transport() const override { return transport_; }
  void leadRanks(bool leading) override;
  void serveRanks(const ElementSolution& solution) override;
  Result<bool> refine(const std::vector<Light>& lights, std::vector<Rgb>& radiosity, SolveCallReport& report) override;
  const Mesh& vertexMesh() const override { return leaves_.mesh; }
  std::vector<Rgb> vertexValues(const std::vector<Rgb>& perElement) const override;
  // The final gather (hierarchical/final_gather.h) at every vertex, with the lights' direct light
  // evaluated there too; T-junction vertices are then constrained to their edges.
  Result<std::vector<Rgb>> pointIrradiance(const ElementSolution& solution, std::span<const SurfacePoint> points) const override;
  Result<PointGather> pointGather(const ElementSolution& solution, std::span<const SurfacePoint> points, PointGatherPart part) const override;
  Result<std::vector<Rgb>> nodeMeanRadiosity(const ElementSolution& solution) const override;
  Result<PointGather> vertexGather(const ElementSolution& solution, std::span<const std::uint32_t> vertices, PointGatherPart part) const override;
  // PointGather's light (and weights) at its sites, each through its leaf.
  // atPoints: sites anywhere on the leaves (pointGather), else the vertices (vertexGather), gathered
  // as vertexValues gathers them (FinalGather's resolveClusterVisibility).
  void gatherAt(const ElementSolution& solution, PointGatherPart part, bool atPoints, PointGather& out) const;
  // A distributed solve: the light at the sites (PointGatherPart::Light), each gathered by the
  // rank of its leaf and handed to every rank; Ok where the part can be so gathered.
  void gatherAtAcrossRanks(const ElementSolution& solution, bool atPoints, PointGather& out) const;
  Status spreadOverRanks(PointGatherPart part) const;
  std::vector<std::vector<Rgb>> vertexSolution(const ElementSolution& solution,
                                               std::span<const VertexQuantity> quantities) const override;
  void startSolve(const SolveBudget& budget) override;
  void addStats(Stats& stats) const override;
  Status saveCache() override { return Ok{}; }  // the link cache is written as soon as the links are made

  const ElementHierarchy& hierarchy() const { return hierarchy_; }
  const Links& links() const { return *links_; }

 private:
  void splitAtLightEdges(const std::vector<Light>& lights, double threshold, SolveCallReport& report);
  void rebuildLeaves();
  // The link cache (hierarchical/link_cache.h): loadLinks takes every pass from the file when it holds
  // them (returns whether it did), saveLinks writes them after the last pass.
  bool loadLinks(const std::vector<Light>& lights, std::vector<Rgb>& radiosity);
  // The transport over the current hierarchy and links, spread over the communicator's ranks.
  std::shared_ptr<HierarchicalTransport> makeTransport() const;
  // A distributed solve's share of the hierarchy (docs/distributed.md), fixed at the first
  // refinement: the current leaves cut depth first into one run per rank, balanced by area and
  // count, into nodeRank_; and this rank's nodes for the refinement (hierarchical/links.h).
  void assignRanks();
  LinkShare linkShare() const;
  // After each refinement of a distributed solve, every rank alike: the links over all ranks.
  void countLinksOverRanks();
  struct LinksOverRanks {
    double total = 0;      // each link once (those of a shared node are held by every rank under it)
    double mostHeld = 0;   // by one rank
    double mostBytes = 0;  // one rank's link memory, the largest
  };
  LinksOverRanks linksOverRanks_;
  // The vertices' final gather spread over the ranks: the gathered
  // irradiance at every vertex and the close sources' corner weights, as `whole` (the gather over
  // every vertex, whose sites and leaves it reuses) would give them in one process.
  // A distributed gather's sites by the rank of their leaf: each rank's sites, and the leaves of
  // this rank's (kNoNode for the others'), for a FinalGather over this rank's sites alone; and
  // every rank's values of its own sites (ofMine: indexed by site), back in site order.
  struct SitesByRank {
    std::vector<std::vector<std::uint32_t>> sites;
    std::vector<std::uint32_t> mine;
  };
  SitesByRank sitesByRank(const std::vector<std::uint32_t>& leaf) const;
  template <class T>
  std::vector<T> inSiteOrder(const SitesByRank& split, const std::vector<T>& ofMine) const;
  std::vector<Rgb> gatherAcrossRanks(const FinalGather& whole, const std::vector<Rgb>& mean, FinalGatherCounts& counts,
                                     NearFieldWeights& near) const;
  void saveLinks(const std::vector<Rgb>& warmStart);

  const Scene& scene_;  // the engine's, which owns this strategy
  HierarchicalOptions options_;
  double shadowTolerance_ = 0;  // DirectLightOptions::shadowTolerance: Ward's τ at every point lit here
  double memoryLimitBytes_ = 0;  // RadiosityOptions::memoryLimitBytes
  std::shared_ptr<Communicator> communicator_;  // RadiosityOptions::communicator: the sweeps spread over its ranks
  double sweepCommunicationSeconds_ = 0;         // the earlier passes' transports' exchanges
  // Per node, the rank whose leaves lie under it, or HierarchicalTransport::kSharedNode where several ranks' do (empty
  // until the first refinement of a distributed solve). Each rank holds the links into its own
  // nodes and the shared ones over them.
  std::vector<int> nodeRank_;
  // Rank 0 computing a distributed solve's outputs (leadRanks): each final gather it makes first
  // asks the other ranks (serveRanks) to join it, unless they are making it already (answering_:
  // within a gather asked for, on any rank).
  enum class Ask : std::uint32_t { Done, Vertices, Points };
  struct Asked {
    Ask ask;
    std::uint32_t part;      // Points: the PointGatherPart
    std::uint64_t digest;    // Vertices: the gather's input (acrossRanks_)
  };
  void askRanks(const Asked& asked, std::span<const SurfacePoint> points) const;
  bool leading_ = false;
  mutable int answering_ = 0;
  struct Answering {
    explicit Answering(const HierarchicalMethod& m) : meshing(m) { ++meshing.answering_; }
    ~Answering() { --meshing.answering_; }
    const HierarchicalMethod& meshing;
  };
  // The last vertex gather spread over the ranks, for the vertexSolution calls that follow: the
  // coupled gather and the digest of its input (node means, and the vertices' direct light,
  // emission and albedo).
  struct AcrossRanks {
    std::uint64_t digest = 0;
    std::vector<Rgb> gathered;
  };
  mutable AcrossRanks acrossRanks_;  // under gatherCacheMutex_
  Timer created_;  // started before the hierarchy is built
  ElementHierarchy hierarchy_;
  ElementHierarchy::LeafMesh leaves_;
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
  struct LinkCacheFile {
    std::string directory;        // RadiosityOptions::cacheDirectory; empty: off
    RadiosityOptions options;     // what the key reads of them
    SolveBudget firstBudget;      // of the first solve
    std::string path;             // the file, once keyed
    std::uint64_t key = 0;
    std::string status = "off";   // the formfactor_cache stat
    std::uint64_t bytes = 0;      // the file's size, loaded or saved
    double seconds = 0;           // keying, loading and replaying, or saving
  } linkCache_;
  // The final gather's visibility and irradiance files beside the links (hierarchical/link_cache.h):
  // read before the first gather over the last pass's links. The visibility file is written after
  // that gather where it held nothing usable; the irradiance file where it held no values for
  // that gather's input (so it holds the last process's first gather).
  struct GatherCacheFile {
    bool tried = false;
    std::shared_ptr<const GatherVisibility> known;
    std::uint64_t knownDigest = 0;  // gatherVisibilityDigest(known)
    std::string status = "off";  // the gather_cache stat
    std::uint64_t bytes = 0;     // the file's size, loaded or saved
    double seconds = 0;          // loading or saving
    std::shared_ptr<const CachedGatherIrradiance> irradiance;
    std::string irradianceStatus = "off";  // the gather_irradiance_cache stat
    std::uint64_t irradianceBytes = 0;     // the file's size, loaded or saved
    std::uint64_t irradianceReads = 0;     // gathers whose result was read from it
    double irradianceSeconds = 0;          // digests, loading or saving
  };
  mutable std::mutex gatherCacheMutex_;
  mutable GatherCacheFile gatherCache_;
  // The last final gather's work (vertexSolution is const and may run on any thread).
  mutable std::mutex gatherMutex_;
  mutable FinalGatherCounts gatherCounts_;
  mutable std::size_t nearFieldWeights_ = 0;
  mutable int nearFieldIterations_ = 0;
  mutable double gatherSeconds_ = 0;
  // vertexValues' interpolation over the leaf mesh, made once per leaf mesh (lightmap updates
  // call it every frame): leafMeshGeneration_ counts the leaf meshes (and their open fractions).
  int leafMeshGeneration_ = 0;
  mutable std::mutex interpolationMutex_;
  mutable std::shared_ptr<const VertexInterpolation> interpolation_;
  mutable int interpolationGeneration_ = -1;
};

}  // namespace lambert
