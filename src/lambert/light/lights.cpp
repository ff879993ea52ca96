#include "lambert/light/lights.h"

#include <algorithm>
#include <cmath>

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"
#include "lambert/light/sky.h"
#include "lambert/light/photometry.h"
#include "lambert/core/photometric.h"

namespace lambert {
namespace {

constexpr double kDegrees = kPi / 180;


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

// Whether the sphere reaches into the spot's cone. Seen from the light, the sphere spans an
// angle β = asin(radius / distance) about its centre, so it reaches into the cone when the angle
// between the axis and the centre is below cone + β; compared by cosines (cos(cone + β) =
// cos cone cos β − sin cone sin β), as no angle is needed. Beyond π, every direction is within
// reach. A larger sphere about the same or a nearby centre that holds this one reaches in too:
// PatchSphereTree relies on it.
bool sphereReachesCone(const Light& spot, const Cone& cone, const Vec3& centre, double radius) {
  const Vec3 toCentre = centre - spot.position;
  const double distance = length(toCentre);
  if (distance <= radius) return true;
  const double sinBeta = radius / distance, cosBeta = std::sqrt(1 - sinBeta * sinBeta);
  if (cone.cos < 0 && sinBeta >= cone.sin) return true;
  const double cosAxis = std::fmin(std::fmax(dot(cone.axis, toCentre / distance), -1.0), 1.0);
  return cosAxis > cone.cos * cosBeta - cone.sin * sinBeta;
}

// A patch's bounding sphere about its centroid.
double patchRadius(const Patch& patch, const PatchCorners& corners) {
  double radius = 0;
  for (const Vec3& c : corners) radius = std::fmax(radius, length(c - patch.centroid));
  return radius;
}

// Whether any point of the patch can receive the light: it must face the light, and for a spot its
// bounding sphere must reach into the cone. Most patches lie outside a spot's cone; this spares
// them their shadow rays.
bool mayReceive(const Light& light, const Cone& cone, const Patch& patch, const PatchCorners& corners) {
  if (light.kind == LightKind::Directional) return dot(patch.normal, light.direction) < 0;
  // Only a patch facing straight down sees none of the sky above the horizon.
  if (light.kind == LightKind::Sky) return light.sky && (light.sky->isUniformEnvironment() || patch.normal.y > -1 + 1e-12);
  // An opening's sources lie off its centre: a patch edge-on to the centre may face some of them.
  if (light.kind == LightKind::Luminaire && light.luminaireModel == LuminaireModel::Opening) return true;
  bool faces = false;
  for (const Vec3& c : corners) faces |= dot(light.position - c, patch.normal) > 0;
  if (!faces || light.kind != LightKind::Spot) return faces;
  return sphereReachesCone(light, cone, patch.centroid, patchRadius(patch, corners));
}

// The mean irradiance of patch i, or zero where it cannot receive the light.
Rgb meanPatchIrradiance(const Mesh& mesh, std::size_t i, const RayCaster& caster, const Light& light, const Cone& cone,
                        double epsilon, double metresPerUnit, const DirectLightOptions& options) {
  const Patch& patch = mesh.patches[i];
  const PatchCorners corners = mesh.corners(i);
  if (!mayReceive(light, cone, patch, corners)) return {};
  // A sky's light varies smoothly over a patch (the hierarchy splits elements where it does not, at
  // light edges): the centroid, the midpoint rule, exact where the light changes linearly, gives a
  // patch's mean better than a few scattered points, at one estimate's cost (Light::skyDirections
  // rays). Floor patches lit through a window: 3.7% off at worst with four scattered points, 1% at
  // the centroid (SkyComponentTest.APatchsSkyIsItsPointsMean).
  if (light.kind == LightKind::Sky) return irradiance(light, patch.centroid, patch.normal, caster, epsilon, metresPerUnit);
  Pcg32 rng(options.seed, i);
  const std::uint32_t su = rng.nextUint(), sv = rng.nextUint();
  const int samples = std::max(options.samplesPerPatch, 1);
  Rgb sum;
  for (int k = 0; k < samples; ++k) {
    auto [u, v] = scrambledZeroTwo(static_cast<std::uint32_t>(k), su, sv);
    sum += irradiance(light, sampleConvexPolygon(corners, u, v), patch.normal, caster, epsilon, metresPerUnit);
  }
  return sum / samples;
}

}  // namespace

double spotFalloff(const Light& spot, const Vec3& towardPoint) {
  double cosAngle = dot(normalize(spot.direction), normalize(towardPoint));
  double outer = spot.coneAngleDegrees * kDegrees;
  double inner = std::fmax(outer - spot.falloffDegrees * kDegrees, 0.0);
  return smoothstep(std::cos(outer), std::cos(inner), cosAngle);
}

LuminaireFrame luminaireFrame(const LuminaireAiming& aiming) {
  // The compass in scene axes (lambert is y-up with north −z, so AGi32's X, Y, Z = x, −z, y).
  const Vec3 east{1, 0, 0}, north{0, 0, -1}, up{0, 1, 0};
  const double o = aiming.orientDegrees * kDegrees, t = aiming.tiltDegrees * kDegrees;
  const double r = aiming.rollDegrees * kDegrees, s = aiming.spinDegrees * kDegrees;
  // Orient then tilt: the nadir leaves straight down toward the oriented C0 (the plan direction
  // `horizontal`), and C0 rises with it, toward up; C90 stays horizontal, `horizontal` turned 90°
  // toward the east-to-north sense.
  const Vec3 horizontal = east * std::cos(o) + north * std::sin(o);
  LuminaireFrame f;
  f.nadir = horizontal * std::sin(t) - up * std::cos(t);
  f.c0 = horizontal * std::cos(t) + up * std::sin(t);
  f.c90 = north * std::cos(o) - east * std::sin(o);
  // Roll about C0: the nadir toward C90 (C90 toward −nadir, the local +Z).
  const Vec3 nadir = f.nadir * std::cos(r) + f.c90 * std::sin(r);
  f.c90 = f.c90 * std::cos(r) - f.nadir * std::sin(r);
  f.nadir = nadir;
  // Spin about the nadir's axis: C0 toward C90.
  const Vec3 c0 = f.c0 * std::cos(s) + f.c90 * std::sin(s);
  f.c90 = f.c90 * std::cos(s) - f.c0 * std::sin(s);
  f.c0 = c0;
  return f;
}

LuminaireAiming aimingOfDirection(const Vec3& aim, double spinDegrees) {
  const Vec3 a = normalize(aim);
  const double eastward = a.x, northward = -a.z, horizontal = std::hypot(eastward, northward);
  LuminaireAiming angles;
  angles.tiltDegrees = std::atan2(horizontal, -a.y) / kDegrees;
  if (horizontal > 1e-9) {
    angles.orientDegrees = std::atan2(northward, eastward) / kDegrees;
    if (angles.orientDegrees < 0) angles.orientDegrees += 360;
    angles.orientDegrees += 0.0;  // atan2(−0, x) is −0: never print "−0"
  } else {
    // Vertical: the plan azimuth is undefined; orient 0 leaves C0 to the spin alone (and the
    // tilt exactly 0 or 180, so that a downlight's frame is east turned by its spin).
    angles.tiltDegrees = a.y < 0 ? 0 : 180;
  }
  angles.spinDegrees = spinDegrees;
  return angles;
}

LuminaireFrame luminaireFrame(const Light& light) {
  return luminaireFrame(aimingOfDirection(light.direction, light.rotationDegrees));
}

void setLuminaireFrame(Light& light, const Vec3& nadir, const Vec3& c0) {
  light.direction = normalize(nadir);
  const LuminaireFrame unspun = luminaireFrame(aimingOfDirection(light.direction, 0));
  light.rotationDegrees = std::atan2(dot(c0, unspun.c90), dot(c0, unspun.c0)) / kDegrees;
}

void aimLuminaire(Light& light, const LuminaireAiming& aiming) {
  const LuminaireFrame f = luminaireFrame(aiming);
  setLuminaireFrame(light, f.nadir, f.c0);
}

void photometricAngles(const LuminaireFrame& frame, const Vec3& direction, double& cDegrees, double& gammaDegrees) {
  const double cosGamma = std::fmin(std::fmax(dot(direction, frame.nadir), -1.0), 1.0);
  gammaDegrees = std::acos(cosGamma) / kDegrees;
  cDegrees = std::atan2(dot(direction, frame.c90), dot(direction, frame.c0)) / kDegrees;
  if (cDegrees < 0) cDegrees += 360;
}

namespace {

// The IES tilt factor of a luminaire as aimed: its lamps tilt with it, by the angle between its
// aim and straight down (LM-63-2002 §5.8; lamp geometry 1, the common one, tilts about any axis).
double tiltFactor(const Light& light) {
  if (!light.photometry || light.photometry->tilt.degrees.empty()) return 1;
  const double cosTilt = std::fmin(std::fmax(-normalize(light.direction).y, -1.0), 1.0);
  return light.photometry->tilt.factor(std::acos(cosTilt) / kDegrees);
}

Rgb luminaireIntensity(const Light& light, const LuminaireFrame& frame, double tilt, const Vec3& outward) {
  if (!light.photometry) return {};
  double c = 0, gamma = 0;
  photometricAngles(frame, outward, c, gamma);
  return light.intensity * (light.photometry->candela(c, gamma) * tilt / kLumensPerWatt);
}

// E = I(direction) cosθ / r² from a point source at `source` sending `share` of the luminaire's
// intensity, r in metres.
Rgb luminaireSourceIrradiance(const Light& light, const LuminaireFrame& frame, double tilt, double share, const Vec3& source,
                              const Vec3& x, const Vec3& n, double metresPerUnit) {
  const Vec3 toLight = source - x;
  const double distanceSquared = lengthSquared(toLight);
  if (!(distanceSquared > 0)) return {};
  const double distance = std::sqrt(distanceSquared);
  const double cosine = dot(n, toLight) / distance;
  if (cosine <= 0) return {};
  return luminaireIntensity(light, frame, tilt, toLight / -distance) * (share * cosine / (distanceSquared * metresPerUnit * metresPerUnit));
}

}  // namespace

Rgb luminaireIntensity(const Light& light, const Vec3& outward) {
  return luminaireIntensity(light, luminaireFrame(light), tiltFactor(light), normalize(outward));
}

std::vector<Vec3> luminaireSources(const Light& light, double metresPerUnit) {
  if (light.luminaireModel != LuminaireModel::Opening || !light.photometry) return {light.position};
  const Photometry& p = *light.photometry;
  const double longest = std::fmax(p.openingLength, p.openingWidth);
  if (!(longest > 0)) return {light.position};
  const int perSide = std::max(1, light.openingSamplesPerSide);
  const int nLength = std::max(1, static_cast<int>(std::lround(perSide * p.openingLength / longest)));
  const int nWidth = std::max(1, static_cast<int>(std::lround(perSide * p.openingWidth / longest)));
  const LuminaireFrame frame = luminaireFrame(light);
  std::vector<Vec3> sources;
  for (int i = 0; i < nLength; ++i)
    for (int j = 0; j < nWidth; ++j) {
      // Cell centres, as fractions of the sides from the centre: (i + ½)/n − ½.
      const double a = (i + 0.5) / nLength - 0.5, b = (j + 0.5) / nWidth - 0.5;
      if (p.round && a * a + b * b > 0.25) continue;
      sources.push_back(light.position + (frame.c0 * (a * p.openingLength) + frame.c90 * (b * p.openingWidth)) / metresPerUnit);
    }
  if (sources.empty()) sources.push_back(light.position);
  return sources;
}

double smoothstep(double edge0, double edge1, double x) {
  if (edge0 == edge1) return x < edge0 ? 0 : 1;
  double t = std::fmin(std::fmax((x - edge0) / (edge1 - edge0), 0.0), 1.0);
  return t * t * (3 - 2 * t);
}

Rgb unshadowedIrradiance(const Light& light, const Vec3& x, const Vec3& n, double metresPerUnit) {
  if (light.kind == LightKind::Sky) {
    // The same directions as irradiance() below, all visible: never less than the shadowed value.
    if (!light.sky) return {};
    return light.sky->colour() * (unobstructedSkyIlluminance(*light.sky, n, light.skyDirections) / kLumensPerWatt);
  }
  if (light.kind == LightKind::Luminaire) {
    const LuminaireFrame frame = luminaireFrame(light);
    const double tilt = tiltFactor(light);
    if (light.luminaireModel == LuminaireModel::FarField)
      return luminaireSourceIrradiance(light, frame, tilt, 1.0, light.position, x, n, metresPerUnit);
    const std::vector<Vec3> sources = luminaireSources(light, metresPerUnit);
    Rgb e;
    for (const Vec3& s : sources) e += luminaireSourceIrradiance(light, frame, tilt, 1.0 / sources.size(), s, x, n, metresPerUnit);
    return e;
  }
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
               double metresPerUnit, SkyEdges skyEdges) {
  if (light.kind == LightKind::Sky) {
    // ∫ L(ω) V(x, ω) max(0, n·ω) dω: a ray to infinity per direction above the horizon (every
    // direction of a uniform environment).
    if (!light.sky) return {};
    const Vec3 origin = x + n * epsilon;
    thread_local std::vector<Ray> rays;
    const double lux = skyIlluminance(*light.sky, n, light.skyDirections, [&](std::span<const Vec3> directions, std::span<bool> seen) {
      rays.clear();
      for (const Vec3& w : directions) rays.push_back(Ray{origin, w, 0, INFINITY});
      caster.occluded(rays, seen);
      for (bool& s : seen) s = !s;
    }, skyEdges);
    return light.sky->colour() * (lux / kLumensPerWatt);
  }
  if (light.kind == LightKind::Luminaire && light.luminaireModel == LuminaireModel::Opening) {
    // Each of the opening's sources with its own shadow ray: a partly hidden opening gives a
    // penumbra.
    const LuminaireFrame frame = luminaireFrame(light);
    const double tilt = tiltFactor(light);
    const std::vector<Vec3> sources = luminaireSources(light, metresPerUnit);
    const Vec3 origin = x + n * epsilon;
    Rgb e;
    for (const Vec3& s : sources) {
      const Rgb part = luminaireSourceIrradiance(light, frame, tilt, 1.0 / sources.size(), s, x, n, metresPerUnit);
      if (part.maxComponent() > 0 && !caster.occluded(Ray{origin, s - origin, 0, 1 - 1e-7})) e += part;
    }
    return e;
  }
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
  const Cone cone(light);
  parallelFor(0, mesh.numPatches(), [&](std::size_t i) {
    result[i] = meanPatchIrradiance(mesh, i, caster, light, cone, epsilon, metresPerUnit, options);
  }, 16);
  return result;
}

void patchIrradiance(const Mesh& mesh, const RayCaster& caster, const Light& light, double metresPerUnit,
                     const DirectLightOptions& options, double epsilon, std::span<const std::uint32_t> patches,
                     std::vector<Rgb>& irradiance) {
  LAMBERT_CHECK(irradiance.size() == mesh.numPatches());
  const Cone cone(light);
  parallelFor(0, patches.size(), [&](std::size_t k) {
    const std::uint32_t i = patches[k];
    irradiance[i] = meanPatchIrradiance(mesh, i, caster, light, cone, epsilon, metresPerUnit, options);
  }, 16);
}

PatchSphereTree::PatchSphereTree(const Mesh& mesh) : numPatches_(mesh.numPatches()) {
  LAMBERT_CHECK(numPatches_ < 0xffffffffu);
  patches_.resize(numPatches_);
  std::vector<Vec3> centre(numPatches_);
  std::vector<double> radius(numPatches_);
  for (std::uint32_t i = 0; i < numPatches_; ++i) {
    patches_[i] = i;
    centre[i] = mesh.patches[i].centroid;
    radius[i] = patchRadius(mesh.patches[i], mesh.corners(i));
  }
  if (numPatches_ == 0) return;
  // The nodes, depth first on an explicit stack, each with the range of patches_ it holds, split
  // at the median centroid along the centroids' longest extent.
  nodes_.push_back({});
  nodes_[0].end = static_cast<std::uint32_t>(numPatches_);
  std::vector<std::uint32_t> stack{0};
  while (!stack.empty()) {
    const std::uint32_t at = stack.back();
    stack.pop_back();
    const std::uint32_t begin = nodes_[at].begin, end = nodes_[at].end;
    if (end - begin <= kLeafSize) continue;
    // (std::min and std::max, not fmin and fmax, which are calls: centroids are finite.)
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (std::uint32_t k = begin; k < end; ++k) {
      const Vec3& c = centre[patches_[k]];
      lo[0] = std::min(lo[0], c.x), lo[1] = std::min(lo[1], c.y), lo[2] = std::min(lo[2], c.z);
      hi[0] = std::max(hi[0], c.x), hi[1] = std::max(hi[1], c.y), hi[2] = std::max(hi[2], c.z);
    }
    const Vec3 extent{hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(patches_.begin() + begin, patches_.begin() + mid, patches_.begin() + end, [&](std::uint32_t a, std::uint32_t b) {
      const double x = centre[a][axis], y = centre[b][axis];
      return x < y || (x == y && a < b);
    });
    const auto first = static_cast<std::uint32_t>(nodes_.size());
    nodes_[at].firstChild = first;
    nodes_.push_back({{}, 0, begin, mid, 0});
    nodes_.push_back({{}, 0, mid, end, 0});
    stack.push_back(first);
    stack.push_back(first + 1);
  }
  // The spheres, children (made after their parents) first: a leaf's about the middle of its
  // patches' spheres' box, reaching the farthest; a parent's the smallest that holds its two
  // children's. Each is grown past rounding, so that a sphere it holds never reaches into a cone
  // it misses.
  auto grown = [](Node& node) {
    const double scale = std::fmax(std::fabs(node.centre.x), std::fmax(std::fabs(node.centre.y), std::fabs(node.centre.z)));
    node.radius = node.radius * (1 + 1e-9) + 1e-9 * scale;
  };
  for (std::size_t at = nodes_.size(); at-- > 0;) {
    Node& node = nodes_[at];
    if (node.firstChild == 0) {
      Vec3 lo{INFINITY, INFINITY, INFINITY}, hi = -lo;
      for (std::uint32_t k = node.begin; k < node.end; ++k) {
        const std::uint32_t i = patches_[k];
        const Vec3 r{radius[i], radius[i], radius[i]};
        lo = componentMin(lo, centre[i] - r);
        hi = componentMax(hi, centre[i] + r);
      }
      node.centre = (lo + hi) * 0.5;
      node.radius = 0;
      for (std::uint32_t k = node.begin; k < node.end; ++k)
        node.radius = std::fmax(node.radius, length(centre[patches_[k]] - node.centre) + radius[patches_[k]]);
      grown(node);
      continue;
    }
    const Node &a = nodes_[node.firstChild], &b = nodes_[node.firstChild + 1];
    const double apart = length(b.centre - a.centre);
    if (apart + b.radius <= a.radius) {
      node.centre = a.centre, node.radius = a.radius;
    } else if (apart + a.radius <= b.radius) {
      node.centre = b.centre, node.radius = b.radius;
    } else {
      node.radius = 0.5 * (apart + a.radius + b.radius);
      node.centre = a.centre + (b.centre - a.centre) * ((node.radius - a.radius) / apart);
    }
    grown(node);
  }
}

std::vector<std::uint32_t> PatchSphereTree::candidates(const Light& light) const {
  std::vector<std::uint32_t> out;
  if (light.kind != LightKind::Spot) {
    out.resize(numPatches_);
    for (std::uint32_t i = 0; i < numPatches_; ++i) out[i] = i;
    return out;
  }
  if (nodes_.empty()) return out;
  const Cone cone(light);
  std::vector<std::uint32_t> stack{0};
  while (!stack.empty()) {
    const Node& node = nodes_[stack.back()];
    stack.pop_back();
    if (!sphereReachesCone(light, cone, node.centre, node.radius)) continue;
    if (node.firstChild == 0) {
      out.insert(out.end(), patches_.begin() + node.begin, patches_.begin() + node.end);
      continue;
    }
    stack.push_back(node.firstChild);
    stack.push_back(node.firstChild + 1);
  }
  std::sort(out.begin(), out.end());
  return out;
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

double lightLumens(const Light& light) {
  const double intensity = kLumensPerWatt * light.intensity.luminance();  // cd along the axis (a luminaire's multiplier)
  switch (light.kind) {
    case LightKind::Point:
      return 4 * kPi * intensity;
    case LightKind::Spot: {
      const double outer = std::fmin(light.coneAngleDegrees, 180.0);
      const int steps = std::max(1, static_cast<int>(std::ceil(outer / 0.01)));
      const double dTheta = outer * kDegrees / steps;
      double solidAngle = 0;  // ∫ falloff dω
      Light axis = light;
      axis.direction = {0, 0, 1};
      for (int k = 0; k < steps; ++k) {
        const double theta = (k + 0.5) * dTheta;
        solidAngle += spotFalloff(axis, {std::sin(theta), 0, std::cos(theta)}) * std::sin(theta) * dTheta;
      }
      return 2 * kPi * solidAngle * intensity;
    }
    case LightKind::Luminaire:
      return light.photometry ? light.photometry->luminousFlux() * light.intensity.luminance() * tiltFactor(light) : 0;
    case LightKind::Directional:
    case LightKind::Sky:
      return 0;
  }
  return 0;
}

}  // namespace lambert
