#include "lambert/light/lights.h"

#include <cmath>

#include "lambert/core/parallel.h"
#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"

namespace lambert {
namespace {

constexpr double kDegrees = kPi / 180;

double smoothstep(double edge0, double edge1, double x) {
  if (edge0 == edge1) return x < edge0 ? 0 : 1;
  double t = std::fmin(std::fmax((x - edge0) / (edge1 - edge0), 0.0), 1.0);
  return t * t * (3 - 2 * t);
}

// A spot's cone as mayReceive tests every patch against it: the unit axis and the cosine and sine
// of the half angle, computed once per light rather than per patch.
struct Cone {
  Vec3 axis;
  double cos = -1, sin = 0;
  explicit Cone(const Light& light) {
    if (light.kind != LightKind::Spot) return;
    axis = normalize(light.direction);
    cos = std::cos(light.coneAngleDegrees * kDegrees);
    sin = std::sin(light.coneAngleDegrees * kDegrees);
  }
};

// Whether any point of the patch can receive the light: it must face the light, and for a spot its
// bounding sphere must reach into the cone. Most patches lie outside a spot's cone; this spares
// them their shadow rays.
bool mayReceive(const Light& light, const Cone& cone, const Patch& patch, const PatchCorners& corners) {
  if (light.kind == LightKind::Directional) return dot(patch.normal, light.direction) < 0;
  bool faces = false;
  for (const Vec3& c : corners) faces |= dot(light.position - c, patch.normal) > 0;
  if (!faces || light.kind != LightKind::Spot) return faces;
  double radius = 0;
  for (const Vec3& c : corners) radius = std::fmax(radius, length(c - patch.centroid));
  Vec3 toCentre = patch.centroid - light.position;
  double distance = length(toCentre);
  if (distance <= radius) return true;
  // The sphere, seen from the light at an angle β = asin(radius / distance) about its centre,
  // reaches into the cone when the angle between the axis and the centre is below cone + β;
  // compared by cosines (cos(cone + β) = cos cone cos β − sin cone sin β), as no angle is needed.
  // Beyond π, every direction is within reach.
  const double sinBeta = radius / distance, cosBeta = std::sqrt(1 - sinBeta * sinBeta);
  if (cone.cos < 0 && sinBeta >= cone.sin) return true;
  const double cosAxis = std::fmin(std::fmax(dot(cone.axis, toCentre / distance), -1.0), 1.0);
  return cosAxis > cone.cos * cosBeta - cone.sin * sinBeta;
}

}  // namespace

double spotFalloff(const Light& spot, const Vec3& towardPoint) {
  double cosAngle = dot(normalize(spot.direction), normalize(towardPoint));
  double outer = spot.coneAngleDegrees * kDegrees;
  double inner = std::fmax(outer - spot.falloffDegrees * kDegrees, 0.0);
  return smoothstep(std::cos(outer), std::cos(inner), cosAngle);
}

Rgb unshadowedIrradiance(const Light& light, const Vec3& x, const Vec3& n, double metresPerUnit) {
  if (light.kind == LightKind::Directional) {
    double cosine = -dot(n, normalize(light.direction));
    return cosine > 0 ? light.irradiance * cosine : Rgb{};
  }
  Vec3 toLight = light.position - x;
  double distanceSquared = lengthSquared(toLight);
  double cosine = dot(n, toLight) / std::sqrt(distanceSquared);
  if (cosine <= 0 || distanceSquared <= 0) return {};
  double falloff = light.kind == LightKind::Spot ? spotFalloff(light, -toLight) : 1.0;
  if (falloff <= 0) return {};
  // E = I cosθ / r², with r in metres.
  return light.intensity * (falloff * cosine / (distanceSquared * metresPerUnit * metresPerUnit));
}

Rgb irradiance(const Light& light, const Vec3& x, const Vec3& n, const RayCaster& caster, double epsilon,
               double metresPerUnit) {
  Rgb e = unshadowedIrradiance(light, x, n, metresPerUnit);
  if (e.maxComponent() <= 0) return e;
  Vec3 origin = x + n * epsilon;
  Ray shadow = light.kind == LightKind::Directional
                   ? Ray{origin, -normalize(light.direction), 0, INFINITY}
                   : Ray{origin, light.position - origin, 0, 1 - 1e-7};
  return caster.occluded(shadow) ? Rgb{} : e;
}

std::vector<Rgb> patchIrradiance(const Mesh& mesh, const RayCaster& caster, const Light& light, double metresPerUnit,
                                 const DirectLightOptions& options) {
  std::vector<Rgb> result(mesh.numPatches());
  const double epsilon = rayEpsilon(mesh);
  const int samples = std::max(options.samplesPerPatch, 1);
  const Cone cone(light);
  parallelFor(0, mesh.numPatches(), [&](std::size_t i) {
    const Patch& patch = mesh.patches[i];
    PatchCorners corners = mesh.corners(i);
    if (!mayReceive(light, cone, patch, corners)) return;
    Pcg32 rng(options.seed, i);
    const std::uint32_t su = rng.nextUint(), sv = rng.nextUint();
    Rgb sum;
    for (int k = 0; k < samples; ++k) {
      auto [u, v] = scrambledZeroTwo(static_cast<std::uint32_t>(k), su, sv);
      sum += irradiance(light, sampleConvexPolygon(corners, u, v), patch.normal, caster, epsilon, metresPerUnit);
    }
    result[i] = sum / samples;
  }, 16);
  return result;
}

std::vector<Rgb> injectedRadiosity(const Mesh& mesh, const std::vector<Rgb>& albedo, const std::vector<Rgb>& irradiance) {
  std::vector<Rgb> injected(mesh.numPatches());
  for (std::size_t i = 0; i < mesh.numPatches(); ++i) injected[i] = albedo[i] * irradiance[i];
  return injected;
}

Rgb reflectedDirectRadiance(std::span<const Light> lights, const Vec3& x, const Vec3& n, const Rgb& albedo,
                            const RayCaster& caster, double epsilon, double metresPerUnit) {
  Rgb e;
  for (const Light& light : lights) e += irradiance(light, x, n, caster, epsilon, metresPerUnit);
  return albedo * e / kPi;
}

Light lightAtTime(const Light& light, double seconds) {
  Light moved = light;
  double speed = length(light.angularVelocity);
  if (speed > 0) moved.direction = normalize(rotate(light.direction, light.angularVelocity / speed, speed * seconds));
  return moved;
}

}  // namespace lambert
