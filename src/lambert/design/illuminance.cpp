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
#include "lambert/engine/solution.h"
#include "lambert/formfactor/kernels.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/light/emission.h"
#include "lambert/light/lights.h"
#include "lambert/light/many_lights.h"
#include "lambert/mesh/vertex_radiosity.h"

namespace lambert {
namespace {

// An emitting surface is integrated explicitly at a point where the bound on its light there is
// at least this share of the largest emitter's bound (see IlluminanceMeter::measure).
constexpr double kExplicitShare = 0.02;
// Below this share of the largest bound, an emitter is integrated explicitly only where one probe
// ray finds it visible.
constexpr double kProbeShare = 0.25;

// An emitting triangle of the scene (a fan triangle of an emitting face): its corners and front
// normal.
struct EmitterTriangle {
  std::array<Vec3, 3> corners;
  Vec3 normal;
};

// An emitting surface: its triangles (a range of Emitters::triangles), its emitted radiosity
// B_e = π L_e (W/m²), and a bounding sphere and area for the bound on what it can give a point.
struct EmitterSurface {
  std::uint32_t first = 0, count = 0;
  Rgb radiosity;
  double luminance = 0;  // of radiosity
  Vec3 centre;
  double radius = 0, area = 0;
  Vec3 normal;  // the front of a planar surface (every triangle facing the same way); zero otherwise
};

struct Emitters {
  std::vector<EmitterTriangle> triangles;
  std::vector<EmitterSurface> surfaces;
  std::vector<int> ofSceneSurface;  // per scene surface: its index in surfaces, or −1
};

Emitters sceneEmitters(const Scene& scene) {
  Emitters out;
  out.ofSceneSurface.assign(scene.surfaces.size(), -1);
  for (std::size_t index = 0; index < scene.surfaces.size(); ++index) {
    const Surface& surface = scene.surfaces[index];
    const Rgb radiosity = meanEmittedRadiance(scene, surface) * kPi;
    if (!(radiosity.maxComponent() > 0)) continue;
    EmitterSurface e;
    e.first = static_cast<std::uint32_t>(out.triangles.size());
    e.radiosity = radiosity;
    e.luminance = radiosity.luminance();
    Vec3 lo{INFINITY, INFINITY, INFINITY}, hi = -lo;
    for (const std::vector<std::uint32_t>& face : surfaceFaces(surface)) {
      const std::vector<Vec3> polygon = facePositions(surface, face);
      for (const Vec3& p : polygon) lo = componentMin(lo, p), hi = componentMax(hi, p);
      for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
        const Vec3 areaVector = cross(polygon[k] - polygon[0], polygon[k + 1] - polygon[0]);
        if (!(length(areaVector) > 0)) continue;
        out.triangles.push_back({{polygon[0], polygon[k], polygon[k + 1]}, normalize(areaVector)});
        e.area += length(areaVector) / 2;
      }
    }
    e.count = static_cast<std::uint32_t>(out.triangles.size()) - e.first;
    if (e.count == 0) continue;
    e.centre = (lo + hi) / 2;
    e.radius = length(hi - lo) / 2;
    e.normal = out.triangles[e.first].normal;
    for (std::uint32_t t = e.first; t < e.first + e.count; ++t)
      if (dot(out.triangles[t].normal, e.normal) < 1 - 1e-9) e.normal = {};
    out.ofSceneSurface[index] = static_cast<int>(out.surfaces.size());
    out.surfaces.push_back(e);
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

// The same directions at every point, each in the point's own frame: a scrambled (0,2)-sequence
// mapped to the cosine-weighted hemisphere (Malley's method: the unit disc lifted onto it),
// z along the normal.
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

}  // namespace

struct IlluminanceMeter::State {
  explicit State(const SolutionView& s) : solution(s) {}
  SolutionView solution;
  IlluminanceOptions options;
  std::unique_ptr<RayCaster> vertexCaster;  // over solution.vertexMesh(), for the hemisphere rays
  std::unique_ptr<PatchInterpolation> reflected;  // ρ·E on the vertex mesh's patches (E per vertex)
  Emitters emitters;
  std::vector<Rgb> patchEmission;  // B_e per patch of the vertex mesh
  std::unique_ptr<DirectLighting> lighting;
  std::vector<Vec3> directions;
  double epsilon = 0;
  double setupSeconds = 0;
  mutable std::atomic<std::uint64_t> emitterRays{0};
};

IlluminanceMeter::IlluminanceMeter(const SolutionView& solution, const IlluminanceOptions& options)
    : state_(std::make_unique<State>(solution)) {
  const Timer timer;
  State& s = *state_;
  s.options = options;
  const Mesh& mesh = solution.vertexMesh();
  s.vertexCaster = makeEmbreeRayCaster(mesh);
  s.reflected = std::make_unique<PatchInterpolation>(mesh, solution.vertexValues(VertexQuantity::Irradiance), solution.vertexMeshAlbedo());
  s.emitters = sceneEmitters(solution.scene());
  s.lighting = std::make_unique<DirectLighting>(solution.lights(), solution.scene().metresPerUnit, options.shadowTolerance);
  s.patchEmission = emittedRadiosity(solution.scene(), mesh);
  s.directions = cosineDirections(options.indirectRays, options.seed);
  s.epsilon = rayEpsilon(mesh);
  s.setupSeconds = timer.seconds();
}

IlluminanceMeter::~IlluminanceMeter() = default;
IlluminanceMeter::IlluminanceMeter(IlluminanceMeter&&) noexcept = default;
IlluminanceMeter& IlluminanceMeter::operator=(IlluminanceMeter&&) noexcept = default;

double IlluminanceMeter::setupSeconds() const { return state_->setupSeconds; }

std::uint64_t IlluminanceMeter::raysCast() const {
  return state_->vertexCaster->raysCast() + state_->emitterRays.load() ;
}

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
  const Mesh& mesh = s.solution.vertexMesh();
  const std::vector<Light>& lights = s.solution.lights();
  const RayCaster& shadows = s.solution.caster();
  const int samples = std::max(s.options.emitterSamples, 1);
  Pcg32 rng(s.options.seed, 0xe31);
  const std::uint32_t su = rng.nextUint(), sv = rng.nextUint();

  std::vector<PointIrradiance> out(points.size());
  Progress progress("illuminance", points.size(), s.options.showProgress);
  parallelFor(0, points.size(), [&](std::size_t i) {
    const Vec3 n = normalize(points[i].normal);
    const Vec3 x = points[i].position;
    const Vec3 origin = x + n * s.epsilon;
    PointIrradiance& e = out[i];
    if (!lights.empty()) e.direct += s.lighting->irradiance(x, n, shadows, s.epsilon);
    // The emitting surfaces: each one's unoccluded light is bounded by
    // B_e·min(1, A cos θ_x⁺ cos θ_y⁺ / (π (d − r)²)) over its bounding sphere (centre at d, radius
    // r): the kernel cos θ_x cos θ_y / (π |y − x|²) with each cosine at most (its projection of
    // the centre + r)/(d − r) (θ_y's only for a planar surface); those whose bound is at least
    // kExplicitShare of the largest are integrated explicitly, the rest (far or small: a
    // building's other rooms) are left to the hemisphere rays below, which count the emission of
    // exactly those emitters where they hit them — two disjoint estimators, no emitter counted
    // twice or missed.
    std::uint64_t rays = 0;
    thread_local std::vector<double> bound;
    thread_local std::vector<char> explicitly;
    bound.assign(s.emitters.surfaces.size(), 0);
    explicitly.assign(s.emitters.surfaces.size(), 0);
    double largestBound = 0;
    for (std::size_t k = 0; k < s.emitters.surfaces.size(); ++k) {
      const EmitterSurface& surface = s.emitters.surfaces[k];
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
    for (std::size_t k = 0; k < s.emitters.surfaces.size(); ++k) {
      if (!(bound[k] > 0) || bound[k] < kExplicitShare * largestBound) continue;
      const EmitterSurface& surface = s.emitters.surfaces[k];
      // A lesser emitter (another room's lamp) is first probed with one ray to its first
      // triangle's centroid: hidden, it is left to the hemisphere rays like a far one (the split
      // is still decided before those rays, so each emitter is counted by one estimator).
      if (bound[k] < kProbeShare * largestBound) {
        const EmitterTriangle& first = s.emitters.triangles[surface.first];
        const Vec3 d = (first.corners[0] + first.corners[1] + first.corners[2]) / 3 - origin;
        const double tMax = 1 - s.epsilon / std::fmax(length(d), 1e-300);
        ++rays;
        if (dot(d, n) <= 0 || tMax <= 0 || shadows.occluded(Ray{origin, d, 0, tMax})) continue;
      }
      explicitly[k] = 1;
      // Each triangle's exact unoccluded factor (its part above x's plane, kept for the samples);
      // then the surface's visible share from emitterSamples stratified points, each in a
      // triangle picked in proportion to its factor (the sequence's first coordinate picks it and
      // is reused, rescaled, within it).
      thread_local std::vector<double> cumulative;
      thread_local std::vector<ClippedTriangle> clipped;
      cumulative.assign(surface.count, 0);
      clipped.resize(surface.count);
      double surfaceFactor = 0;
      for (std::uint32_t t = 0; t < surface.count; ++t) {
        const EmitterTriangle& triangle = s.emitters.triangles[surface.first + t];
        ClippedTriangle& part = clipped[t];
        part.count = 0;
        if (dot(origin - triangle.corners[0], triangle.normal) > 0) {  // behind it, its back does not emit
          part.count = clipAbovePlane(triangle.corners, x, n, part.corners.data());
          const std::span<const Vec3> polygon(part.corners.data(), part.count);
          surfaceFactor += contourFormFactor(x, n, polygon);
          if (part.count >= 3) part.area = polygonArea(polygon);
        }
        cumulative[t] = surfaceFactor;
      }
      if (!(surfaceFactor > 0)) continue;
      // Where the first emitterSamples points do not all agree (a penumbra), four times as many.
      double visible = 0, total = 0;
      for (int j = 0; j < 4 * samples; ++j) {
        if (j == samples && (visible == 0 || visible == total)) break;
        auto [u, v] = scrambledZeroTwo(static_cast<std::uint32_t>(j), su, sv);
        const double pick = u * surfaceFactor;
        const std::uint32_t t = static_cast<std::uint32_t>(
            std::min<std::ptrdiff_t>(std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin(), surface.count - 1));
        const double below = t ? cumulative[t - 1] : 0, share = cumulative[t] - below;
        const ClippedTriangle& part = clipped[t];
        if (!(share > 0) || part.count < 3) continue;
        u = std::clamp((pick - below) / share, 0.0, 1.0 - 1e-12);
        const EmitterTriangle& triangle = s.emitters.triangles[surface.first + t];
        const Vec3 y = sampleConvexPolygon(std::span<const Vec3>(part.corners.data(), part.count), u, v);
        const Vec3 d = y - origin;
        const double r2 = lengthSquared(d);
        if (!(r2 > 0)) continue;
        // The kernel over the density the pick gives the point (∝ its triangle's factor over the
        // part's area): a consistent ratio estimate of the visible share.
        const double kernel = std::max(0.0, dot(d, n)) * std::max(0.0, -dot(d, triangle.normal)) / (r2 * r2);
        const double density = share / part.area;
        if (!(kernel > 0) || !(density > 0)) continue;
        const double weight = kernel / density;
        total += weight;
        ++rays;
        // The ray stops short of the emitter by the lift epsilon, so that it does not hit it.
        const double tMax = 1 - s.epsilon / std::sqrt(r2);
        if (tMax > 0 && !shadows.occluded(Ray{origin, d, 0, tMax})) visible += weight;
      }
      const double visibleFactor = total > 0 ? surfaceFactor * visible / total : 0;
      e.direct += surface.radiosity * visibleFactor;
    }
    if (rays) s.emitterRays.fetch_add(rays, std::memory_order_relaxed);
    Vec3 tangent, bitangent;
    orthonormalBasis(n, tangent, bitangent);
    Rgb reflected, emitted;
    thread_local std::vector<Ray> hemisphere;
    thread_local std::vector<std::optional<RayHit>> hits;
    hemisphere.resize(s.directions.size());
    hits.resize(s.directions.size());
    for (std::size_t k = 0; k < s.directions.size(); ++k) {
      const Vec3& local = s.directions[k];
      hemisphere[k] = Ray{origin, tangent * local.x + bitangent * local.y + n * local.z, 0, INFINITY};
    }
    s.vertexCaster->intersect(hemisphere, hits);
    for (std::size_t k = 0; k < s.directions.size(); ++k) {
      const std::optional<RayHit>& hit = hits[k];
      const Vec3& w = hemisphere[k].direction;
      if (!hit || !hit->frontFace) continue;
      reflected += s.reflected->at(hit->patch, origin + w * hit->t);
      const int emitter = s.emitters.ofSceneSurface[mesh.patches[hit->patch].surface];
      if (emitter >= 0 && !explicitly[emitter]) emitted += s.patchEmission[hit->patch];
    }
    e.indirect = reflected / static_cast<double>(s.directions.size());
    e.direct += emitted / static_cast<double>(s.directions.size());
    progress.advance();
  }, 16);
  progress.finish();
  return out;
}

}  // namespace lambert
