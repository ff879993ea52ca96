#include "lambert/light/sky.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>

#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"
#include "lambert/light/sun.h"

namespace lambert {
namespace {

constexpr double kRadians = kPi / 180;

// ISO 15469:2004 table 1: the six gradation groups (a, b) and six indicatrix groups (c, d, e), and
// which pair each of the fifteen types combines.
constexpr double kGradation[6][2] = {{4.0, -0.70}, {1.1, -0.8}, {0.0, -1.0}, {-1.0, -0.55}, {-1.0, -0.32}, {-1.0, -0.15}};
constexpr double kIndicatrix[6][3] = {{0, -1.0, 0.00}, {2, -1.5, 0.15}, {5, -2.5, 0.30}, {10, -3.0, 0.45}, {16, -3.0, 0.30}, {24, -2.8, 0.15}};
constexpr int kTypeGroups[15][2] = {{1, 1}, {1, 2}, {2, 1}, {2, 2}, {3, 1}, {3, 2}, {3, 3}, {3, 4},
                                    {4, 2}, {4, 3}, {4, 4}, {5, 4}, {5, 5}, {6, 5}, {6, 6}};
const char* const kDescriptions[15] = {
    "CIE standard overcast sky, steep luminance gradation towards zenith, azimuthal uniformity",
    "overcast, with steep luminance gradation and slight brightening towards the sun",
    "overcast, moderately graded with azimuthal uniformity",
    "overcast, moderately graded and slight brightening towards the sun",
    "sky of uniform luminance",
    "partly cloudy sky, no gradation towards zenith, slight brightening towards the sun",
    "partly cloudy sky, no gradation towards zenith, brighter circumsolar region",
    "partly cloudy sky, no gradation towards zenith, distinct solar corona",
    "partly cloudy, with the obscured sun",
    "partly cloudy, with brighter circumsolar region",
    "white-blue sky with distinct solar corona",
    "CIE standard clear sky, low luminance turbidity",
    "CIE standard clear sky, polluted atmosphere",
    "cloudless turbid sky with broad solar corona",
    "white-blue turbid sky with broad solar corona",
};

double gradation(const CieSkyParameters& p, double cosZenith) {
  if (cosZenith <= 0) return 1;  // exp(b / cos Z) → 0 at the horizon (b < 0 in every type)
  return 1 + p.a * std::exp(p.b / cosZenith);
}

double indicatrix(const CieSkyParameters& p, double cosSunAngle) {
  const double chi = std::acos(std::clamp(cosSunAngle, -1.0, 1.0));
  return 1 + p.c * (std::exp(p.d * chi) - std::exp(p.d * kPi / 2)) + p.e * cosSunAngle * cosSunAngle;
}

// Perez et al. 1993, eq. 1: the same gradation (b ≤ 0 here; b = 0 gives 1 + a up to the horizon),
// and the indicatrix 1 + c·exp(d·γ) + e·cos²γ, without the standard's shift that makes f(90°) = 1.
// Each is clamped at 0 (SkyModel::perez says why).
double perezGradation(const CieSkyParameters& p, double cosZenith) {
  if (cosZenith <= 0) return std::fmax(0.0, p.b < 0 ? 1 : 1 + p.a);
  return std::fmax(0.0, 1 + p.a * std::exp(p.b / cosZenith));
}

double perezIndicatrix(const CieSkyParameters& p, double cosSunAngle) {
  const double gamma = std::acos(std::clamp(cosSunAngle, -1.0, 1.0));
  return std::fmax(0.0, 1 + p.c * std::exp(p.d * gamma) + p.e * cosSunAngle * cosSunAngle);
}

// The largest values of the two factors: the gradation is monotonic in cos Z (its ends); the
// indicatrix, a monotonic exponential plus e·cos²γ, can peak inside (e < 0): sampled every 0.18°.
double perezGradationMost(const CieSkyParameters& p) { return std::fmax(perezGradation(p, 1), perezGradation(p, 0)); }
double perezIndicatrixMost(const CieSkyParameters& p) {
  double most = 0;
  for (int i = 0; i <= 1024; ++i) most = std::fmax(most, perezIndicatrix(p, std::cos(i * kPi / 1024)));
  return most;
}

}  // namespace

CieSkyParameters cieStandardSkyParameters(int type) {
  LAMBERT_CHECK(type >= 1 && type <= 15);
  const auto [g, i] = kTypeGroups[type - 1];
  return {kGradation[g - 1][0], kGradation[g - 1][1], kIndicatrix[i - 1][0], kIndicatrix[i - 1][1], kIndicatrix[i - 1][2]};
}

std::string cieStandardSkyDescription(int type) {
  LAMBERT_CHECK(type >= 1 && type <= 15);
  return kDescriptions[type - 1];
}

Result<SkyModel> SkyModel::cieStandard(int type, double sunAzimuthDegrees, double sunElevationDegrees, double zenithLuminance,
                                       const Vec3& north) {
  if (type < 1 || type > 15) return Error{"CIE standard sky type " + std::to_string(type) + " does not exist (types are 1 to 15)"};
  if (!(sunElevationDegrees >= -90 && sunElevationDegrees <= 90)) return Error{"the sun's elevation must be within −90° to 90°"};
  if (!std::isfinite(sunAzimuthDegrees)) return Error{"the sun's azimuth must be a finite number of degrees"};
  if (!(zenithLuminance >= 0 && std::isfinite(zenithLuminance))) return Error{"the zenith luminance must be finite and not negative"};
  if (!(std::fabs(north.x) + std::fabs(north.z) > 0)) return Error{"north must be a horizontal direction (not along y)"};
  SkyModel sky;
  sky.type_ = type;
  sky.p_ = cieStandardSkyParameters(type);
  sky.sunAzimuthDegrees_ = sunAzimuthDegrees;
  sky.sunElevationDegrees_ = sunElevationDegrees;
  sky.north_ = normalize(Vec3{north.x, 0, north.z});
  sky.zenithLuminance_ = zenithLuminance;
  sky.finish();
  return sky;
}

SkyModel SkyModel::traditionalOvercast(double zenithLuminance, const Vec3& north) {
  LAMBERT_CHECK(zenithLuminance >= 0 && std::isfinite(zenithLuminance));
  LAMBERT_CHECK(std::fabs(north.x) + std::fabs(north.z) > 0);
  SkyModel sky;
  sky.type_ = 0;
  sky.north_ = normalize(Vec3{north.x, 0, north.z});
  sky.zenithLuminance_ = zenithLuminance;
  sky.finish();
  return sky;
}

Result<SkyModel> SkyModel::perez(const PerezCoefficients& coefficients, double sunAzimuthDegrees, double sunElevationDegrees,
                                 double zenithLuminance, const Vec3& north) {
  for (double x : {coefficients.a, coefficients.b, coefficients.c, coefficients.d, coefficients.e})
    if (!std::isfinite(x)) return Error{"the Perez coefficients a–e must be finite numbers"};
  if (!(sunElevationDegrees >= -90 && sunElevationDegrees <= 90)) return Error{"the sun's elevation must be within −90° to 90°"};
  if (!std::isfinite(sunAzimuthDegrees)) return Error{"the sun's azimuth must be a finite number of degrees"};
  if (!(zenithLuminance >= 0 && std::isfinite(zenithLuminance))) return Error{"the zenith luminance must be finite and not negative"};
  if (!(std::fabs(north.x) + std::fabs(north.z) > 0)) return Error{"north must be a horizontal direction (not along y)"};
  SkyModel sky;
  sky.type_ = kPerez;
  sky.perez_ = coefficients;
  sky.perez_.b = std::fmin(coefficients.b, 0.0);
  sky.p_ = {sky.perez_.a, sky.perez_.b, sky.perez_.c, sky.perez_.d, sky.perez_.e};
  sky.sunAzimuthDegrees_ = sunAzimuthDegrees;
  sky.sunElevationDegrees_ = sunElevationDegrees;
  sky.north_ = normalize(Vec3{north.x, 0, north.z});
  sky.zenithLuminance_ = zenithLuminance;
  if (!(perezGradationMost(sky.p_) > 0) || !(perezIndicatrixMost(sky.p_) > 0)) sky.p_ = {};  // all dark: uniform, as gendaymtx
  sky.finish();
  return sky;
}

Result<SkyModel> SkyModel::uniformEnvironment(const Rgb& radiance) {
  for (int c = 0; c < 3; ++c)
    if (!(radiance[c] >= 0 && std::isfinite(radiance[c])))
      return Error{"an environment's radiance must be finite and not negative in every channel"};
  if (!(radiance.luminance() > 0)) return Error{"an environment's radiance must not be black (it would light nothing)"};
  SkyModel sky;
  sky.type_ = kUniformEnvironment;
  sky.zenithLuminance_ = luminanceCandelasPerSquareMetre(radiance);
  sky.colour_ = radiance * (1 / radiance.luminance());
  sky.finish();
  return sky;
}

void SkyModel::finish() {
  sun_ = skyDirection(sunAzimuthDegrees_, sunElevationDegrees_, north_);
  if (type_ == kUniformEnvironment) {
    gradationAtZenith_ = indicatrixAtZenith_ = 1;
    horizontalIlluminance_ = kPi * zenithLuminance_;
    return;
  }
  const double cosSunZenith = std::sin(sunElevationDegrees_ * kRadians);
  gradationAtZenith_ = type_ == 0 ? 1 : type_ == kPerez ? perezGradation(p_, 1) : gradation(p_, 1);
  indicatrixAtZenith_ = type_ == 0 ? 1 : type_ == kPerez ? perezIndicatrix(p_, cosSunZenith) : indicatrix(p_, cosSunZenith);
  if (type_ == kPerez) {
    // A factor the formula darkens at the zenith is taken relative to its largest value instead
    // (SkyModel::perez: the sky's scale is then no zenith luminance).
    if (!(gradationAtZenith_ > 1e-9)) gradationAtZenith_ = perezGradationMost(p_);
    if (!(indicatrixAtZenith_ > 1e-9)) indicatrixAtZenith_ = perezIndicatrixMost(p_);
  }
  // E_h = ∫₀^{2π} ∫₀^{π/2} L(Z, α) cos Z sin Z dZ dα: Simpson's rule in Z (the integrand is smooth
  // up to the horizon, where exp(b / cos Z) and all its derivatives vanish) and the midpoint rule
  // in α (periodic: it converges geometrically); 128 × 256 cells, accurate to about 1e-8 (a Perez
  // sky's clamped factors have kinks, where the rules are first order: PerezSkyTest's quadrature
  // checks it to 1e-5). Made for every hour of a year of weather (design/annual_daylight.h), so
  // the cosines are tabulated once: cos χ = cos Zs cos Z + sin Zs sin Z cos(α − αs).
  constexpr int kZenithSteps = 128, kAzimuthSteps = 256;
  const double dz = (kPi / 2) / kZenithSteps, da = 2 * kPi / kAzimuthSteps;
  const double sunZenith = (90 - sunElevationDegrees_) * kRadians, sunAzimuth = sunAzimuthDegrees_ * kRadians;
  std::array<double, kAzimuthSteps> cosDeltaAzimuth;
  for (int j = 0; j < kAzimuthSteps; ++j) cosDeltaAzimuth[j] = std::cos((j + 0.5) * da - sunAzimuth);
  double sum = 0;
  for (int i = 0; i <= kZenithSteps; ++i) {
    const double z = i * dz, cosZ = std::cos(z), sinZ = std::sin(z);
    const double weight = i == 0 || i == kZenithSteps ? 1 : i % 2 ? 4 : 2;
    double ring = 0;
    for (int j = 0; j < kAzimuthSteps; ++j)
      ring += relativeFromCosines(cosZ, std::clamp(std::cos(sunZenith) * cosZ + std::sin(sunZenith) * sinZ * cosDeltaAzimuth[j], -1.0, 1.0));
    sum += weight * ring * cosZ * sinZ;
  }
  sum /= 3;
  horizontalIlluminance_ = zenithLuminance_ * sum * dz * da;
}

SkyModel SkyModel::withHorizontalIlluminance(double lux) const {
  LAMBERT_CHECK(lux > 0 && std::isfinite(lux));
  SkyModel scaled = *this;
  if (!(zenithLuminance_ > 0)) {  // a dark sky: its shape at Lz = 1 first
    scaled.zenithLuminance_ = 1;
    scaled.finish();
    return scaled.withHorizontalIlluminance(lux);
  }
  const double perZenithLuminance = horizontalIlluminance_ / zenithLuminance_;
  scaled.zenithLuminance_ = lux / perZenithLuminance;
  scaled.horizontalIlluminance_ = lux;
  return scaled;
}

double SkyModel::relativeGradation(double cosZenith) const {
  if (type_ == kUniformEnvironment) return 1;
  if (type_ == 0) return (1 + 2 * cosZenith) / 3;  // Moon and Spencer: (1 + 2 sin elevation) / 3
  return (type_ == kPerez ? perezGradation(p_, cosZenith) : gradation(p_, cosZenith)) / gradationAtZenith_;
}

double SkyModel::relativeIndicatrix(double cosSunAngle) const {
  if (type_ == kUniformEnvironment || type_ == 0) return 1;
  return (type_ == kPerez ? perezIndicatrix(p_, cosSunAngle) : indicatrix(p_, cosSunAngle)) / indicatrixAtZenith_;
}

double SkyModel::relativeLuminance(double zenithAngle, double azimuth) const {
  const double sunZenith = (90 - sunElevationDegrees_) * kRadians, sunAzimuth = sunAzimuthDegrees_ * kRadians;
  const double cosSunAngle = std::cos(sunZenith) * std::cos(zenithAngle) +
                             std::sin(sunZenith) * std::sin(zenithAngle) * std::cos(azimuth - sunAzimuth);
  return relativeFromCosines(std::cos(zenithAngle), cosSunAngle);
}

double SkyModel::luminance(const Vec3& direction) const {
  const double len = length(direction);
  if (!(len > 0)) return 0;
  const Vec3 w = direction / len;
  if (type_ == kUniformEnvironment) return zenithLuminance_;
  if (w.y <= 0) return 0;
  return zenithLuminance_ * relativeFromCosines(w.y, dot(w, sun_));
}

const SkyModel* daylightFactorSky(const Scene& scene) {
  if (scene.lights.size() != 1 || scene.lights[0].kind != LightKind::Sky || !scene.lights[0].sky) return nullptr;
  for (const Surface& surface : scene.surfaces) {
    if (surface.emittedRadiance.maxComponent() > 0) return nullptr;
  }
  return scene.lights[0].sky.get();
}

int skyGridSide(int directions) {
  int m = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(std::max(directions, 1))) - 1e-9)));
  while (static_cast<long>(m) * m < directions) ++m;
  return m;
}

void skyJitter(std::uint64_t index, double& du, double& dv) {
  const std::uint64_t h = mixBits(index * 0x9e3779b97f4a7c15ULL + 0x2545f4914f6cdd1dULL);
  du = (h >> 40) * 0x1p-24;
  dv = ((h >> 16) & 0xffffff) * 0x1p-24;
}

Vec3 skySquareToDirection(const Vec3& n, const Vec3& tangent, const Vec3& bitangent, double u, double v) {
  // The concentric map keeps the cells' shapes compact and neighbours neighbours, so the
  // stratification and the edge test survive; Malley's lift makes the directions cosine-weighted.
  const auto [x, y] = concentricDisk(u, v);
  const double z = std::sqrt(std::fmax(0.0, 1 - x * x - y * y));
  return tangent * x + bitangent * y + n * z;
}

SkyLuminanceTable::SkyLuminanceTable(const SkyModel& sky) : sky_(sky) {
  constexpr int n = kSkyTableIntervals;
  const double half = std::sqrt(0.5);
  zenithward_.resize(n + 2);
  sunward_.resize(n + 2);
  awayward_.resize(n + 2);
  for (int i = 0; i <= n + 1; ++i) {  // one past the end: the interpolation reads i + 1 at x = 1
    const double x = std::min(1.0, static_cast<double>(i) / n), h = half * x;
    zenithward_[i] = sky_.zenithLuminance() * sky_.relativeGradation(x);
    sunward_[i] = sky_.relativeIndicatrix(1 - 2 * h * h);   // sin(χ/2) = h
    awayward_[i] = sky_.relativeIndicatrix(2 * h * h - 1);  // cos(χ/2) = h
  }
}

double SkyLuminanceTable::luminance(const Vec3& w) const {
  if (sky_.isUniformEnvironment()) return sky_.zenithLuminance();
  if (w.y <= 0) return 0;
  auto lerp = [](const std::vector<double>& table, double x) {
    const double at = std::clamp(x, 0.0, 1.0) * kSkyTableIntervals;
    const int i = static_cast<int>(at);
    return table[i] + (table[i + 1] - table[i]) * (at - i);
  };
  const double cosChi = dot(w, sky_.sunDirection()), toHalf = std::sqrt(2.0);
  const double indicatrix = cosChi >= 0 ? lerp(sunward_, std::sqrt(std::max(0.0, (1 - cosChi) / 2)) * toHalf)
                                        : lerp(awayward_, std::sqrt(std::max(0.0, (1 + cosChi) / 2)) * toHalf);
  return lerp(zenithward_, w.y) * indicatrix;
}

namespace {

// skyIlluminance's sample directions about the z axis for one grid side: every cell's first
// sample, then every cell's kSkyEdgeRefinement² sub-samples. Made once per grid side and shared,
// up to kTabulatedCells cells (kTabulatedEdgeCells for the sub-samples); a larger grid, which few
// estimates use, has its directions computed as they are needed instead (2²⁴ directions'
// sub-samples alone would take 6.4 GB).
constexpr std::size_t kTabulatedCells = std::size_t{1} << 20;      // 24 MiB of directions
constexpr std::size_t kTabulatedEdgeCells = std::size_t{1} << 14;  // 16,384 directions' sub-samples: 6 MiB

struct SkyLocalDirections {
  std::vector<Vec3> first, edge;  // empty where not tabulated
};

Vec3 localFirst(int m, std::size_t k) {
  const int i = static_cast<int>(k % m), j = static_cast<int>(k / m);
  double du, dv;
  skyJitter(k, du, dv);
  return skySquareToDirection({0, 0, 1}, {1, 0, 0}, {0, 1, 0}, (i + du) / m, (j + dv) / m);
}

Vec3 localEdge(int m, std::size_t k, int q) {
  constexpr int r = kSkyEdgeRefinement;
  const int i = static_cast<int>(k % m), j = static_cast<int>(k / m);
  double du, dv;
  skyJitter((k + 1) * (r * r) + q + static_cast<std::size_t>(m) * m, du, dv);
  return skySquareToDirection({0, 0, 1}, {1, 0, 0}, {0, 1, 0}, (i + (q % r + du) / r) / m, (j + (q / r + dv) / r) / m);
}

const SkyLocalDirections& skyLocalDirections(int m) {
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<const SkyLocalDirections>> made;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& slot = made[m];
  if (slot) return *slot;
  auto table = std::make_unique<SkyLocalDirections>();
  constexpr int r = kSkyEdgeRefinement;
  const std::size_t cells = static_cast<std::size_t>(m) * m;
  if (cells <= kTabulatedCells) {
    table->first.resize(cells);
    for (std::size_t k = 0; k < cells; ++k) table->first[k] = localFirst(m, k);
  }
  if (cells <= kTabulatedEdgeCells) {
    table->edge.resize(cells * r * r);
    for (std::size_t k = 0; k < cells; ++k)
      for (int q = 0; q < r * r; ++q) table->edge[k * r * r + q] = localEdge(m, k, q);
  }
  slot = std::move(table);
  return *slot;
}

}  // namespace

SkyHemisphere::Sample SkyHemisphere::turned(const Vec3& local) const {
  Sample sample;
  sample.direction = t_ * local.x + b_ * local.y + n_ * local.z;
  sample.luminance = sky_->luminance(sample.direction);
  return sample;
}

void SkyHemisphere::reset(const SkyLuminanceTable& sky, const Vec3& n, int gridSide) {
  sky_ = &sky;
  n_ = n;
  m_ = gridSide;
  orthonormalBasis(n_, t_, b_);
  const SkyLocalDirections& local = skyLocalDirections(m_);
  first_.resize(static_cast<std::size_t>(m_) * m_);
  for (std::size_t k = 0; k < first_.size(); ++k) first_[k] = turned(local.first.empty() ? localFirst(m_, k) : local.first[k]);
  edgeAt_.assign(first_.size(), -1);
  edge_.clear();
  fineAt_.clear();
  fine_.clear();
  unobstructed_ = -1;
}

const SkyHemisphere::Sample* SkyHemisphere::edgeSamples(std::size_t k) {
  constexpr int r = kSkyEdgeRefinement;
  if (edgeAt_[k] < 0) {
    edgeAt_[k] = static_cast<std::int32_t>(edge_.size());
    const SkyLocalDirections& local = skyLocalDirections(m_);
    for (int q = 0; q < r * r; ++q) edge_.push_back(turned(local.edge.empty() ? localEdge(m_, k, q) : local.edge[k * r * r + q]));
    fineAt_.resize(edge_.size(), -1);
  }
  return &edge_[static_cast<std::size_t>(edgeAt_[k])];
}

const SkyHemisphere::Sample* SkyHemisphere::fineSamples(std::size_t k, int q) {
  // Few sub-cells are ever refined (those a point's edges cross), so their directions are made as
  // asked, not tabulated. The stratum that holds the sub-cell's own sample keeps it: the
  // refinement adds samples rather than replacing the one that called for it, which would bias
  // the estimate (a probe that saw the dark below a sill, replaced, would count less dark than it
  // is).
  constexpr int r = kSkyEdgeRefinement, s = kSkyFineRefinement;
  const Sample own = edgeSamples(k)[q];
  const std::size_t at = static_cast<std::size_t>(edgeAt_[k]) + q;
  if (fineAt_[at] < 0) {
    fineAt_[at] = static_cast<std::int32_t>(fine_.size());
    const std::size_t cells = static_cast<std::size_t>(m_) * m_;
    const int i = static_cast<int>(k % m_), j = static_cast<int>(k / m_);
    double ownU, ownV;
    skyJitter((k + 1) * (r * r) + q + cells, ownU, ownV);  // localEdge's
    const int ownStratum = std::min(s - 1, static_cast<int>(ownV * s)) * s + std::min(s - 1, static_cast<int>(ownU * s));
    for (int p = 0; p < s * s; ++p) {
      if (p == ownStratum) {
        fine_.push_back(own);
        continue;
      }
      double du, dv;
      skyJitter(cells * (r * r + 2) + (k * (r * r) + q) * (s * s) + p, du, dv);
      const double u = (i + (q % r + (p % s + du) / s) / r) / m_, v = (j + (q / r + (p / s + dv) / s) / r) / m_;
      fine_.push_back(turned(skySquareToDirection({0, 0, 1}, {1, 0, 0}, {0, 1, 0}, u, v)));
    }
  }
  return &fine_[static_cast<std::size_t>(fineAt_[at])];
}

double SkyHemisphere::unobstructedIlluminance() {
  if (unobstructed_ < 0)
    unobstructed_ = skyIlluminance(*this, [](std::span<const Vec3>, std::span<bool> out) { std::fill(out.begin(), out.end(), true); }, SkyEdges::Cells);
  return unobstructed_;
}

SkyHemisphere& skyHemisphere(const SkyModel& sky, const Vec3& n, int gridSide) {
  // A few normals per thread: a room's walls, or the two sides a light edge compares. Replaced
  // hemispheres are reset in place, keeping their memory. A grid above kKeptCells (2 MiB a
  // hemisphere) has one hemisphere per thread, so that a large direction count costs one.
  constexpr std::size_t kKept = 8, kKeptCells = std::size_t{1} << 16;
  thread_local std::unique_ptr<SkyLuminanceTable> table;
  thread_local std::vector<std::unique_ptr<SkyHemisphere>> kept;
  thread_local std::unique_ptr<SkyHemisphere> large;
  thread_local std::size_t next = 0;
  constexpr double kGrid = 0x1p30;
  const Vec3 rounded = normalize(Vec3{std::round(n.x * kGrid), std::round(n.y * kGrid), std::round(n.z * kGrid)});
  if (!table || !(table->sky() == sky)) {
    table = std::make_unique<SkyLuminanceTable>(sky);
    kept.clear();  // they point into the old table
    large.reset();
    next = 0;
  }
  SkyHemisphere* h = nullptr;
  if (static_cast<std::size_t>(gridSide) * gridSide > kKeptCells) {
    if (!large) large = std::make_unique<SkyHemisphere>();
    if (large->matches(sky, rounded, gridSide)) return *large;
    h = large.get();
  } else {
    for (auto& k : kept)
      if (k->matches(sky, rounded, gridSide)) return *k;
    if (kept.size() < kKept) {
      kept.push_back(std::make_unique<SkyHemisphere>());
      h = kept.back().get();
    } else {
      h = kept[next].get();
      next = (next + 1) % kKept;
    }
  }
  h->reset(*table, rounded, gridSide);
  return *h;
}

}  // namespace lambert
