#include "lambert/hierarchical/links.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "lambert/core/error.h"
#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"
#include "lambert/core/spherical_sampling.h"
#include "lambert/core/vec3.h"
#include "lambert/formfactor/kernels.h"
#include "lambert/geometry/coverage.h"
#include "lambert/hierarchical/link_estimator.h"

namespace lambert {
namespace {

// Where the oracle asks a cluster link's own samples (LinkEstimator::judgedTransfer): closer
// than kCloseReach times the spheres' reach, and where a node shows less than kFairShare of its
// area along the centres' line.
constexpr double kCloseReach = 2.0;
constexpr double kFairShare = 0.1;
// Sample pairs of the oracle's estimate: 4 judge the closed room as well as 8 (surfaces within
// 1.7–1.8% either way) at half the cost; the MGF floor's refinement then takes what it took
// when judged by the centres alone.
constexpr int kOracleSamples = 4;

// Whether any corner of polygon a lies in front of the plane of element b.
bool anyCornerInFront(const HierarchyNode& a, const HierarchyNode& b, double epsilon) {
  for (std::size_t k = 0; k < a.numCorners; ++k)
    if (dot(a.corners[k] - b.centre, b.normal) > epsilon) return true;
  return false;
}

// The unoccluded form factor from element r to polygon s: the exact point-to-polygon factor
// averaged over r by a degree-2 rule (three points for a triangle, 2×2 Gauss points for a quad).
// The centroid alone would underestimate it next to a shared edge, where the factor climbs
// steeply, and leave light missing in every corner. Also gives the spread of the point values
// (quadrature points and corners): how much the factor changes across r, which a parent's link
// hands to all its children alike.
struct ElementFactor {
  double mean = 0, spread = 0;
};
ElementFactor meanFormFactor(const HierarchyNode& r, const HierarchyNode& s) {
  const auto& p = r.corners;
  double values[4];
  std::size_t count = 0;
  if (r.numCorners == 3) {
    for (int k = 0; k < 3; ++k) {
      const Vec3 x = p[k] * (2.0 / 3.0) + p[(k + 1) % 3] * (1.0 / 6.0) + p[(k + 2) % 3] * (1.0 / 6.0);
      values[count++] = pointToPolygonFormFactorFast(x, r.normal, s.polygon(), s.normal);
    }
  } else {
    constexpr double a = 0.5 - 0.28867513459481287, b = 0.5 + 0.28867513459481287;  // 1/2 ∓ 1/(2√3)
    for (double u : {a, b})
      for (double v : {a, b}) values[count++] = pointToPolygonFormFactorFast(lerp(lerp(p[0], p[1], u), lerp(p[3], p[2], u), v), r.normal, s.polygon(), s.normal);
  }
  ElementFactor f;
  double lo = values[0], hi = values[0];
  for (std::size_t k = 0; k < count; ++k) {
    f.mean += values[k] / static_cast<double>(count);
    lo = std::fmin(lo, values[k]);
    hi = std::fmax(hi, values[k]);
  }
  // The corners too (drawn 1% in, off the edges), for the spread only: the quadrature points sit
  // well inside, and a factor that falls off sharply at the element's rim (a wall's top row
  // below a ceiling light) would not show in them.
  for (std::size_t k = 0; k < r.numCorners; ++k) {
    const double value = pointToPolygonFormFactorFast(lerp(p[k], r.centre, 0.01), r.normal, s.polygon(), s.normal);
    lo = std::fmin(lo, value);
    hi = std::fmax(hi, value);
  }
  f.spread = hi - lo;
  return f;
}

// P_s(−ω) P_r(ω) / (π d² A_r): the transfer between the nodes' centres, d apart along ω, from
// the areas they show each other (Sillion 1995's non-isotropic clusters).
double centreTransfer(const HierarchyNode& r, const HierarchyNode& s) {
  const Vec3 d = s.centre - r.centre;
  const double distanceSquared = lengthSquared(d);
  const Vec3 w = d / std::sqrt(distanceSquared);
  return std::fmin(1.0, s.projectedArea(-w) * r.projectedArea(w) / (kPi * distanceSquared * r.area));
}

// Shares of a total in 255ths, rounded down (each is at most 1/255 short of its value).
std::array<std::uint8_t, 6> quantizedShares(const std::array<double, 6>& parts, double total) {
  std::array<std::uint8_t, 6> q{};
  for (int b = 0; b < 6; ++b) q[b] = static_cast<std::uint8_t>(std::clamp(std::floor(255 * parts[b] / total), 0.0, 255.0));
  return q;
}

// A cone as LinkEstimator keeps it, in floats: its half angle padded for the axis's rounding.
std::array<float, 4> storedCone(const NormalCone& c) {
  if (c.empty() || c.whole()) return {0, 0, 1, static_cast<float>(c.halfAngle)};
  return {static_cast<float>(c.axis.x), static_cast<float>(c.axis.y), static_cast<float>(c.axis.z), static_cast<float>(c.halfAngle + 1e-6)};
}

// A face as casterFace holds it: surface << 32 | face.
std::uint64_t faceKey(const HierarchyNode& e) { return static_cast<std::uint64_t>(e.surface) << 32 | e.face; }

}  // namespace

std::size_t Links::bytes() const {
  return start.capacity() * sizeof(std::uint32_t) + source.capacity() * sizeof(std::uint32_t) +
         (formFactor.capacity() + uncertainty.capacity()) * sizeof(float) + receiverSide.capacity() * sizeof(std::uint8_t) +
         facing.capacity() * sizeof(facing[0]);
}

// Cluster pairs this many times their spheres' reach apart are judged by the direction between
// their centres alone (estimate()).
constexpr double kFarApart = 2;

double minimumElementArea(const ElementHierarchy& hierarchy, const LinkOptions& options) {
  return options.minElementArea > 0 ? options.minElementArea : hierarchy.totalArea() * 1e-5;
}

LinkEstimator::LinkEstimator(const ElementHierarchy& hierarchy, const RayCaster& caster, double rayEpsilon,
                             std::span<const std::uint64_t> casterFace, const LinkOptions& options,
                             std::span<const double> leafRadiosity, std::span<const double> leafOpenFraction)
    : h_(hierarchy), caster_(caster), casterFace_(casterFace), epsilon_(rayEpsilon), options_(options),
      minArea_(minimumElementArea(hierarchy, options)) {
  const auto& nodes = h_.nodes();
  LAMBERT_CHECK(leafRadiosity.size() == h_.leafNodes().size());
  LAMBERT_CHECK(leafOpenFraction.size() == h_.leafNodes().size());
  partlyCovered_.assign(nodes.size(), 0);
  for (std::size_t l = 0; l < leafOpenFraction.size(); ++l) partlyCovered_[h_.leafNodes()[l]] = leafOpenFraction[l] < 1;
  for (std::size_t i = nodes.size(); i-- > 0;)  // children have larger indices than their parents
    if (nodes[i].parent != kNoNode && partlyCovered_[i]) partlyCovered_[nodes[i].parent] = kMayBeCovered;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].enclosed) partlyCovered_[i] = kEnclosed;
  unenclosedArea_ = h_.unenclosedAreas();
  normalCone_.resize(nodes.size());
  {
    std::vector<NormalCone> cones(nodes.size());
    for (std::size_t i = nodes.size(); i-- > 0;) {  // children first
      if (!nodes[i].isCluster()) {
        cones[i] = nodes[i].enclosed ? NormalCone{} : NormalCone::of(nodes[i].normal);
      } else {
        for (std::uint32_t k : h_.children(static_cast<std::uint32_t>(i))) cones[i] = mergeCones(cones[i], cones[k]);
      }
      normalCone_[i] = storedCone(cones[i]);
    }
  }
  radiosity_.assign(nodes.size(), 0.0);
  peakRadiosity_.assign(nodes.size(), 0.0);
  double power = 0;
  for (std::size_t l = 0; l < leafRadiosity.size(); ++l) {
    std::uint32_t n = h_.leafNodes()[l];
    radiosity_[n] = leafRadiosity[l] * nodes[n].area;  // summed power first, divided below
    peakRadiosity_[n] = leafRadiosity[l];
    power += leafRadiosity[l] * nodes[n].area;
  }
  // Pull: children have larger indices than their parents.
  for (std::size_t i = nodes.size(); i-- > 0;) {
    const std::uint32_t parent = nodes[i].parent;
    if (parent == kNoNode) continue;
    radiosity_[parent] += radiosity_[i];
    peakRadiosity_[parent] = std::fmax(peakRadiosity_[parent], peakRadiosity_[i]);
  }
  // A cluster's mean over its faces outside closed objects, as the transport pulls it.
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const double area = nodes[i].isCluster() ? unenclosedArea_[i] : nodes[i].area;
    radiosity_[i] = area > 0 ? radiosity_[i] / area : 0.0;
  }
  threshold_ = options_.linkError * power;
}

void LinkEstimator::addChildren(std::uint32_t node) {
  for (std::uint32_t k : h_.children(node)) {
    LAMBERT_CHECK(k == radiosity_.size());
    radiosity_.push_back(radiosity_[node]);
    peakRadiosity_.push_back(radiosity_[node]);  // a leaf's radiosity is one value
    partlyCovered_.push_back(partlyCovered_[node]);
    unenclosedArea_.push_back(h_.node(k).enclosed ? 0.0 : h_.node(k).area);
    normalCone_.push_back(normalCone_[node]);  // the same plane
  }
}

// The rays between receiving points and source points that face each other. A receiving point
// that is covered (the floor under a block: the first surface along its normal is seen from
// behind) receives nothing, and the links' K is the irradiance of the receiver's open part
// (hierarchical/transport.h): it is left out, not counted as blocked. Only blocked rays from
// elements partly covered are asked, so open receivers cost nothing more.
struct LinkEstimator::Visibility {
  int open = 0, facing = 0, covered = 0;
  int coverageRays = 0;  // rays that asked whether a receiving point is covered
  std::uint8_t rays() const { return static_cast<std::uint8_t>(std::min(255, facing + covered + coverageRays)); }
};

// What a cluster link's sample pairs give (estimate()): Σ contribution over the open pairs and
// over all facing pairs, the rays' outcomes, and the pairs that do not face each other. Without
// rays (the oracle's transfer) every facing pair counts as open and no ray is cast.
struct LinkEstimator::ClusterSample {
  double sum = 0, unoccluded = 0;
  Visibility seen;
  int nonFacing = 0;
  std::array<double, 6> facing{};  // sum split by the receiving faces' normals (Links::facing)
};

// A face sampleFace chose, and its weight.
struct LinkEstimator::FaceSample {
  std::uint32_t element;
  double weight;
};

// Fills in the candidate's verdict, K and visibility; returns the rays it cast.
std::uint8_t LinkEstimator::estimate(Candidate& c) const {
  const HierarchyNode& r = h_.node(c.receiver);
  const HierarchyNode& s = h_.node(c.source);
  c.estimated = true;
  // A node whose every face lies inside closed objects (geometry/enclosures.h) receives nothing,
  // and sends nothing either: its faces' radiosity stays zero (an emitter inside makes its
  // enclosure lit, not enclosed). Judged only by boxes, the inner twins of a closed sphere were
  // inadmissible against the outer ones they overlap, and opened down to every pair of faces.
  if (!(unenclosedArea_[c.receiver] > 0) || !(unenclosedArea_[c.source] > 0)) {
    c.verdict = Verdict::Empty;
    return 0;
  }
  // With a cluster at either end, pairs that cannot face each other at all (a floor's clusters
  // side by side, a wall's cluster with itself) are empty before anything is sampled: refined,
  // every pair of elements under them would be found empty (anyCornerInFront), one candidate
  // at a time, and the Monte Carlo estimates on the way would find no pair of points facing.
  if ((r.isCluster() || s.isCluster()) && (!mayFace(c.receiver, c.source) || !mayFace(c.source, c.receiver))) {
    c.verdict = Verdict::Empty;
    return 0;
  }
  if (c.receiver == c.source) {
    c.verdict = r.isCluster() ? Verdict::Inadmissible : Verdict::Empty;  // a plane does not see itself
    return 0;
  }
  Pcg32 rng(options_.seed, (static_cast<std::uint64_t>(c.receiver) << 32) ^ c.source);
  const std::uint32_t su = rng.nextUint(), sv = rng.nextUint(), tu = rng.nextUint(), tv = rng.nextUint();
  const int n = std::max(1, options_.visibilityRays);
  if (!r.isCluster() && !s.isCluster()) {
    if (!anyCornerInFront(r, s, epsilon_) || !anyCornerInFront(s, r, epsilon_)) {
      c.verdict = Verdict::Empty;
      return 0;
    }
    const ElementFactor factor = meanFormFactor(r, s);
    const double k = std::fmin(1.0, factor.mean);
    if (!(k > 0)) {
      // The points of r see nothing of s although parts of the two face each other: r's
      // children may, so r is split, never s: no part of s can show r's points anything (the
      // point factor to s is the sum of those to its parts, none negative). Where r is as
      // small as elements get, the link is empty. Split by area instead, a luminaire's sliver
      // end-cap triangles, each with a corner just above a reflector's plane, cut the whole
      // 1.2 m reflector down to the smallest elements for nothing.
      c.verdict = splittable(c.receiver) ? Verdict::Inadmissible : Verdict::Empty;
      c.receiverSide = true;
      return 0;
    }
    // The oracle's factor is the unoccluded K or its spread, whatever the rays give: above the
    // threshold as both, the link is refined, and the node split does not depend on the rays
    // (receiverSide) unless both could split and the source is the larger.
    const float unoccludedBound = static_cast<float>(k), spreadBound = static_cast<float>(factor.spread);
    const bool canR = splittable(c.receiver), canS = splittable(c.source);
    if ((canR || canS) && (!canR || !canS || r.area >= s.area) && tooCoarse(c, std::fmin(unoccludedBound, spreadBound))) {
      c.verdict = Verdict::Coarse;
      return 0;
    }
    // Visibility: the share of the light from s that reaches r unoccluded, among the pairs of
    // points that face each other. Points x uniform on r; points on s uniform in the solid angle
    // it subtends at x (core/spherical_sampling.h), each pair weighed by Ω(x) cos θ_x (and the
    // source leaf's radiosity where they differ): the ratio of Monte Carlo estimates of the
    // occluded and the unoccluded ∫∫ cos cos / (π r²). Points uniform in area weighed a large
    // source's far, hidden part as much as its near, visible one (a furnished closed furnace's
    // furniture 3.8% dark, unclustered). Where the elements cross each other's planes K already
    // leaves out the part behind, and a ray to it would count it out twice. Cluster links keep
    // points uniform in area: weighed alike, RenderPark's classroom's large regions came out 2.4
    // points darker against the path tracer (its clustered tables already lose light: docs/
    // hierarchical.md, "What is left").
    Visibility seen;
    const bool weighed = peakRadiosity_[c.source] > radiosity_[c.source] * (1 + 1e-12);
    double shown = 0, reaching = 0;
    for (int i = 0; i < n; ++i) {
      auto [u1, v1] = scrambledZeroTwo(static_cast<std::uint32_t>(i), su, sv);
      auto [u2, v2] = scrambledZeroTwo(static_cast<std::uint32_t>(i), tu, tv);
      const Vec3 x = sampleConvexPolygon(r.polygon(), u1, v1);
      const std::optional<SolidAngleSample> y = sampleBySolidAngle(x, s.polygon(), u2, v2);
      if (!y) continue;
      const double cosX = dot(r.normal, y->direction);
      if (!(cosX > 0) || !(-dot(s.normal, y->direction) > 0)) continue;
      const int facingBefore = seen.facing, openBefore = seen.open;
      trace(x, r.normal, partlyCovered_[c.receiver], y->point, s.normal, faceKey(s), seen);
      if (seen.facing > facingBefore) {
        const double weight = y->solidAngle * cosX * (weighed ? leafRadiosityAt(c.source, y->point) : 1.0);
        shown += weight;
        reaching += seen.open > openBefore ? weight : 0.0;
      }
    }
    const int open = seen.open, facing = seen.facing;
    if (facing == 0 && seen.covered == 0) {
      c.verdict = Verdict::Inadmissible;  // only slivers face each other: look closer
      return 0;
    }
    // Every point that faces s is covered: as if every ray were blocked (the rest of r may be open).
    const double visible = shown > 0 ? reaching / shown : 0.0;
    c.formFactor = static_cast<float>(k * visible);
    // Unoccluded, the error is the factor's spread over r; a shadow edge may cross r where
    // only some rays get through, and then the whole unoccluded factor is in doubt.
    c.uncertainty = static_cast<float>(open < facing || facing == 0 ? k : factor.spread);
    c.receiverSide = facing > 0 && open == facing;
    c.verdict = open > 0 ? Verdict::Estimated : Verdict::Occluded;
    return seen.rays();
  }

  // A cluster at either end: only between nodes whose boxes are apart and neither of which cuts
  // through the other's element plane. Boxes, not spheres: a column's cluster is as tall as
  // the column, its sphere reaches through the floor it stands on and holds the floor around
  // its foot, and with spheres no floor element near it (with the sphere as the plane test, none
  // anywhere) could link to it. Refinement then opened it down to every facet, each linked to
  // the floor's elements one by one (the MGF floor's finely divided cylinders made 47 M links).
  // The estimate below is exact on average at any distance, so the boxes need only be apart.
  const Vec3 d = s.centre - r.centre;
  if (!boxesApart(r, s) || cutsThrough(r, s) || cutsThrough(s, r)) {
    c.verdict = Verdict::Inadmissible;
    // An element's plane that cuts through a cluster's box cuts through it however finely the
    // element is split: only opening the cluster makes the pair admissible. Split by area (the
    // larger first), the element went first wherever the cluster's faces summed to less area:
    // a luminaire's 1.2 m reflectors and casing, each cutting through the box of the lamp's or
    // the vanes' cluster, were split down to the smallest elements (30,000 leaves of 294 faces).
    c.openSource = s.isCluster() && cutsThrough(r, s);
    c.openReceiver = r.isCluster() && cutsThrough(s, r);
    return 0;
  }
  const double distance = length(d);
  const Vec3 w = d / distance;
  // Far apart, faces that show nothing toward the other node's centre show nothing toward the
  // node. Only far: the directions between two nodes lie within about (r_r + r_s)/d of the
  // centres' line, and where that is wide the Monte Carlo estimate below decides. With the
  // spheres merely apart, a cluster of floor pieces and the luminaires over them, seen level from
  // another such cluster, showed nothing toward its centre, and the floor lost the far
  // luminaires' light (a 4 × 4 grid's floor vertices 12% off, 2.3% without the link dropped);
  // close by, dropping such links lost 2.5% of what the clustering test's receivers gather.
  if (distance > kFarApart * (r.radius + s.radius) && (!(s.projectedArea(-w) > 0) || !(r.projectedArea(w) > 0))) {
    c.verdict = Verdict::Empty;
    return 0;
  }
  // A cluster link is judged by a transfer that does not depend on its own samples (judge()).
  c.judgedTransfer = static_cast<float>(judgedTransfer(c));
  if ((splittable(c.receiver) || splittable(c.source)) && tooCoarse(c, c.judgedTransfer)) {
    c.verdict = Verdict::Coarse;
    return 0;
  }
  // K = 1/A_r ∫_r Σ_f F(x→f) V(x, f) B_f / B̄_s, by Monte Carlo over the link's own sample pairs:
  // a point x on a receiving face g (chosen with probability P(g), uniform on it) and a source
  // face f (chosen with probability P(f)), each contributing A_g F(x→f) V B_f / (A_r P(g) P(f) B̄_s),
  // with F(x→f) the exact point-to-polygon factor (bounded close by, where the point-to-point
  // kernel between the nodes' centres is not) and V one ray to a point on f. Faces are chosen
  // by the area they show toward the other node, and a source's also by their radiosity (a lamp
  // among dark ceiling tiles, which it covers, must be seen where it shines). Far apart, this is
  // the point-to-point transfer P_s(−ω) P_r(ω) / (π d² A_r) of Sillion's non-isotropic
  // clusters; close by, where that kernel is 15–20% high, this stays exact on average. The
  // radiosity weights are those of the refinement's estimate; dynamic lights reuse them.
  const ClusterSample sample = sampleCluster<true>(c, w, n, {su, sv, tu, tv});
  const double sum = sample.sum, unoccluded = sample.unoccluded;
  const Visibility& seen = sample.seen;
  const int nonFacing = sample.nonFacing;
  if (seen.facing == 0 && seen.covered == 0) {
    // No sampled pair faced each other: look closer, unless the faces of one of the two, few
    // enough to ask one by one, show that none of them faces the other (two patches of one
    // sphere, side by side: their spheres overlap, which leaves the cones no say).
    c.verdict = facesSeeNothingOf(c.receiver, c.source) || facesSeeNothingOf(c.source, c.receiver) ? Verdict::Empty : Verdict::Inadmissible;
    return 0;
  }
  // Covered receiving points are left out: K is the irradiance of the receiver's open part.
  const double counted = seen.facing + nonFacing;
  const double k = counted > 0 ? std::fmin(1.0, unoccluded / counted) : 0.0;
  c.uncertainty = static_cast<float>(k);  // unoccluded K: the final gather reads K / this as the visibility
  c.formFactor = counted > 0 ? static_cast<float>(std::fmin(1.0, sum / counted)) : 0.0f;
  if (r.isCluster() && sum > 0) c.facing = quantizedShares(sample.facing, sum);
  c.verdict = seen.open > 0 ? Verdict::Estimated : Verdict::Occluded;
  return seen.rays();
}

// The radiosity of the leaf under `node` (an element) that holds the point y of its plane: its
// children split it into four, and y lies in one of them (the one it is least outside of).
double LinkEstimator::leafRadiosityAt(std::uint32_t node, const Vec3& y) const {
  while (!h_.node(node).isLeaf()) {
    std::uint32_t best = node;
    double bestMargin = -INFINITY;
    for (std::uint32_t child : h_.children(node)) {
      const HierarchyNode& e = h_.node(child);
      double margin = INFINITY;
      for (std::size_t k = 0; k < e.numCorners; ++k) {
        const Vec3& a = e.corners[k];
        const Vec3& b = e.corners[(k + 1) % e.numCorners];
        margin = std::fmin(margin, dot(cross(b - a, y - a), e.normal) / std::fmax(length(b - a), 1e-300));
      }
      if (margin > bestMargin) bestMargin = margin, best = child;
    }
    node = best;
  }
  return radiosity_[node];
}

// Whether the two nodes' boxes are apart along some axis.
bool LinkEstimator::boxesApart(const HierarchyNode& a, const HierarchyNode& b) const {
  Vec3 aLo, aHi, bLo, bHi;
  a.box(aLo, aHi);
  b.box(bLo, bHi);
  const Vec3 gap = componentMax(aLo - bHi, bLo - aHi);
  return std::fmax(gap.x, std::fmax(gap.y, gap.z)) > epsilon_;
}

// Whether some face under node `faces` may have a point of node `seen` more than a ray epsilon
// in front of its plane. An element: the most the points of seen's boxes (an element's corners)
// rise over its plane. A cluster: first its normal cone against the directions from its sphere
// to seen's; then the height n·(x − y) of a point x in seen's box over a point y of a face,
// a sum over the axes of n_axis (x − y)_axis, where a term is positive only if the normal's
// component and the offset's can share a sign (the cluster's axis areas say which signs its
// normals take) and the two boxes bound the offsets. The ray epsilon is anyCornerInFront's: no
// corner of an element under seen is in front of an element under `faces` where this says no.
bool LinkEstimator::mayFace(std::uint32_t faces, std::uint32_t seen) const {
  const HierarchyNode& a = h_.node(faces);
  const HierarchyNode& b = h_.node(seen);
  if (!a.isCluster()) return b.extentAlong(a.normal).hi - dot(a.normal, a.centre) > epsilon_;
  if (!coneMayFace(normalCone(faces), a.centre, a.radius, b.centre, b.radius)) return false;
  Vec3 aLo, aHi, bLo, bHi;
  a.box(aLo, aHi);
  b.box(bLo, bHi);
  const Vec3 most = bHi - aLo, least = bLo - aHi;  // the range of (x − y) along each axis
  const double mostOf[3] = {most.x, most.y, most.z}, leastOf[3] = {least.x, least.y, least.z};
  double height = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (a.bounds.axisArea[2 * axis] > 0) height += std::fmax(0.0, mostOf[axis]);
    if (a.bounds.axisArea[2 * axis + 1] > 0) height += std::fmax(0.0, -leastOf[axis]);
  }
  return height > epsilon_;
}

// Whether no face under `faces` (outside closed objects) has a point of `seen` more than a ray
// epsilon in front of its plane, asked face by face where there are at most kFacesAsked of them;
// false (not known) where there are more.
bool LinkEstimator::facesSeeNothingOf(std::uint32_t faces, std::uint32_t seen) const {
  constexpr std::size_t kFacesAsked = 16;
  const HierarchyNode& b = h_.node(seen);
  std::uint32_t stack[kFacesAsked + 1];
  std::size_t depth = 0, asked = 0;
  stack[depth++] = faces;
  while (depth > 0) {
    const std::uint32_t n = stack[--depth];
    const HierarchyNode& a = h_.node(n);
    if (!(unenclosedArea_[n] > 0)) continue;
    if (!a.isCluster()) {
      if (++asked > kFacesAsked || b.extentAlong(a.normal).hi - dot(a.normal, a.centre) > epsilon_) return false;
      continue;
    }
    for (std::uint32_t k : h_.children(n)) {
      if (depth == kFacesAsked + 1) return false;
      stack[depth++] = k;
    }
  }
  return true;
}

// Whether element e's plane cuts through node b (its boxes). Touching is not cutting: a column
// standing on the floor is all in front of it.
bool LinkEstimator::cutsThrough(const HierarchyNode& e, const HierarchyNode& b) const {
  if (e.isCluster()) return false;
  const Extent along = b.extentAlong(e.normal);
  const double plane = dot(e.normal, e.centre);
  return along.lo < plane - epsilon_ && along.hi > plane + epsilon_;
}

// The ray runs to a ray epsilon behind the source point: anything it meets first other than
// the source's own face blocks it, a face lying on the source included. A ray run only to a
// point in front of the source never meets a face lying on it, and every face of a stack is
// then seen whole (a binder ring in office1/graz.mgf gathered K = 0.99 from each of three).
void LinkEstimator::trace(const Vec3& x, const Vec3& xNormal, std::uint8_t xCoverage, const Vec3& y, const Vec3& yNormal,
                          std::uint64_t sourceFace, Visibility& seen) const {
  if (xCoverage == kEnclosed) {  // no light reaches inside a closed object: as covered, left out of K
    ++seen.covered;
    return;
  }
  const bool xMayBeCovered = xCoverage == kMayBeCovered;
  const Vec3 from = x + xNormal * epsilon_, to = y - yNormal * epsilon_;
  const std::optional<RayHit> hit = caster_.intersect(Ray{from, to - from, 0, 1});
  const bool blocked = hit && casterFace_[hit->patch] != sourceFace;
  if (blocked && xMayBeCovered) {
    ++seen.coverageRays;
    if (isCovered(caster_, x, xNormal, epsilon_)) {
      ++seen.covered;
      return;
    }
  }
  ++seen.facing;
  seen.open += !blocked;
}

template <bool withRays>
LinkEstimator::ClusterSample LinkEstimator::sampleCluster(const Candidate& c, const Vec3& w, int n,
                                                         const std::array<std::uint32_t, 4>& scramble) const {
  double sum = 0, unoccluded = 0;
  Visibility seen;
  int nonFacing = 0;
  std::array<double, 6> facing{};
  for (int i = 0; i < n; ++i) {
    auto [u1, v1] = scrambledZeroTwo(static_cast<std::uint32_t>(i), scramble[0], scramble[1]);
    auto [u2, v2] = scrambledZeroTwo(static_cast<std::uint32_t>(i), scramble[2], scramble[3]);
    const FaceSample onReceiver = sampleFace(c.receiver, w, false, u1);
    const FaceSample onSource = sampleFace(c.source, -w, true, u2);
    const HierarchyNode& g = h_.node(onReceiver.element);
    const HierarchyNode& f = h_.node(onSource.element);
    const Vec3 x = sampleConvexPolygon(g.polygon(), u1, v1);
    const double factor = pointToPolygonFormFactorFast(x, g.normal, f.polygon(), f.normal);
    if (!(factor > 0)) {
      ++nonFacing;
      continue;
    }
    const double contribution = factor * onReceiver.weight * onSource.weight * g.area / unenclosedArea_[c.receiver];
    bool open = true;
    Vec3 toSource;  // to the source point the ray goes to (the facing shares, read only with rays)
    if constexpr (withRays) {
      const Vec3 y = sampleConvexPolygon(f.polygon(), u2, v2);
      toSource = y - x;
      // Where f straddles x's horizon and this point on it lies below, the factor counts only
      // the part above, which no ray to y would test: counted as unoccluded.
      if (pointToPointKernel(x, g.normal, y, f.normal) > 0) {
        const int openBefore = seen.open, coveredBefore = seen.covered;
        trace(x, g.normal, partlyCovered_[onReceiver.element], y, f.normal, faceKey(f), seen);
        if (seen.covered > coveredBefore) continue;
        open = seen.open > openBefore;
      } else {
        ++seen.facing;
        ++seen.open;
      }
    } else {
      ++seen.facing;  // without rays every facing pair counts as open
      ++seen.open;
    }
    sum += open ? contribution : 0.0;
    unoccluded += contribution;
    if (withRays && open) {
      // Into the bins of the normal's axis sides, each by n_a·w_a (w toward the source): the
      // terms of n·w where the face meets the light. A face's light from a source off its axes
      // goes where faces of its orientation take it again, and the bins hold where light comes
      // from: by |n_a| alone, a sphere's face turned toward a wall put half its light in the +y
      // bin, which faces turned away took (its top ring's mean 46% over the exact factor).
      // Faces along an axis are as before: one term.
      const double components[3] = {g.normal.x, g.normal.y, g.normal.z};
      const double toward[3] = {toSource.x, toSource.y, toSource.z};
      double meets[3], total = 0;
      for (int a = 0; a < 3; ++a) total += meets[a] = std::fmax(0.0, components[a] * toward[a]);
      if (!(total > 0))  // the sampled point lies below the horizon (the factor counts the part above)
        for (int a = 0; a < 3; ++a) total += meets[a] = std::fabs(components[a]);
      for (int a = 0; a < 3; ++a) facing[axisSide(a, components[a])] += contribution * meets[a] / total;
    }
  }
  return {sum, unoccluded, seen, nonFacing, facing};
}

// The transfer a cluster link is judged by: the larger of the point-to-point transfer between
// the centres and the unoccluded K estimated from sample pairs of its own, independent of the
// link's (no rays: every pair that faces counts). Judged by the link's own estimate, the links
// it happens to underestimate would be kept and those it overestimates refined (the clustered
// solutions came out 3–14% dark); judged by the centres alone, close pairs whose centres' line
// runs along one node's faces (a wall's strip beside a floor's, K 0.05) showed a transfer of 0
// and were never refined, and their 8-sample estimates, skewed low close by (where the kernel
// peaks at a shared edge that few samples reach), left a closed room 2–10% dark.
double LinkEstimator::judgedTransfer(const Candidate& c) const {
  const HierarchyNode& r = h_.node(c.receiver);
  const HierarchyNode& s = h_.node(c.source);
  const double centres = centreTransfer(r, s);
  const Vec3 d = s.centre - r.centre;
  const double distance = length(d);
  // Far apart (twice the spheres' reach), the centres' transfer is the link's K, and where it
  // already calls for refinement the samples could only agree.
  if (distance > kCloseReach * (r.radius + s.radius) || tooCoarse(c, centres)) return centres;
  const Vec3 w = d / distance;
  // Nor where both nodes show a fair share of their area along the centres' line: the centres'
  // transfer misjudges a link where one node shows (nearly) nothing that way. Asking the samples
  // only there keeps the exact box's surfaces within 1.7–2.0% (1.6–1.8% asking everywhere) at
  // no measurable cost, where asking everywhere made the 10⁵-face building's refinement 1.5×.
  if (r.projectedArea(w) > kFairShare * r.area && s.projectedArea(-w) > kFairShare * s.area) return centres;
  Pcg32 rng(options_.seed ^ 0x6a09e667f3bcc909ull, (static_cast<std::uint64_t>(c.receiver) << 32) ^ c.source);
  const std::array<std::uint32_t, 4> scramble{rng.nextUint(), rng.nextUint(), rng.nextUint(), rng.nextUint()};
  const ClusterSample sample = sampleCluster<false>(c, w, kOracleSamples, scramble);
  const double unoccluded = std::fmin(1.0, sample.unoccluded / kOracleSamples);
  return std::fmax(centres, unoccluded);
}

// A face of the node: the element itself, or a face inside the cluster, the children chosen
// in proportion to the area they show toward `toward` (a twentieth of their whole area mixed
// in, so that close by, where the direction between the nodes' centres is not the direction
// between their faces, every face can be chosen) times, for a source, their radiosity.
// weight is 1/P(face), times B_face / B̄_node for a source chosen by radiosity. `u` chooses,
// and is rescaled within each choice for the next one and for the point on the face (as
// sampleConvexPolygon reuses it), so that stratified (u, v) stay stratified over the faces:
// with independent choices a column's facets, each gathering from a few close clusters, came
// out striped.
LinkEstimator::FaceSample LinkEstimator::sampleFace(std::uint32_t node, const Vec3& toward, bool source, double& u) const {
  const bool byRadiosity = source && radiosity_[node] > 0;
  const double meanRadiosity = radiosity_[node];
  double probability = 1;
  while (h_.node(node).isCluster()) {
    std::span<const std::uint32_t> kids = h_.children(node);
    double shown[8], total = 0;
    const std::size_t count = std::min<std::size_t>(kids.size(), 8);
    for (std::size_t k = 0; k < count; ++k) {
      const HierarchyNode& kid = h_.node(kids[k]);
      shown[k] = kid.projectedArea(toward) + 0.05 * kid.area;
      if (byRadiosity) shown[k] *= radiosity_[kids[k]];
      if (!source) shown[k] *= kid.area > 0 ? unenclosedArea_[kids[k]] / kid.area : 0.0;  // no light reaches an enclosed face
      total += shown[k];
    }
    std::size_t chosen = 0;
    double share = 1.0 / static_cast<double>(count);
    if (total > 0) {
      double pick = u * total;
      for (std::size_t k = 0; k < count; ++k) {
        chosen = k;
        if (pick < shown[k] || k + 1 == count) break;
        pick -= shown[k];
      }
      share = shown[chosen] / total;
      u = shown[chosen] > 0 ? std::clamp(pick / shown[chosen], 0.0, std::nextafter(1.0, 0.0)) : 0.5;
    } else {
      chosen = std::min(count - 1, static_cast<std::size_t>(u * static_cast<double>(count)));
      u = std::clamp(u * static_cast<double>(count) - static_cast<double>(chosen), 0.0, std::nextafter(1.0, 0.0));
    }
    probability *= share;
    node = kids[chosen];
  }
  double weight = probability > 0 ? 1.0 / probability : 0.0;
  if (byRadiosity) weight *= radiosity_[node] / meanRadiosity;
  return {node, weight};
}

}  // namespace lambert
