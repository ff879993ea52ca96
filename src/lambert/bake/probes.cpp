#include "lambert/bake/probes.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>

#include "lambert/core/atomic_file.h"
#include "lambert/core/parallel.h"
#include "lambert/core/progress.h"
#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"
#include "lambert/core/timer.h"
#include "lambert/method/solution.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/light/lights.h"
#include "lambert/light/sky.h"
#include "lambert/mesh/vertex_radiosity.h"

namespace lambert {
namespace {

constexpr char kMagic[8] = {'L', 'M', 'B', 'P', 'R', 'O', 'B', 'E'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderBytes = 64;
constexpr std::size_t kMaxProbes = std::size_t{1} << 24;
constexpr double kDefaultProbeCount = 4096;

// Â_l of the clamped cosine, per coefficient k = l² + l + m.
constexpr double kCosineBand[kShCoefficients] = {kPi,          2 * kPi / 3, 2 * kPi / 3, 2 * kPi / 3, kPi / 4,
                                                 kPi / 4,      kPi / 4,     kPi / 4,     kPi / 4};

// Point `index` of the scrambled (0,2)-sequence on the unit sphere, by the equal-area map
// z = 1 − 2u, φ = 2πv (Archimedes' hat-box theorem), which keeps the square's strata equal in
// solid angle.
Vec3 sphereDirection(std::uint32_t index, std::uint32_t scrambleU, std::uint32_t scrambleV) {
  const UnitSquarePoint p = scrambledZeroTwo(index, scrambleU, scrambleV);
  const double z = 1 - 2 * p.u;
  const double r = std::sqrt(std::fmax(0.0, 1 - z * z));
  const double phi = 2 * kPi * p.v;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

int roundedRays(int rays) { return static_cast<int>(std::bit_ceil(static_cast<unsigned>(std::max(rays, 1)))); }

void addScaled(ShRgb& sh, const Vec3& direction, const Rgb& value) {
  const std::array<double, kShCoefficients> y = shBasis(direction);
  for (int k = 0; k < kShCoefficients; ++k) sh[k] += value * y[k];
}

void putU32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int b = 0; b < 4; ++b) out.push_back(static_cast<std::uint8_t>(v >> (8 * b)));
}
void putU64(std::vector<std::uint8_t>& out, std::uint64_t v) {
  for (int b = 0; b < 8; ++b) out.push_back(static_cast<std::uint8_t>(v >> (8 * b)));
}
void putF64(std::vector<std::uint8_t>& out, double v) { putU64(out, std::bit_cast<std::uint64_t>(v)); }

std::uint32_t getU32(const std::uint8_t* p) {
  std::uint32_t v = 0;
  for (int b = 0; b < 4; ++b) v |= static_cast<std::uint32_t>(p[b]) << (8 * b);
  return v;
}
double getF64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int b = 0; b < 8; ++b) v |= static_cast<std::uint64_t>(p[b]) << (8 * b);
  return std::bit_cast<double>(v);
}

std::size_t paddedToFour(std::size_t n) { return (n + 3) / 4 * 4; }

}  // namespace

std::array<double, kShCoefficients> shBasis(const Vec3& d) {
  constexpr double c0 = 0.28209479177387814;  // 1 / (2√π)
  constexpr double c1 = 0.48860251190291992;  // √(3 / 4π)
  constexpr double c2 = 1.0925484305920792;   // √(15 / 4π)
  constexpr double c3 = 0.31539156525252005;  // √(5 / 16π)
  constexpr double c4 = 0.54627421529603959;  // √(15 / 16π)
  return {c0,
          c1 * d.y,
          c1 * d.z,
          c1 * d.x,
          c2 * d.x * d.y,
          c2 * d.y * d.z,
          c3 * (3 * d.z * d.z - 1),
          c2 * d.x * d.z,
          c4 * (d.x * d.x - d.y * d.y)};
}

ShRgb projectRadiance(const std::function<Rgb(const Vec3&)>& radiance, int rays, std::uint64_t seed,
                      std::uint64_t stream) {
  const int n = roundedRays(rays);
  Pcg32 rng(seed, stream);
  const std::uint32_t su = rng.nextUint(), sv = rng.nextUint();
  ShRgb sumLY{};                                 // Σ L(ω) Y_k(ω)
  std::array<double, kShCoefficients> sumY{};    // Σ Y_k(ω): the quadrature's error on a constant
  Rgb sumL;
  for (int i = 0; i < n; ++i) {
    const Vec3 w = sphereDirection(static_cast<std::uint32_t>(i), su, sv);
    const Rgb l = radiance(w);
    const std::array<double, kShCoefficients> y = shBasis(w);
    for (int k = 0; k < kShCoefficients; ++k) {
      sumLY[k] += l * y[k];
      sumY[k] += y[k];
    }
    sumL += l;
  }
  // The sample mean as a control variate: its projection is known exactly (onto Y00 alone), so
  // only the variation about it is left to the quadrature, and a uniform environment gives
  // exactly L·√(4π) Y00.
  const Rgb mean = sumL / n;
  ShRgb sh;
  sh[0] = mean * std::sqrt(4 * kPi);
  for (int k = 1; k < kShCoefficients; ++k) sh[k] = (sumLY[k] - mean * sumY[k]) * (4 * kPi / n);
  return sh;
}

ShRgb irradianceFromRadiance(const ShRgb& radiance) {
  ShRgb e;
  for (int k = 0; k < kShCoefficients; ++k) e[k] = radiance[k] * kCosineBand[k];
  return e;
}

Rgb evaluateSh(const ShRgb& coefficients, const Vec3& n) {
  const std::array<double, kShCoefficients> y = shBasis(n);
  Rgb sum;
  for (int k = 0; k < kShCoefficients; ++k) sum += coefficients[k] * y[k];
  return sum;
}

Vec3 ProbeVolume::position(std::size_t probe) const {
  const std::size_t i = probe % dims[0], j = probe / dims[0] % dims[1], k = probe / dims[0] / dims[1];
  return origin + Vec3{static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)} * spacing;
}

ShRgb ProbeVolume::irradianceSh(std::size_t probe) const {
  ShRgb sh;
  const float* c = coefficients.data() + probe * kProbeFloats;
  for (int k = 0; k < kShCoefficients; ++k) sh[k] = {c[3 * k], c[3 * k + 1], c[3 * k + 2]};
  return sh;
}

Rgb ProbeVolume::irradiance(std::size_t probe, const Vec3& unitNormal) const {
  return evaluateSh(irradianceSh(probe), unitNormal);
}

std::optional<ShRgb> ProbeVolume::irradianceShAt(const Vec3& p) const {
  if (valid.empty()) return std::nullopt;
  // The cell holding p (clamped onto the grid) and p's place in it, per axis.
  std::array<std::uint32_t, 3> lo{};
  std::array<double, 3> t{};
  for (int a = 0; a < 3; ++a) {
    const double g = std::fmin(std::fmax((p[a] - origin[a]) / spacing, 0.0), dims[a] - 1.0);
    lo[a] = std::min(static_cast<std::uint32_t>(g), dims[a] > 1 ? dims[a] - 2 : 0u);
    t[a] = dims[a] > 1 ? g - lo[a] : 0;
  }
  ShRgb sum{};
  double weights = 0;
  for (int corner = 0; corner < 8; ++corner) {
    std::array<std::size_t, 3> index{};
    double w = 1;
    for (int a = 0; a < 3; ++a) {
      const int step = corner >> a & 1;
      if (step && dims[a] == 1) w = 0;
      index[a] = lo[a] + static_cast<std::size_t>(step);
      w *= step ? t[a] : 1 - t[a];
    }
    if (w <= 0) continue;
    const std::size_t probe = index[0] + dims[0] * (index[1] + dims[1] * index[2]);
    if (!valid[probe]) continue;
    const ShRgb sh = irradianceSh(probe);
    for (int k = 0; k < kShCoefficients; ++k) sum[k] += sh[k] * w;
    weights += w;
  }
  if (weights <= 0) return std::nullopt;
  for (Rgb& c : sum) c = c / weights;
  return sum;
}

Result<ProbeVolume> probeGrid(const Scene& scene, const ProbeOptions& options) {
  if (!std::isfinite(options.spacing) || options.spacing < 0)
    return Error{"probe spacing must be a positive number of scene units (or 0 for the default), not " +
                 std::to_string(options.spacing)};
  const Bounds bounds = options.bounds ? *options.bounds : sceneBounds(scene);
  const Vec3 extent = bounds.hi - bounds.lo;
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(extent[a]) || extent[a] < 0)
      return Error{"the probe grid's bounds are empty (the scene has no surfaces, or lo exceeds hi)"};
  const double diagonal = length(extent);
  if (!(diagonal > 0)) return Error{"the probe grid's bounds have no extent"};
  double spacing = options.spacing;
  if (spacing == 0)
    spacing = std::fmax(std::cbrt(extent.x * extent.y * extent.z / kDefaultProbeCount), diagonal / 64);
  ProbeVolume volume;
  volume.spacing = spacing;
  double count = 1;
  for (int a = 0; a < 3; ++a) {
    const double cells = std::fmax(1.0, std::ceil(extent[a] / spacing - 1e-9));
    count *= cells;
    if (count > static_cast<double>(kMaxProbes))
      return Error{"a probe spacing of " + std::to_string(spacing) + " gives more than " + std::to_string(kMaxProbes) +
                   " probes over the bounds; give a spacing of at least " +
                   std::to_string(std::cbrt(std::fmax(extent.x, spacing) * std::fmax(extent.y, spacing) *
                                            std::fmax(extent.z, spacing) / static_cast<double>(kMaxProbes)) * 1.01)};
    volume.dims[a] = static_cast<std::uint32_t>(cells);
  }
  // Cells centred on the box: the first probe half a cell in from the grid's corner.
  const Vec3 centre = (bounds.lo + bounds.hi) * 0.5;
  auto firstProbe = [&](int a) { return centre[a] - 0.5 * spacing * (volume.dims[a] - 1.0); };
  volume.origin = {firstProbe(0), firstProbe(1), firstProbe(2)};
  return volume;
}

Result<ProbeVolume> bakeProbes(const SolutionView& solution, const ProbeOptions& options) {
  Timer timer;
  if (options.raysPerProbe < 1 || options.raysPerProbe > (1 << 20))
    return Error{"rays per probe must be between 1 and 2^20, not " + std::to_string(options.raysPerProbe)};
  if (!(options.invalidBackFaceFraction >= 0 && options.invalidBackFaceFraction <= 1))
    return Error{"the back-face share that marks a probe invalid must be between 0 and 1, not " +
                 std::to_string(options.invalidBackFaceFraction)};
  Result<ProbeVolume> grid = probeGrid(solution.scene(), options);
  if (!grid) return grid;
  ProbeVolume volume = std::move(*grid);
  const std::size_t numProbes = std::size_t{volume.dims[0]} * volume.dims[1] * volume.dims[2];
  volume.valid.assign(numProbes, 0);
  volume.coefficients.assign(numProbes * kProbeFloats, 0.0f);

  const Mesh& mesh = solution.vertexMesh();
  const std::unique_ptr<RayCaster> caster = makeEmbreeRayCaster(mesh);
  const Timer radianceTimer;
  const PatchInterpolation vertexRadiance(mesh, solution.vertexRadiance());
  volume.radianceSeconds = radianceTimer.seconds();
  const std::vector<Light>& lights = solution.lights();
  const RayCaster& shadowCaster = solution.caster();
  const double metresPerUnit = solution.scene().metresPerUnit;
  const int rays = roundedRays(options.raysPerProbe);
  const double allowedBackFaces = options.invalidBackFaceFraction * rays;

  Progress progress("probes", numProbes, options.showProgress);
  std::atomic<std::size_t> numValid{0};
  parallelFor(0, numProbes, [&](std::size_t probe) {
    const Vec3 p = volume.position(probe);
    int backFaces = 0;
    ShRgb radiance = projectRadiance([&](const Vec3& w) -> Rgb {
      const std::optional<RayHit> hit = caster->intersect(Ray{p, w, 0, INFINITY});
      if (!hit) {  // a ray that leaves the scene sees the sky, where there is one
        Rgb sky;
        for (const Light& light : lights)
          if (light.kind == LightKind::Sky && light.sky) sky += light.sky->radiance(w);
        return sky;
      }
      if (!hit->frontFace) {
        ++backFaces;
        return {};
      }
      return vertexRadiance.at(hit->patch, p + w * hit->t);
    }, rays, options.seed, probe);
    progress.advance();
    if (backFaces > allowedBackFaces) return;
    // The lights: a delta of E⊥ toward each light it sees (irradiance() along that very direction,
    // with its shadow ray).
    for (const Light& light : lights) {
      if (light.kind == LightKind::Sky) continue;  // not a delta: its radiance came with the rays above
      const Vec3 toward = light.kind == LightKind::Directional ? -normalize(light.direction) : light.position - p;
      if (!(lengthSquared(toward) > 0)) continue;
      const Vec3 w = normalize(toward);
      const Rgb perpendicular = irradiance(light, p, w, shadowCaster, 0, metresPerUnit);
      if (perpendicular.maxComponent() > 0) addScaled(radiance, w, perpendicular);
    }
    const ShRgb e = irradianceFromRadiance(radiance);
    float* out = volume.coefficients.data() + probe * kProbeFloats;
    for (int k = 0; k < kShCoefficients; ++k)
      for (int c = 0; c < 3; ++c) out[3 * k + c] = static_cast<float>(e[k][c]);
    volume.valid[probe] = 1;
    numValid.fetch_add(1, std::memory_order_relaxed);
  }, 4);
  progress.finish();
  volume.numValid = numValid.load();
  volume.raysCast = caster->raysCast();
  volume.seconds = timer.seconds();
  return volume;
}

Status writeProbes(const std::string& path, const ProbeVolume& volume) {
  const std::size_t n = volume.numProbes();
  LAMBERT_CHECK(n == std::size_t{volume.dims[0]} * volume.dims[1] * volume.dims[2]);
  LAMBERT_CHECK(volume.coefficients.size() == n * kProbeFloats);
  std::vector<std::uint8_t> bytes;
  bytes.reserve(kHeaderBytes + paddedToFour(n) + 4 * volume.coefficients.size());
  bytes.insert(bytes.end(), std::begin(kMagic), std::end(kMagic));
  putU32(bytes, kVersion);
  putU32(bytes, kShCoefficients);
  for (int a = 0; a < 3; ++a) putF64(bytes, volume.origin[a]);
  putF64(bytes, volume.spacing);
  for (int a = 0; a < 3; ++a) putU32(bytes, volume.dims[a]);
  std::size_t numValid = 0;
  for (std::uint8_t v : volume.valid) numValid += v != 0;
  putU32(bytes, static_cast<std::uint32_t>(numValid));
  LAMBERT_CHECK(bytes.size() == kHeaderBytes);
  for (std::uint8_t v : volume.valid) bytes.push_back(v != 0);
  bytes.resize(kHeaderBytes + paddedToFour(n), 0);
  for (float f : volume.coefficients) putU32(bytes, std::bit_cast<std::uint32_t>(f));
  return writeFileAtomically(path, bytes);
}

Result<ProbeVolume> readProbes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open the probe file"};
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < kHeaderBytes || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    return Error{path + ": not a lambert probe file (no LMBPROBE header)"};
  const std::uint8_t* h = bytes.data();
  if (std::uint32_t version = getU32(h + 8); version != kVersion)
    return Error{path + ": probe file version " + std::to_string(version) + ", this lambert reads version " +
                 std::to_string(kVersion)};
  if (getU32(h + 12) != kShCoefficients)
    return Error{path + ": " + std::to_string(getU32(h + 12)) + " SH coefficients per channel, expected 9"};
  ProbeVolume volume;
  volume.origin = {getF64(h + 16), getF64(h + 24), getF64(h + 32)};
  volume.spacing = getF64(h + 40);
  std::uint64_t n = 1;
  for (int a = 0; a < 3; ++a) {
    volume.dims[a] = getU32(h + 48 + 4 * a);
    n *= volume.dims[a];
  }
  if (!std::isfinite(volume.spacing) || !(volume.spacing > 0) || n == 0 || n > kMaxProbes)
    return Error{path + ": header gives spacing " + std::to_string(volume.spacing) + " and " + std::to_string(n) +
                 " probes; the file is damaged"};
  const std::uint32_t numValid = getU32(h + 60);
  const std::uint64_t expected = kHeaderBytes + paddedToFour(n) + 4 * kProbeFloats * n;
  if (bytes.size() != expected)
    return Error{path + ": " + std::to_string(bytes.size()) + " bytes, but its header's grid needs " +
                 std::to_string(expected) + "; the file is truncated or damaged"};
  volume.valid.assign(h + kHeaderBytes, h + kHeaderBytes + n);
  for (std::uint8_t v : volume.valid) volume.numValid += v != 0;
  if (volume.numValid != numValid)
    return Error{path + ": the header counts " + std::to_string(numValid) + " valid probes, the flags " +
                 std::to_string(volume.numValid) + "; the file is damaged"};
  volume.coefficients.resize(n * kProbeFloats);
  const std::uint8_t* c = h + kHeaderBytes + paddedToFour(n);
  for (std::size_t i = 0; i < volume.coefficients.size(); ++i)
    volume.coefficients[i] = std::bit_cast<float>(getU32(c + 4 * i));
  return volume;
}

}  // namespace lambert
