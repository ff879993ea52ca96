#include "lambert/design/illuminance.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <string>

#include "lambert/core/parallel.h"
#include "lambert/core/progress.h"
#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"
#include "lambert/core/timer.h"
#include "lambert/method/solution.h"
#include "lambert/formfactor/kernels.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/light/emission.h"
#include "lambert/light/lights.h"
#include "lambert/light/many_lights.h"
#include "lambert/mesh/vertex_radiosity.h"

namespace lambert {
namespace {

// A source surface (an emitting surface, or a bright reflecting region) is integrated explicitly
// at a point where the bound on its light there is at least this share of the largest source's
// bound of its kind (see IlluminanceMeter::measure).
constexpr double kExplicitShare = 0.02;
// Below this share of the largest bound, a source is integrated explicitly only where one probe
// ray finds it visible.
constexpr double kProbeShare = 0.25;
// A patch of the vertex mesh is a bright reflector, integrated like an emitter, where its
// reflected radiosity's luminance is at least this many times the area-weighted mean over the
// scene's patches: the ceiling over an uplight, a sun patch. 256 hemisphere rays sample such a
// small, bright region poorly: under a pendant uplight 10 cm below the ceiling (RenderPark's
// examp1.ies, two of them in a 6 × 4 m room), mirror-image work-plane points differed by up to
// 25% in their indirect light (16,384 rays: 2%).
constexpr double kBrightFactor = 8;
// At most this many bright patches (the brightest), so that a scene of many lit rooms keeps a
// bounded cost per point.
constexpr std::size_t kMostBrightPatches = 8192;

// A triangle of a source: its corners, front normal, radiosity B (W/m²) and B's luminance.
struct SourceTriangle {
  std::array<Vec3, 3> corners;
  Vec3 normal;
  Rgb radiosity;
  double luminance = 0;
};

// A source surface: its triangles (a range of Sources::triangles), a bounding sphere, its area and
// the largest luminance of its triangles, for the bound on what it can give a point.
struct SourceSurface {
  std::uint32_t first = 0, count = 0;
  double luminance = 0;
  Vec3 centre;
  double radius = 0, area = 0;
  Vec3 normal;  // the front of a planar surface (every triangle facing the same way); zero otherwise
};

// Surfaces whose light a point integrates explicitly where it may matter, and the hemisphere rays
// count elsewhere.
struct Sources {
  std::vector<SourceTriangle> triangles;
  std::vector<SourceSurface> surfaces;
  std::vector<int> ofPatch;  // per patch of the vertex mesh: the surface it belongs to, or −1

  // Closes the surface whose triangles run from `first` to the end; false where it has none.
  bool close(std::uint32_t first) {
    SourceSurface e;
    e.first = first;
    e.count = static_cast<std::uint32_t>(triangles.size()) - first;
    if (e.count == 0) return false;
    Vec3 lo{INFINITY, INFINITY, INFINITY}, hi = -lo;
    e.normal = triangles[first].normal;
    for (std::uint32_t t = first; t < first + e.count; ++t) {
      const SourceTriangle& triangle = triangles[t];
      for (const Vec3& p : triangle.corners) lo = componentMin(lo, p), hi = componentMax(hi, p);
      e.area += length(cross(triangle.corners[1] - triangle.corners[0], triangle.corners[2] - triangle.corners[0])) / 2;
      e.luminance = std::max(e.luminance, triangle.luminance);
      if (dot(triangle.normal, e.normal) < 1 - 1e-9) e.normal = {};
    }
    e.centre = (lo + hi) / 2;
    e.radius = length(hi - lo) / 2;
    surfaces.push_back(e);
    return true;
  }
};

void addTriangle(Sources& sources, const Vec3& a, const Vec3& b, const Vec3& c, const Rgb& radiosity) {
  const Vec3 areaVector = cross(b - a, c - a);
  if (!(length(areaVector) > 0)) return;
  sources.triangles.push_back({{a, b, c}, normalize(areaVector), radiosity, radiosity.luminance()});
}

// The scene's emitting surfaces, their faces fanned into triangles, B = B_e = π L_e.
Sources sceneEmitters(const Scene& scene, const Mesh& mesh) {
  Sources out;
  std::vector<int> ofSceneSurface(scene.surfaces.size(), -1);
  for (std::size_t index = 0; index < scene.surfaces.size(); ++index) {
    const Surface& surface = scene.surfaces[index];
    const Rgb radiosity = meanEmittedRadiance(scene, surface) * kPi;
    if (!(radiosity.maxComponent() > 0)) continue;
    const auto first = static_cast<std::uint32_t>(out.triangles.size());
    for (const std::vector<std::uint32_t>& face : surfaceFaces(surface)) {
      const std::vector<Vec3> polygon = facePositions(surface, face);
      for (std::size_t k = 1; k + 1 < polygon.size(); ++k) addTriangle(out, polygon[0], polygon[k], polygon[k + 1], radiosity);
    }
    if (out.close(first)) ofSceneSurface[index] = static_cast<int>(out.surfaces.size()) - 1;
  }
  out.ofPatch.resize(mesh.numPatches());
  for (std::size_t p = 0; p < mesh.numPatches(); ++p) out.ofPatch[p] = ofSceneSurface[mesh.patches[p].surface];
  return out;
}

// The bright reflectors: patches whose reflected radiosity ρE (at their centroid) has a luminance
// of at least kBrightFactor × the area-weighted mean, at most kMostBrightPatches of them, grouped
// by scene surface.
Sources brightReflectors(const Mesh& mesh, const PatchInterpolation& reflected) {
  std::vector<double> luminance(mesh.numPatches());
  std::vector<Rgb> radiosity(mesh.numPatches());
  double weighted = 0, area = 0;
  for (std::size_t p = 0; p < mesh.numPatches(); ++p) {
    radiosity[p] = reflected.at(static_cast<std::uint32_t>(p), mesh.patches[p].centroid);
    luminance[p] = radiosity[p].luminance();
    weighted += luminance[p] * mesh.patches[p].area;
    area += mesh.patches[p].area;
  }
  Sources out;
  out.ofPatch.assign(mesh.numPatches(), -1);
  if (!(area > 0) || !(weighted > 0)) return out;
  const double threshold = kBrightFactor * weighted / area;
  std::vector<std::uint32_t> bright;
  for (std::size_t p = 0; p < mesh.numPatches(); ++p)
    if (luminance[p] >= threshold) bright.push_back(static_cast<std::uint32_t>(p));
  if (bright.size() > kMostBrightPatches) {
    std::nth_element(bright.begin(), bright.begin() + kMostBrightPatches, bright.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return luminance[a] > luminance[b]; });
    bright.resize(kMostBrightPatches);
  }
  // One source surface per scene surface: its bright patches in patch order.
  std::stable_sort(bright.begin(), bright.end(), [&](std::uint32_t a, std::uint32_t b) {
    return mesh.patches[a].surface < mesh.patches[b].surface;
  });
  for (std::size_t begin = 0; begin < bright.size();) {
    std::size_t end = begin;
    const auto first = static_cast<std::uint32_t>(out.triangles.size());
    const int index = static_cast<int>(out.surfaces.size());
    while (end < bright.size() && mesh.patches[bright[end]].surface == mesh.patches[bright[begin]].surface) {
      const std::uint32_t p = bright[end++];
      const PatchCorners corners = mesh.corners(p);
      for (std::size_t k = 1; k + 1 < corners.count; ++k) addTriangle(out, corners.points[0], corners.points[k], corners.points[k + 1], radiosity[p]);
      out.ofPatch[p] = index;
    }
    if (!out.close(first))
      for (std::size_t k = begin; k < end; ++k) out.ofPatch[bright[k]] = -1;
    begin = end;
  }
  return out;
}

// A convex polygon's area (a fan from its first corner).
double polygonArea(std::span<const Vec3> polygon) {
  Vec3 twice;
  for (std::size_t k = 1; k + 1 < polygon.size(); ++k) twice += cross(polygon[k] - polygon[0], polygon[k + 1] - polygon[0]);
  return length(twice) / 2;
}

// An emitting triangle's part above a point's plane: at most four corners.
struct ClippedTriangle {
  std::array<Vec3, 4> corners;
  std::size_t count = 0;
  double area = 0;
};

}  // namespace

std::vector<Vec3> cosineDirections(int rays, std::uint64_t seed) {
  const int count = static_cast<int>(std::bit_ceil(static_cast<unsigned>(std::max(rays, 1))));
  Pcg32 rng(seed, 0x1ec7);
  const std::uint32_t su = rng.nextUint(), sv = rng.nextUint();
  std::vector<Vec3> out(count);
  for (int k = 0; k < count; ++k) {
    const auto [u, v] = scrambledZeroTwo(static_cast<std::uint32_t>(k), su, sv);
    const double r = std::sqrt(u), phi = 2 * kPi * v;
    out[k] = {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::fmax(0.0, 1 - u))};
  }
  return out;
}

// What a point receives from a set of source surfaces, those that may matter there integrated
// explicitly (their flags in `explicitly` set, so that the hemisphere rays leave them out):
// each one whose bound B·min(1, A cos θ_x⁺ cos θ_y⁺ / (π (d − r)²)) over its bounding sphere
// (centre at d, radius r; each cosine at most (its projection of the centre + r)/(d − r), θ_y's
// only for a planar surface) is at least kExplicitShare of the largest; one under kProbeShare of
// it only where a probe ray to its first triangle's centroid finds it visible. The rest (far or
// small: a building's other rooms) are left to the hemisphere rays, which count exactly those
// where they hit them — two disjoint estimators, no source counted twice or missed.
struct ExplicitIntegration {
  const Sources& sources;
  const RayCaster& shadows;
  double epsilon;
  int samples;
  std::uint32_t su, sv;

  Rgb operator()(const Vec3& x, const Vec3& n, std::vector<char>& explicitly, std::uint64_t& rays) const {
    const Vec3 origin = x + n * epsilon;
    thread_local std::vector<double> bound;
    bound.assign(sources.surfaces.size(), 0);
    explicitly.assign(sources.surfaces.size(), 0);
    double largestBound = 0;
    for (std::size_t k = 0; k < sources.surfaces.size(); ++k) {
      const SourceSurface& surface = sources.surfaces[k];
      const Vec3 toCentre = surface.centre - origin;
      if (dot(toCentre, n) < -surface.radius) continue;  // wholly behind the point's plane
      const double gap = length(toCentre) - surface.radius;
      double factorBound = 1;
      if (gap > 0) {
        const double cosReceiver = std::clamp((dot(toCentre, n) + surface.radius) / gap, 0.0, 1.0);
        const double cosEmitter =
            length(surface.normal) > 0 ? std::clamp((-dot(toCentre, surface.normal) + surface.radius) / gap, 0.0, 1.0) : 1.0;
        factorBound = std::min(1.0, surface.area * cosReceiver * cosEmitter / (kPi * gap * gap));
      }
      bound[k] = surface.luminance * factorBound;
      largestBound = std::max(largestBound, bound[k]);
    }
    Rgb received;
    for (std::size_t k = 0; k < sources.surfaces.size(); ++k) {
      if (!(bound[k] > 0) || bound[k] < kExplicitShare * largestBound) continue;
      const SourceSurface& surface = sources.surfaces[k];
      if (bound[k] < kProbeShare * largestBound) {
        const SourceTriangle& first = sources.triangles[surface.first];
        const Vec3 d = (first.corners[0] + first.corners[1] + first.corners[2]) / 3 - origin;
        const double tMax = 1 - epsilon / std::max(length(d), 1e-300);
        ++rays;
        if (dot(d, n) <= 0 || tMax <= 0 || shadows.occluded(Ray{origin, d, 0, tMax})) continue;
      }
      explicitly[k] = 1;
      received += visibleLight(surface, x, n, origin, rays);
    }
    return received;
  }

  // Σ_t B_t F_t V_t over the surface's triangles: F_t each triangle's exact unoccluded factor
  // (Lambert's contour integral over its part above x's plane, formfactor/kernels.h), V the
  // luminance-weighted visible share from `samples` stratified points (four times as many where
  // they disagree: a penumbra), each in a triangle picked in proportion to its L_t F_t (the
  // sequence's first coordinate picks it and is reused, rescaled, within it), weighted by the
  // kernel over its density: a consistent ratio estimate, exact where the surface is wholly
  // visible or wholly hidden.
  Rgb visibleLight(const SourceSurface& surface, const Vec3& x, const Vec3& n, const Vec3& origin, std::uint64_t& rays) const {
    thread_local std::vector<double> cumulative, factor;
    thread_local std::vector<ClippedTriangle> clipped;
    cumulative.assign(surface.count, 0);
    factor.assign(surface.count, 0);
    clipped.resize(surface.count);
    Rgb unoccluded;
    double picked = 0;
    for (std::uint32_t t = 0; t < surface.count; ++t) {
      const SourceTriangle& triangle = sources.triangles[surface.first + t];
      ClippedTriangle& part = clipped[t];
      part.count = 0;
      if (dot(origin - triangle.corners[0], triangle.normal) > 0) {  // behind it, its back does not emit
        part.count = clipAbovePlane(triangle.corners, x, n, part.corners.data());
        const std::span<const Vec3> polygon(part.corners.data(), part.count);
        factor[t] = contourFormFactor(x, n, polygon);
        if (part.count >= 3) part.area = polygonArea(polygon);
        unoccluded += triangle.radiosity * factor[t];
        picked += triangle.luminance * factor[t];
      }
      cumulative[t] = picked;
    }
    if (!(picked > 0)) return {};
    double visible = 0, total = 0;
    for (int j = 0; j < 4 * samples; ++j) {
      if (j == samples && (visible == 0 || visible == total)) break;
      auto [u, v] = scrambledZeroTwo(static_cast<std::uint32_t>(j), su, sv);
      const double pick = u * picked;
      const std::uint32_t t = static_cast<std::uint32_t>(
          std::min<std::ptrdiff_t>(std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin(), surface.count - 1));
      const double below = t ? cumulative[t - 1] : 0, share = cumulative[t] - below;
      const ClippedTriangle& part = clipped[t];
      if (!(share > 0) || part.count < 3 || !(factor[t] > 0)) continue;
      u = std::clamp((pick - below) / share, 0.0, 1.0 - 1e-12);
      const SourceTriangle& triangle = sources.triangles[surface.first + t];
      const Vec3 y = sampleConvexPolygon(std::span<const Vec3>(part.corners.data(), part.count), u, v);
      const Vec3 d = y - origin;
      const double r2 = lengthSquared(d);
      if (!(r2 > 0)) continue;
      // The kernel over the point's density (∝ L_t F_t / area of the part; L_t cancels against
      // the luminance weighting of the share).
      const double kernel = std::max(0.0, dot(d, n)) * std::max(0.0, -dot(d, triangle.normal)) / (r2 * r2);
      if (!(kernel > 0)) continue;
      const double weight = kernel * part.area / factor[t];
      total += weight;
      ++rays;
      // The ray stops short of the source by the lift epsilon, so that it does not hit it.
      const double tMax = 1 - epsilon / std::sqrt(r2);
      if (tMax > 0 && !shadows.occluded(Ray{origin, d, 0, tMax})) visible += weight;
    }
    return total > 0 ? unoccluded * (visible / total) : Rgb{};
  }
};

struct IlluminanceMeter::State {
  explicit State(const SolutionView& s) : solution(s) {}
  SolutionView solution;
  IlluminanceOptions options;
  std::unique_ptr<RayCaster> vertexCaster;  // over solution.vertexMesh(), for the hemisphere rays
  std::unique_ptr<PatchInterpolation> reflected;  // ρ·E on the vertex mesh's patches (E per vertex)
  Sources emitters;                // B_e
  Sources bright;                  // ρE where it is far above the scene's mean
  std::vector<Rgb> patchEmission;  // B_e per patch of the vertex mesh
  std::vector<Light> electric, daylight;  // the solution's lights: the skies and suns apart
  std::unique_ptr<DirectLighting> lighting;  // over `electric`
  std::vector<Vec3> directions;
  double epsilon = 0;
  double setupSeconds = 0;
  mutable std::atomic<std::uint64_t> explicitRays{0};
};

IlluminanceMeter::IlluminanceMeter(const SolutionView& solution, const IlluminanceOptions& options)
    : state_(std::make_unique<State>(solution)) {
  const Timer timer;
  State& s = *state_;
  s.options = options;
  const Mesh& mesh = solution.vertexMesh();
  s.vertexCaster = makeEmbreeRayCaster(mesh);
  s.reflected = std::make_unique<PatchInterpolation>(mesh, solution.vertexValues(VertexQuantity::Irradiance), solution.vertexMeshAlbedo());
  s.emitters = sceneEmitters(solution.scene(), mesh);
  s.bright = brightReflectors(mesh, *s.reflected);
  // Skies and suns are measured apart (each alone, exactly as lights.h's irradiance gives it), so
  // that their parts of the direct light are known; the other lights go through Ward's testing.
  for (const Light& light : solution.lights())
    (light.kind == LightKind::Sky || light.kind == LightKind::Directional ? s.daylight : s.electric).push_back(light);
  s.lighting = std::make_unique<DirectLighting>(s.electric, solution.scene().metresPerUnit, options.shadowTolerance);
  s.patchEmission = emittedRadiosity(solution.scene(), mesh);
  s.directions = cosineDirections(options.indirectRays, options.seed);
  s.epsilon = rayEpsilon(mesh);
  s.setupSeconds = timer.seconds();
}

IlluminanceMeter::~IlluminanceMeter() = default;
IlluminanceMeter::IlluminanceMeter(IlluminanceMeter&&) noexcept = default;
IlluminanceMeter& IlluminanceMeter::operator=(IlluminanceMeter&&) noexcept = default;

double IlluminanceMeter::setupSeconds() const { return state_->setupSeconds; }

std::uint64_t IlluminanceMeter::raysCast() const { return state_->vertexCaster->raysCast() + state_->explicitRays.load(); }

Result<std::vector<PointIrradiance>> IlluminanceMeter::measure(std::span<const CalculationPoint> points) const {
  const State& s = *state_;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& n = points[i].normal;
    const Vec3& p = points[i].position;
    if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
      return Error{"point " + std::to_string(i) + ": its position is not finite"};
    if (!(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z) && length(n) > 0))
      return Error{"point " + std::to_string(i) + ": its normal is zero or not finite"};
  }
  const RayCaster& shadows = s.solution.caster();
  const double metresPerUnit = s.solution.scene().metresPerUnit;
  const int samples = std::max(s.options.emitterSamples, 1);
  Pcg32 rng(s.options.seed, 0xe31);
  const std::uint32_t su = rng.nextUint(), sv = rng.nextUint();
  const ExplicitIntegration emitters{s.emitters, shadows, s.epsilon, samples, su, sv};
  const ExplicitIntegration bright{s.bright, shadows, s.epsilon, samples, su, sv};

  std::vector<PointIrradiance> out(points.size());
  Progress progress("illuminance", points.size(), s.options.showProgress);
  parallelFor(0, points.size(), [&](std::size_t i) {
    const Vec3 n = normalize(points[i].normal);
    const Vec3 x = points[i].position;
    const Vec3 origin = x + n * s.epsilon;
    PointIrradiance& e = out[i];
    if (!s.electric.empty()) e.direct += s.lighting->irradiance(x, n, shadows, s.epsilon);
    for (const Light& light : s.daylight) (light.kind == LightKind::Sky ? e.sky : e.sun) += irradiance(light, x, n, shadows, s.epsilon, metresPerUnit, SkyEdges::Traced);
    e.direct += e.sky + e.sun;
    std::uint64_t rays = 0;
    thread_local std::vector<char> explicitEmitter, explicitBright;
    e.direct += emitters(x, n, explicitEmitter, rays);
    e.indirect += bright(x, n, explicitBright, rays);
    if (rays) s.explicitRays.fetch_add(rays, std::memory_order_relaxed);
    // The hemisphere: what the explicit integrations left out.
    Vec3 tangent, bitangent;
    orthonormalBasis(n, tangent, bitangent);
    thread_local std::vector<Ray> hemisphere;
    thread_local std::vector<std::optional<RayHit>> hits;
    hemisphere.resize(s.directions.size());
    hits.resize(s.directions.size());
    for (std::size_t k = 0; k < s.directions.size(); ++k) {
      const Vec3& local = s.directions[k];
      hemisphere[k] = Ray{origin, tangent * local.x + bitangent * local.y + n * local.z, 0, INFINITY};
    }
    s.vertexCaster->intersect(hemisphere, hits);
    Rgb reflected, emitted;
    for (std::size_t k = 0; k < s.directions.size(); ++k) {
      const std::optional<RayHit>& hit = hits[k];
      if (!hit || !hit->frontFace) continue;
      const int reflector = s.bright.ofPatch[hit->patch];
      if (reflector < 0 || !explicitBright[reflector]) reflected += s.reflected->at(hit->patch, origin + hemisphere[k].direction * hit->t);
      const int emitter = s.emitters.ofPatch[hit->patch];
      if (emitter >= 0 && !explicitEmitter[emitter]) emitted += s.patchEmission[hit->patch];
    }
    const double rayCount = static_cast<double>(s.directions.size());
    e.indirect += reflected / rayCount;
    e.direct += emitted / rayCount;
    progress.advance();
  }, 16);
  progress.finish();
  return out;
}

}  // namespace lambert
