#include "lambert/design/annual_daylight.h"

#include <Eigen/Dense>

#include <cmath>
#include <cstring>
#include <optional>

#include "lambert/core/cache_file.h"
#include "lambert/core/parallel.h"
#include "lambert/core/timer.h"
#include "lambert/core/warning.h"
#include "lambert/light/perez_sky.h"
#include "lambert/light/sun.h"
#include "lambert/scene/scene_hash.h"
#include "lambert/link_sources_digest.h"
#include "lambert/version.h"

namespace lambert {
namespace {

// The coefficient file: the cache header (core/cache_file.h), then a payload of seven u64 counts
// (sensors, sky component patches, sky patches, basis suns, suns, and the two arrays of ints'
// lengths are implied by them) followed by the arrays as they are in memory:
//   float skyDirect[sensors × fine], skyIndirect[sensors × coarse], sunIndirect[sensors × basis],
//   sunDirect[suns × sensors], sunReflected[suns × sensors], basisSunWeight[4 × suns];
//   int32 basisSunPatch[basis], basisSunOf[4 × suns].
constexpr cachefile::Format kFormat{{'L', 'M', 'B', 'R', 'T', 'D', 'C', '\0'}, 2, "daylight coefficient file"};

std::uint64_t coefficientKey(const Scene& scene, std::span<const CalculationPoint> sensors, std::span<const Vec3> suns,
                             const DaylightCoefficientOptions& options, const RadiosityOptions& engine) {
  cachefile::KeyHasher h;
  h.text("lambert daylight coefficients");
  h.u32(kFormat.version);
  h.text(LAMBERT_VERSION_STRING);
  h.text(LAMBERT_LINK_SOURCES_DIGEST);  // the sources that compute them (CMakeLists.txt)
  hashScene(h, scene);
  h.u64(sensors.size());
  for (const CalculationPoint& p : sensors) h.vec3(p.position), h.vec3(p.normal);
  h.u64(suns.size());
  for (const Vec3& s : suns) h.vec3(s);
  h.vec3(options.north);
  h.i64(options.skySubdivisions);
  h.i64(options.directSkySubdivisions);
  h.i64(options.sunSubdivisions);
  h.i64(options.skyDirections);
  h.i64(options.indirectRays);
  h.i64(options.sunReflectionRays);
  h.u64(options.seed);
  h.i64(static_cast<std::int64_t>(engine.meshing));
  h.f64(engine.tolerance);
  h.f64(engine.hierarchical.links.linkError);
  h.f64(engine.hierarchical.links.minElementArea);
  h.i64(engine.hierarchical.refinePasses);
  h.i64(engine.directLight.samplesPerPatch);
  return h.digest();
}

struct Block {
  void* data;
  std::size_t bytes;
};

std::vector<Block> blocks(DaylightCoefficients& c) {
  auto of = [](auto& v) { return Block{v.data(), v.size() * sizeof(v[0])}; };
  return {of(c.skyDirect),    of(c.skyIndirect),    of(c.sunIndirect), of(c.sunDirect),
          of(c.sunReflected), of(c.basisSunWeight), of(c.basisSunPatch), of(c.basisSunOf)};
}

Status writeCoefficients(const std::string& path, std::uint64_t key, DaylightCoefficients& c) {
  const std::uint64_t counts[5] = {c.sensors, static_cast<std::uint64_t>(c.directSky.count()), static_cast<std::uint64_t>(c.sky.count()),
                                   c.basisSunPatch.size(), c.basisSunOf.size() / 4};
  std::vector<unsigned char> payload(sizeof counts);
  std::memcpy(payload.data(), counts, sizeof counts);
  for (const Block& b : blocks(c)) {
    const std::size_t at = payload.size();
    payload.resize(at + b.bytes);
    if (b.bytes) std::memcpy(payload.data() + at, b.data, b.bytes);
  }
  return cachefile::writeFile(path, kFormat, key, payload.size(), payload);
}

// The coefficients the file holds, for options (the patches) and the counts expected.
Result<DaylightCoefficients> readCoefficients(const std::string& path, std::uint64_t key, const DaylightCoefficientOptions& options,
                                              std::size_t sensors, std::size_t suns) {
  Result<cachefile::Reader> reader = cachefile::Reader::open(path, kFormat, key);
  if (!reader) return reader.error();
  DaylightCoefficients c;
  c.sky = SkyPatches::reinhart(options.skySubdivisions, options.north).value();
  c.directSky = SkyPatches::reinhart(options.directSkySubdivisions, options.north).value();
  c.sunPatches = SkyPatches::reinhart(options.sunSubdivisions, options.north).value();
  c.sensors = sensors;
  const std::size_t fine = static_cast<std::size_t>(c.directSky.count()), coarse = static_cast<std::size_t>(c.sky.count());
  std::uint64_t counts[5];
  const std::size_t head = sizeof counts;
  if (reader->count() < head) return Error{path + ": too short for a daylight coefficient file"};
  // The basis suns' number is in the file; read the counts first through the whole payload.
  const std::uint64_t bytes = reader->count();
  if (bytes > (std::uint64_t{1} << 40)) return Error{path + ": an implausible payload of " + std::to_string(bytes) + " bytes"};
  if (Status sized = reader->checkSize(static_cast<std::size_t>(bytes), std::to_string(bytes) + " payload bytes"); !sized) return sized.error();
  std::vector<unsigned char> payload(static_cast<std::size_t>(bytes));
  if (Status read = reader->readPayload(payload.data()); !read) return read.error();
  std::memcpy(counts, payload.data(), head);
  if (counts[0] != sensors || counts[1] != fine || counts[2] != coarse || counts[4] != suns)
    return Error{path + ": its counts do not match the sensors, patches and suns asked for"};
  const std::size_t basis = static_cast<std::size_t>(counts[3]);
  if (basis > 4 * suns) return Error{path + ": more basis suns than the suns' interpolations use"};
  c.skyDirect.resize(sensors * fine);
  c.skyIndirect.resize(sensors * coarse);
  c.sunIndirect.resize(sensors * basis);
  c.sunDirect.resize(suns * sensors);
  c.sunReflected.resize(suns * sensors);
  c.basisSunWeight.resize(4 * suns);
  c.basisSunPatch.resize(basis);
  c.basisSunOf.resize(4 * suns);
  std::size_t at = head;
  for (const Block& b : blocks(c)) {
    if (payload.size() - at < b.bytes) return Error{path + ": shorter than its counts say"};
    if (b.bytes) std::memcpy(b.data, payload.data() + at, b.bytes);
    at += b.bytes;
  }
  if (at != payload.size()) return Error{path + ": longer than its counts say"};
  for (int k : c.basisSunOf)
    if (k < -1 || k >= static_cast<int>(basis)) return Error{path + ": a sun's basis sun is out of range"};
  for (int p : c.basisSunPatch)
    if (p < 0 || p >= c.sunPatches.count()) return Error{path + ": a basis sun's patch is out of range"};
  return c;
}

}  // namespace

Result<AnnualDaylight> annualDaylight(const Scene& scene, std::span<const CalculationPoint> sensors, const WeatherData& weather,
                                      const AnnualDaylightOptions& options, const RadiosityOptions& engineOptions) {
  const DaylightCoefficientOptions& dco = options.coefficients;
  const std::size_t hours = weather.hours.size(), n = sensors.size();
  // Each hour's sky and sun.
  std::vector<PerezHourSky> skies(hours);
  std::vector<int> sunOfHour(hours, -1);
  std::vector<Vec3> suns;
  std::vector<std::string> failed(hours);
  parallelFor(0, hours, [&](std::size_t h) {
    Result<PerezHourSky> sky = perezSkyForHour(weather, weather.hours[h], dco.north);
    if (sky)
      skies[h] = std::move(*sky);
    else
      failed[h] = weather.path + ":" + std::to_string(weather.hours[h].line) + ": " + sky.error().message;
  }, 64);
  for (std::size_t h = 0; h < hours; ++h) {
    if (!failed[h].empty()) return Error{failed[h]};
    if (skies[h].sunInSky && skies[h].sunIlluminanceLux > 0) {
      const Vec3 toSun = skyDirection(skies[h].sun.azimuthDegrees, std::fmax(skies[h].sun.elevationDegrees(), 0.0), dco.north);
      if (toSun.y > 0) {
        sunOfHour[h] = static_cast<int>(suns.size());
        suns.push_back(toSun);
      }
    }
  }

  AnnualDaylight out;
  const Timer coefficientTimer;
  const std::uint64_t key = coefficientKey(scene, sensors, suns, dco, engineOptions);
  const std::string path = options.cacheDirectory.empty() ? std::string() : cachefile::keyedPath(options.cacheDirectory, "daylight-", key, ".ldc");
  std::optional<DaylightCoefficients> dc;
  if (!path.empty() && !cachefile::isMissing(path)) {
    Result<DaylightCoefficients> read = readCoefficients(path, key, dco, n, suns.size());
    if (read) {
      dc = std::move(*read);
      out.coefficientsFromCache = true;
    } else {
      warning(read.error().message + "; computing the daylight coefficients again");
    }
  }
  if (!dc) {
    Result<DaylightCoefficients> computed = computeDaylightCoefficients(scene, sensors, suns, dco, engineOptions);
    if (!computed) return computed.error();
    dc = std::move(*computed);
    out.raysCast = dc->raysCast;
    if (!path.empty())
      if (Status written = writeCoefficients(path, key, *dc); !written) warning(written.error().message);
  }
  out.coefficientSeconds = coefficientTimer.seconds();

  const Timer hourlyTimer;
  const std::size_t fine = static_cast<std::size_t>(dc->directSky.count()), coarse = static_cast<std::size_t>(dc->sky.count());
  const std::size_t basis = dc->basisSunPatch.size();
  out.skyPatches = coarse, out.directSkyPatches = fine, out.basisSuns = basis;
  // The patches' mean luminance per hour (columns), 0 for hours without a sky.
  Eigen::MatrixXf fineLuminance = Eigen::MatrixXf::Zero(static_cast<Eigen::Index>(fine), static_cast<Eigen::Index>(hours));
  Eigen::MatrixXf coarseLuminance = Eigen::MatrixXf::Zero(static_cast<Eigen::Index>(coarse), static_cast<Eigen::Index>(hours));
  parallelFor(0, hours, [&](std::size_t h) {
    if (!skies[h].sky) return;
    for (std::size_t q = 0; q < fine; ++q)
      fineLuminance(static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(h)) = static_cast<float>(dc->directSky.meanLuminance(*skies[h].sky, static_cast<int>(q)));
    for (std::size_t p = 0; p < coarse; ++p)
      coarseLuminance(static_cast<Eigen::Index>(p), static_cast<Eigen::Index>(h)) = static_cast<float>(dc->sky.meanLuminance(*skies[h].sky, static_cast<int>(p)));
  }, 8);
  using RowMajor = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Map<const RowMajor> direct(dc->skyDirect.data(), static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(fine));
  const Eigen::Map<const RowMajor> indirect(dc->skyIndirect.data(), static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(coarse));
  // hours × sensors, hour-major: the transpose of (sensors × patches)(patches × hours).
  RowMajor sky = (direct * fineLuminance + indirect * coarseLuminance).transpose();

  AnnualIlluminance& a = out.illuminance;
  a.sensors = n;
  a.hours.resize(hours);
  a.totalLux.assign(sky.data(), sky.data() + hours * n);
  out.skyLux = a.totalLux;
  a.directSunLux.assign(hours * n, 0.0f);
  for (std::size_t h = 0; h < hours; ++h) {
    a.hours[h] = {weather.hours[h].month, weather.hours[h].day, weather.hours[h].hour};
    if (skies[h].sky) ++out.daylightHours;
    const int k = sunOfHour[h];
    if (k < 0) continue;
    if (!skies[h].sky) ++out.daylightHours;
    ++out.sunHours;
    const double lux = skies[h].sunIlluminanceLux;
    for (std::size_t s = 0; s < n; ++s) {
      const double sunDirect = lux * dc->sunDirect[static_cast<std::size_t>(k) * n + s];
      a.directSunLux[h * n + s] = static_cast<float>(sunDirect);
      a.totalLux[h * n + s] += static_cast<float>(sunDirect + lux * dc->sunInterreflected(static_cast<std::size_t>(k), s));
    }
  }
  out.hourlySeconds = hourlyTimer.seconds();
  return out;
}

}  // namespace lambert
