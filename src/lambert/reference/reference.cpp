#include "lambert/reference/reference.h"

#include <algorithm>
#include <cmath>

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/core/progress.h"
#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"
#include "lambert/formfactor/kernels.h"
#include "lambert/light/emission.h"
#include "lambert/light/lights.h"
#include "lambert/mesh/vertex_radiosity.h"
#include "lambert/render/camera.h"

namespace lambert {
namespace {

// Pixel streams start here, so they never coincide with vertex streams (vertex indices).
constexpr std::uint64_t kPixelStreamBase = std::uint64_t{1} << 40;
// A primary ray passes through at most this many culled backs (walls behind walls); beyond, the
// pixel is black.
constexpr int kMaxCulledBacks = 64;

// A uniformly random permutation of 0 .. order.size() - 1 (Fisher–Yates).
void shuffle(std::vector<std::uint32_t>& order, Pcg32& rng) {
  for (std::uint32_t i = 0; i < order.size(); ++i) {
    std::uint32_t j = rng.nextBelow(i + 1);
    order[i] = order[j];
    order[j] = i;
  }
}

// Power heuristic (β = 2) weight of a strategy whose density is pOwn against one of density
// pOther, written so that an infinite density gives 0 or 1, never NaN.
double powerWeight(double pOwn, double pOther) {
  double ratio = pOther / pOwn;
  return 1 / (1 + ratio * ratio);
}

UnitSquarePoint randomPoint(Pcg32& rng) {
  double u = rng.nextDouble();
  return {u, rng.nextDouble()};
}

}  // namespace

ReferenceRenderer::ReferenceRenderer(const Scene& scene, const Mesh& geometry, ReferenceOptions options)
    : scene_(scene), options_(options), geometry_(std::make_unique<Mesh>(geometry)) {
  LAMBERT_CHECK(options_.samplesPerPixel >= 1);
  LAMBERT_CHECK(options_.vertexSamples >= 1);
  LAMBERT_CHECK(options_.minBounces >= 0);
  LAMBERT_CHECK(options_.maxBounces >= 1);
  LAMBERT_CHECK(geometry_->numPatches() > 0);
  caster_ = makeEmbreeRayCaster(*geometry_);
  epsilon_ = rayEpsilon(*geometry_);
  for (const Surface& surface : scene_.surfaces) {
    LAMBERT_CHECK(surface.material >= 0 && static_cast<std::size_t>(surface.material) < scene_.materials.size());
    // A texture enters as its mean: the tracer does not look textures up per point.
    const Material& material = scene_.materials[static_cast<std::size_t>(surface.material)];
    albedo_.push_back(material.texture ? material.albedo * material.texture->mean : material.albedo);
    emitted_.push_back(meanEmittedRadiance(scene_, surface));
  }
  for (std::uint32_t i = 0; i < geometry_->numPatches(); ++i) {
    const Patch& patch = geometry_->patches[i];
    LAMBERT_CHECK(patch.surface < scene_.surfaces.size());
    if (emitted_[patch.surface].maxComponent() <= 0 || !(patch.area > 0)) continue;
    emitterArea_ += patch.area;
    emitterPatches_.push_back(i);
    emitterCdf_.push_back(emitterArea_);
  }
}

ReferenceRenderer::~ReferenceRenderer() = default;
ReferenceRenderer::ReferenceRenderer(ReferenceRenderer&&) noexcept = default;
ReferenceRenderer& ReferenceRenderer::operator=(ReferenceRenderer&&) noexcept = default;

std::uint64_t ReferenceRenderer::raysCast() const { return caster_->raysCast(); }

Rgb ReferenceRenderer::lightIrradiance(const Vertex& v) const {
  Rgb e;
  for (const Light& light : scene_.lights)
    e += irradiance(light, v.position, v.normal, *caster_, epsilon_, scene_.metresPerUnit);
  return e;
}

// MIS weight of the cosine-sampled direction that reached an emitter at squared distance r² (scene
// units²), against next-event estimation: both as densities per steradian.
double ReferenceRenderer::cosineWeight(double cosAtVertex, double distanceSquared, double cosAtEmitter) const {
  double pCosine = cosAtVertex / kPi;
  double pLight = distanceSquared / (emitterArea_ * cosAtEmitter);
  return powerWeight(pCosine, pLight);
}

// One next-event sample of the emitters' irradiance at v, MIS-weighted:
//   L_e cosθ cosθ' A / r² · w_light = L_e cosθ / p_light · w_light,
// which stays below π L_e / 2 however close the emitter is.
Rgb ReferenceRenderer::emitterIrradiance(const Vertex& v, UnitSquarePoint sample) const {
  if (emitterPatches_.empty()) return {};
  // The first coordinate picks a patch by area and is rescaled to be reused within it.
  double target = sample.u * emitterArea_;
  std::size_t k = static_cast<std::size_t>(std::upper_bound(emitterCdf_.begin(), emitterCdf_.end(), target) -
                                           emitterCdf_.begin());
  k = std::min(k, emitterPatches_.size() - 1);
  const double start = k == 0 ? 0.0 : emitterCdf_[k - 1];
  const std::uint32_t index = emitterPatches_[k];
  const Patch& patch = geometry_->patches[index];
  double u = std::clamp((target - start) / patch.area, 0.0, std::nextafter(1.0, 0.0));
  Vec3 y = sampleConvexPolygon(geometry_->corners(index), u, sample.v);

  Vec3 d = y - v.position;
  double r2 = lengthSquared(d);
  if (!(r2 > 0)) return {};
  double r = std::sqrt(r2);
  double cosX = dot(v.normal, d) / r;
  double cosY = -dot(patch.normal, d) / r;
  if (cosX <= 0 || cosY <= 0) return {};
  Vec3 origin = v.position + v.normal * epsilon_;
  Vec3 end = y + patch.normal * epsilon_;
  if (caster_->occluded(Ray{origin, end - origin, 0, 1})) return {};
  double pLight = r2 / (emitterArea_ * cosY);
  double pCosine = cosX / kPi;
  return emitted_[patch.surface] * (cosX / pLight * powerWeight(pLight, pCosine));
}

// Reflected radiance ρ/π · E leaving v (its emission excluded), estimated along one path whose
// first vertex is v, the `bounce`-th reflection (0-based). The first vertex's emitter sample and
// direction may be given (stratified by the caller); everything else comes from rng.
Rgb ReferenceRenderer::reflected(Vertex v, int bounce, Pcg32& rng, const UnitSquarePoint* firstLight,
                                 const UnitSquarePoint* firstDirection) const {
  Rgb sum;
  Rgb throughput = Rgb::gray(1);  // what multiplies the radiance leaving v
  while (bounce < options_.maxBounces) {
    const Rgb& rho = albedo_[v.surface];
    if (rho.maxComponent() <= 0) break;
    UnitSquarePoint lightSample = firstLight ? *firstLight : randomPoint(rng);
    sum += throughput * rho * (lightIrradiance(v) + emitterIrradiance(v, lightSample)) / kPi;

    // Cosine-weighted continuation: ρ/π · L cosθ / (cosθ/π) = ρ L.
    Rgb next = throughput * rho;
    if (bounce >= options_.minBounces) {
      double survive = std::fmin(0.95, next.maxComponent());
      if (rng.nextDouble() >= survive) break;
      next = next / survive;
    }
    UnitSquarePoint directionSample = firstDirection ? *firstDirection : randomPoint(rng);
    firstLight = firstDirection = nullptr;
    Vec3 direction = cosineDirection(v.normal, directionSample);
    Vec3 origin = v.position + v.normal * epsilon_;
    auto hit = caster_->intersect(Ray{origin, direction, 0, INFINITY});
    if (!hit || !hit->frontFace) break;
    const Patch& patch = geometry_->patches[hit->patch];
    Vertex z{origin + direction * hit->t, patch.normal, patch.surface};
    const Rgb& le = emitted_[z.surface];
    if (le.maxComponent() > 0)
      sum += next * le * cosineWeight(dot(direction, v.normal), hit->t * hit->t, -dot(direction, z.normal));
    throughput = next;
    v = z;
    ++bounce;
  }
  return sum;
}

Rgb ReferenceRenderer::outgoingRadiance(const Vec3& x, const Vec3& n, std::uint32_t surface,
                                        std::uint64_t stream) const {
  LAMBERT_CHECK(surface < scene_.surfaces.size());
  const Rgb& le = emitted_[surface];
  const Rgb& rho = albedo_[surface];
  if (rho.maxComponent() <= 0) return le;
  return le + rho * irradianceAt(x, n, surface, stream) / kPi;
}

Rgb ReferenceRenderer::irradianceAt(const Vec3& x, const Vec3& n, std::uint32_t surface, std::uint64_t stream) const {
  LAMBERT_CHECK(surface < scene_.surfaces.size());
  Pcg32 rng(options_.seed, stream);
  const std::uint32_t lu = rng.nextUint(), lv = rng.nextUint(), du = rng.nextUint(), dv = rng.nextUint();
  const Vertex v{x, n, surface};
  const Vec3 origin = x + n * epsilon_;
  const int samples = options_.vertexSamples;
  Rgb emitterSum, incomingSum;
  for (int k = 0; k < samples; ++k) {
    const auto index = static_cast<std::uint32_t>(k);
    emitterSum += emitterIrradiance(v, scrambledZeroTwo(index, lu, lv));
    // The first bounce is never rouletted: every one of the stratified directions is traced.
    Vec3 direction = cosineDirection(n, scrambledZeroTwo(index, du, dv));
    auto hit = caster_->intersect(Ray{origin, direction, 0, INFINITY});
    if (!hit || !hit->frontFace) continue;
    const Patch& patch = geometry_->patches[hit->patch];
    Vertex z{origin + direction * hit->t, patch.normal, patch.surface};
    const Rgb& lz = emitted_[z.surface];
    if (lz.maxComponent() > 0)
      incomingSum += lz * cosineWeight(dot(direction, n), hit->t * hit->t, -dot(direction, z.normal));
    incomingSum += reflected(z, 1, rng, nullptr, nullptr);
  }
  // E_lights + E_emitters + π L_in (cosine sampling).
  return lightIrradiance(v) + emitterSum / samples + incomingSum * (kPi / samples);
}

std::vector<Rgb> ReferenceRenderer::vertexRadiance(const Mesh& mesh) const {
  const std::size_t n = mesh.numVertices();
  const std::vector<VertexSite> sites = vertexSites(mesh, 1e-4 * sceneDiagonal(scene_));
  std::vector<Rgb> result(n);
  Progress progress("reference", n, options_.showProgress);
  parallelFor(0, n, [&](std::size_t i) {
    if (lengthSquared(sites[i].normal) > 0) {
      const std::uint32_t surface = i < mesh.vertexSurface.size() ? mesh.vertexSurface[i] : 0;
      result[i] = outgoingRadiance(sites[i].point, sites[i].normal, surface, i);
    }
    progress.advance();
  });
  progress.finish();
  return result;
}

Image ReferenceRenderer::render(int width, int height) const {
  PinholeCamera camera(scene_.camera, width, height);
  Image image;
  image.width = width;
  image.height = height;
  image.pixels.assign(static_cast<std::size_t>(width) * height, Rgb{});
  const int spp = options_.samplesPerPixel;
  Progress progress("reference", static_cast<std::uint64_t>(height), options_.showProgress);
  parallelFor(0, static_cast<std::size_t>(height), [&](std::size_t row) {
    std::vector<std::uint32_t> lightOrder(static_cast<std::size_t>(spp)), directionOrder(lightOrder.size());
    for (int col = 0; col < width; ++col) {
      const std::uint64_t pixel = row * static_cast<std::uint64_t>(width) + static_cast<std::uint64_t>(col);
      Pcg32 rng(options_.seed, kPixelStreamBase + pixel);
      std::uint32_t scramble[6];
      for (std::uint32_t& s : scramble) s = rng.nextUint();
      // Padding (Kollig & Keller 2002): the three 2-D sets are paired through independent random
      // permutations of their indices. Pairing point k with point k of the others would make the
      // pixel estimate a slice through the 6-D integrand that does not converge as spp grows.
      shuffle(lightOrder, rng);
      shuffle(directionOrder, rng);
      Rgb sum;
      for (int k = 0; k < spp; ++k) {
        const auto index = static_cast<std::uint32_t>(k);
        UnitSquarePoint offset = scrambledZeroTwo(index, scramble[0], scramble[1]);
        UnitSquarePoint light = scrambledZeroTwo(lightOrder[index], scramble[2], scramble[3]);
        UnitSquarePoint direction = scrambledZeroTwo(directionOrder[index], scramble[4], scramble[5]);
        double px = col + offset.u, py = static_cast<double>(row) + offset.v;
        Vec3 d = normalize(camera.forward * camera.focalPixels + camera.right * (px - 0.5 * width) +
                           camera.up * (0.5 * height - py));
        // The camera culls back faces as the rasterizer does (render/rasterizer.h): a primary
        // ray passes through the backs of one-sided faces. Every later ray meets them as they
        // are, black and opaque.
        // It starts at the near plane, where the rasterizer clips (render/camera.h).
        const double near = camera.nearDistance / std::fmax(dot(d, camera.forward), 1e-6);
        std::optional<RayHit> hit = caster_->intersect(Ray{camera.eye, d, near, INFINITY});
        for (int passed = 0; hit && !hit->frontFace && passed < kMaxCulledBacks; ++passed)
          hit = caster_->intersect(Ray{camera.eye, d, hit->t + epsilon_, INFINITY});
        if (!hit || !hit->frontFace) continue;
        const Patch& patch = geometry_->patches[hit->patch];
        Vertex z{camera.eye + d * hit->t, patch.normal, patch.surface};
        sum += emitted_[z.surface] + reflected(z, 0, rng, &light, &direction);
      }
      image.at(col, static_cast<int>(row)) = sum / spp;
    }
    progress.advance();
  });
  progress.finish();
  return image;
}

}  // namespace lambert
