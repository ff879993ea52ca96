#pragma once
// One candidate link as the refinement (hierarchical/refiner.h) sees it, and what estimates it:
// its K, visibility and verdict by the kernels hierarchical/links.h describes (links.cpp), and the
// BF oracle that judges it against the link error. The refiner's waves decide which candidates
// there are; this decides what one is worth. Its own header so that the two meet here and each
// keeps its own file (refiner.cpp, links.cpp). Internal to hierarchical/.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "lambert/geometry/normal_cone.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/hierarchical/element_hierarchy.h"
#include "lambert/method/hierarchical_options.h"

namespace lambert {

// Estimated: K and visibility known. Inadmissible: too close for the estimate, to be split.
// Occluded: every ray blocked; a few rays are weak evidence (a mostly shadowed element would lose
// its sliver of light every time), so it is split where it could carry too much unoccluded.
// Empty: the two cannot exchange light (back to back, coplanar, or the same element).
// Coarse: the oracle refines it, and splits the same node, whatever its K and visibility come out
// as (its bound is known before any ray): it is not estimated, since judge() would not read it.
enum class Verdict : std::uint8_t { Estimated, Inadmissible, Occluded, Empty, Coarse };

struct Candidate {
  std::uint32_t receiver, source;
  float formFactor = 0;        // K with visibility
  float uncertainty = 0;       // how far K may be from the truth over the receiver (the oracle's factor)
  bool receiverSide = false;   // the uncertainty is the factor's spread over the receiver, or r's
                               // points see nothing of s: split the receiver
  bool openSource = false;     // inadmissible until the source (a cluster) opens: split it first
  bool openReceiver = false;   // inadmissible until the receiver (a cluster) opens: split it first
  Verdict verdict = Verdict::Estimated;
  bool estimated = false;      // already estimated (a previous link judged again)
  float judgedTransfer = -1;   // cluster links: the oracle's transfer (judgedTransfer()); < 0 until computed
  std::array<std::uint8_t, 6> facing{};  // into a cluster: Links::facing
};

class LinkEstimator {
 public:
  // The leaves' radiosities (their largest channel, W/m², one per current leaf) pulled up to
  // every node as area-weighted means, the oracle's threshold (linkError × the scene's power) and
  // which nodes hold a partly covered leaf (leafOpenFraction below 1), as refineLinks takes them.
  LinkEstimator(const ElementHierarchy& hierarchy, const RayCaster& caster, double rayEpsilon,
                std::span<const std::uint64_t> casterFace, const LinkOptions& options, std::span<const double> leafRadiosity,
                std::span<const double> leafOpenFraction);

  // Fills in the candidate's verdict, K and visibility; returns the rays it cast.
  std::uint8_t estimate(Candidate& c) const;
  // The transfer a cluster link is judged by (links.cpp says why not by its own K).
  double judgedTransfer(const Candidate& c) const;

  // The BF oracle: B_s · ΔK · A_r above the threshold.
  bool tooCoarse(const Candidate& c, double uncertainty) const {
    return radiosity_[c.source] * uncertainty * h_.node(c.receiver).area > threshold_;
  }

  // What the BF oracle leaves out: a link hands its receiver the source's mean radiosity, but a
  // receiver close to a source whose leaves differ (a ceiling lit bright only over a lamp panel
  // hung under it) sees some of them far more than others. The transfer that may be wrong by
  // it, (B_peak − B̄_s) · K · A_r, above the threshold: only splitting the source makes it smaller.
  bool sourceVariesTooMuch(const Candidate& c) const {
    return (peakRadiosity_[c.source] - radiosity_[c.source]) * c.formFactor * h_.node(c.receiver).area > threshold_;
  }

  bool splittable(std::uint32_t node) const {
    const HierarchyNode& n = h_.node(node);
    return n.isCluster() || !n.isLeaf() || n.area * childAreaShare(n) >= minArea_;
  }

  // Per node: the area-weighted mean of the leaves' largest channel; and the oracle's threshold.
  double radiosity(std::uint32_t node) const { return radiosity_[node]; }
  double threshold() const { return threshold_; }
  // The children of a node just split start from its estimates.
  void addChildren(std::uint32_t node);

 private:
  struct Visibility;
  struct ClusterSample;
  struct FaceSample;
  bool boxesApart(const HierarchyNode& a, const HierarchyNode& b) const;
  double leafRadiosityAt(std::uint32_t node, const Vec3& y) const;
  bool mayFace(std::uint32_t faces, std::uint32_t seen) const;
  bool facesSeeNothingOf(std::uint32_t faces, std::uint32_t seen) const;
  bool cutsThrough(const HierarchyNode& e, const HierarchyNode& b) const;
  void trace(const Vec3& x, const Vec3& xNormal, std::uint8_t xCoverage, const Vec3& y, const Vec3& yNormal,
             std::uint64_t sourceFace, Visibility& seen) const;
  template <bool withRays>
  ClusterSample sampleCluster(const Candidate& c, const Vec3& w, int n, const std::array<std::uint32_t, 4>& scramble) const;
  FaceSample sampleFace(std::uint32_t node, const Vec3& toward, bool source, double& u) const;

  const ElementHierarchy& h_;  // refined (split) by the refiner between estimates
  const RayCaster& caster_;
  std::span<const std::uint64_t> casterFace_;
  double epsilon_;
  const LinkOptions& options_;
  double minArea_;
  double threshold_ = 0;
  std::vector<double> radiosity_;  // per node: area-weighted mean of the leaves' largest channel
  std::vector<double> peakRadiosity_;  // per node: the largest of its leaves' largest channel
  // Per node: kOpen, kMayBeCovered (a leaf partly covered is, or was, under it) or kEnclosed (an
  // element inside a closed two-sided object, every point covered: geometry/enclosures.h).
  enum Coverage : std::uint8_t { kOpen = 0, kMayBeCovered = 1, kEnclosed = 2 };
  std::vector<std::uint8_t> partlyCovered_;
  // Per node: the area of its faces outside closed two-sided objects (its whole area but for the
  // enclosed inner twins). A link into a cluster carries the irradiance of the cluster's open part
  // (what the transport hands out over the open area): its receiving points are drawn from that
  // area alone, and their sum is over it. Over the whole area, a closed two-sided sphere's inner
  // twins took half of every cluster link's light (issue: spheres dark in the clustered solve).
  std::vector<double> unenclosedArea_;
  // Per node: a cone holding the normals of its faces outside closed objects (floats: 16 bytes).
  // A patch of a sphere, seen from behind, holds no face facing an element on the far wall, but
  // its axis areas say it may, and the few sample pairs that find none only say "look closer":
  // refinement opened every such pair down to the single faces (a 64-segment sphere in a room:
  // 2 × 10⁷ candidates, where the cones leave 10⁵).
  std::vector<std::array<float, 4>> normalCone_;
  NormalCone normalCone(std::uint32_t node) const {
    const std::array<float, 4>& c = normalCone_[node];
    return {{c[0], c[1], c[2]}, c[3]};
  }
};

}  // namespace lambert
