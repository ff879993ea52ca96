#pragma once
// A distributed solve of the hierarchical method (docs/distributed.md): the one interface its
// serial code calls for the ranks, made with RadiosityOptions::communicator. Without one (a
// single process) it holds no ranks and every call does nothing: distributed() and acrossRanks()
// say so where the method must choose. With one, it fixes each rank's share of the hierarchy at
// the first refinement (the leaves cut depth first into one run per rank, balanced by area and
// count), hands the refinement this rank's share (hierarchical/distributed_links.h), makes the
// transport that sweeps over the ranks (hierarchical/distributed_transport.h), and spreads the
// final gathers of the outputs over them (distributed_gathers.cpp): each site gathered by the
// rank of its leaf, through its own links, while rank 0, writing the outputs, leads the others.
// Its own file so that the method's serial path holds no rank logic.
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

#include "lambert/core/communicator.h"
#include "lambert/core/error.h"
#include "lambert/core/stats.h"
#include "lambert/method/point_gather.h"
#include "lambert/method/solution.h"
#include "lambert/hierarchical/distributed_links.h"
#include "lambert/hierarchical/distributed_transport.h"
#include "lambert/hierarchical/element_hierarchy.h"
#include "lambert/hierarchical/final_gather.h"
#include "lambert/hierarchical/links.h"

namespace lambert {

class HierarchyRanks {
 public:
  explicit HierarchyRanks(std::shared_ptr<Communicator> communicator);

  // A distributed solve (one rank included), and one whose outputs are gathered across ranks.
  bool distributed() const { return communicator_ != nullptr; }
  bool acrossRanks() const { return communicator_ && communicator_->size() > 1; }

  // The refinement and the sweeps (distributed_ranks.cpp).
  // This rank's share of a refinement of `hierarchy` (none in one process). The first fixes the
  // ranks' shares of the current leaves.
  std::optional<LinkShare> linkShare(const ElementHierarchy& hierarchy);
  // After each refinement, every rank alike: the nodes from nodesBefore on (the elements split)
  // take their parent's rank, and the links over all ranks are counted.
  void refined(const ElementHierarchy& hierarchy, std::size_t nodesBefore, const Links& links);
  // Whether the ranks share the hierarchy (from the first refinement): the transport is then theirs.
  bool assigned() const { return !nodeRank_.empty(); }
  std::shared_ptr<const HierarchicalTransport> makeTransport(const ElementHierarchy& hierarchy, std::shared_ptr<const Links> links,
                                                             std::span<const double> leafOpenFraction, std::span<const Rgb> leafAlbedo);
  // The figures of a distributed solve, where the method lists them: the ranks and what they
  // exchanged (transportSize: the leaves the transport sweeps), and the links over all ranks
  // (links: this rank's).
  void addCommunicationStats(Stats& stats, std::size_t transportSize) const;
  void addLinkStats(Stats& stats, const Links& links) const;

  // The outputs' gathers (distributed_gathers.cpp).
  // Rank 0 computing a distributed solve's outputs (Method::leadRanks): each final gather it
  // makes first asks the other ranks, waiting in serve(), to join it; lead(false) lets them go.
  void lead(bool leading);
  // The other ranks: makes every gather rank 0 asks for (the vertices' radiosity, or the points'
  // gather of a part) until it lets them go.
  void serve(const std::function<void()>& gatherVertices,
             const std::function<void(std::span<const SurfacePoint>, PointGatherRequest)>& gatherPoints);
  // Ok where the part can be gathered across the ranks.
  Status canGather(PointGatherRequest part) const;
  // Rank 0 leading: asks the others to join a gather of the part at the points.
  void askForPoints(PointGatherRequest part, std::span<const SurfacePoint> points) const;
  // The vertices' final gather spread over the ranks: the gathered irradiance at every vertex
  // with the close sources' corners coupled (FinalGather::coupleNearField), as `whole` (the gather
  // over every vertex, whose sites and leaves it reuses) would give it in one process; counts and
  // near as the gather leaves them. The last one is kept for the calls that follow with the same
  // input (node means, and the vertices' direct light, emission and albedo).
  std::vector<Rgb> gatherAtVertices(const FinalGather& whole, const std::vector<Rgb>& mean, const std::vector<Rgb>& direct,
                                    const std::vector<Rgb>& emitted, const std::vector<Rgb>& albedo, FinalGatherCounts& counts,
                                    NearFieldWeights& near, NearFieldCoupling* coupling) const;
  // The light at the sites of `whole` (PointGatherRequest::Light), each gathered by the rank of its
  // leaf and handed to every rank; cornerRadiosity: the vertices' radiosity the close sources'
  // corners read (asked for within the gather).
  std::vector<Rgb> gatherAtSites(const FinalGather& whole, const std::vector<Rgb>& mean,
                                 const std::function<std::vector<Rgb>()>& cornerRadiosity) const;

 private:
  // The first refinement's cut: the current leaves depth first into one run per rank, balanced
  // by area and count, into nodeRank_.
  void assignRanks(const ElementHierarchy& hierarchy);
  // After each refinement, every rank alike: the links over all ranks.
  void countLinksOverRanks(const ElementHierarchy& hierarchy, const Links& links);
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
  // The vertices' gather spread over the ranks: the gathered irradiance at every vertex and the
  // close sources' corner weights.
  std::vector<Rgb> gatherAcrossRanks(const FinalGather& whole, const std::vector<Rgb>& mean, FinalGatherCounts& counts,
                                     NearFieldWeights& near) const;
  enum class Ask : std::uint32_t { Done, Vertices, Points };
  struct Asked {
    Ask ask;
    std::uint32_t part;      // Points: the PointGatherRequest
    std::uint64_t digest;    // Vertices: the gather's input (lastAtVertices_)
  };
  // Rank 0 leading asks the others to join, unless they are making the gather already
  // (answering_: within a gather asked for, on any rank).
  void askRanks(const Asked& asked, std::span<const SurfacePoint> points) const;
  struct Answering {
    explicit Answering(const HierarchyRanks& r) : ranks(r) { ++ranks.answering_; }
    ~Answering() { --ranks.answering_; }
    const HierarchyRanks& ranks;
  };

  std::shared_ptr<Communicator> communicator_;  // null: one process
  // Per node, the rank whose leaves lie under it, or DistributedTransport::kSharedNode where
  // several ranks' do (empty until the first refinement). Each rank holds the links into its own
  // nodes and the shared ones over them.
  std::vector<int> nodeRank_;
  struct LinksOverRanks {
    double total = 0;      // each link once (those of a shared node are held by every rank under it)
    double mostHeld = 0;   // by one rank
    double mostBytes = 0;  // one rank's link memory, the largest
  };
  LinksOverRanks linksOverRanks_;
  std::shared_ptr<const DistributedTransport> transport_;  // the last one made
  double sweepCommunicationSeconds_ = 0;                    // the earlier passes' transports' exchanges
  bool leading_ = false;
  mutable int answering_ = 0;
  // The last vertex gather spread over the ranks, for the vertexSolution calls that follow: the
  // coupled gather and the digest of its input.
  struct LastAtVertices {
    std::uint64_t digest = 0;
    std::vector<Rgb> gathered;
  };
  mutable std::mutex lastAtVerticesMutex_;
  mutable LastAtVertices lastAtVertices_;
};

}  // namespace lambert
