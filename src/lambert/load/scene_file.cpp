#include "lambert/load/scene_file.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "lambert/core/atomic_file.h"
#include "lambert/core/text.h"
#include "lambert/core/transform.h"
#include "lambert/core/warning.h"
#include "lambert/light/lights.h"
#include "lambert/light/sky.h"
#include "lambert/light/sun.h"
#include "lambert/scene/builtin.h"
#include "lambert/load/gltf.h"
#include "lambert/load/mgf.h"
#include "lambert/load/obj.h"
#include "lambert/load/photometry_file.h"
#include "lambert/load/ply.h"
#include "lambert/scene/texture.h"

namespace lambert {
namespace {

using Json = nlohmann::json;
using OrderedJson = nlohmann::ordered_json;

constexpr int kFormatVersion = 1;

// Thrown inside this file only, caught by parseSceneFile: the JSON path and what is wrong.
struct FieldError {
  std::string pointer;
  std::string message;
};

std::string typeName(const Json& value) {
  if (value.is_number()) return "a number";
  if (value.is_string()) return "a string";
  if (value.is_boolean()) return "a boolean";
  if (value.is_array()) return "an array";
  if (value.is_object()) return "an object";
  return "null";
}

std::string formatNumber(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

// One JSON object read field by field: every field it has must be asked for by finish().
class ObjectReader {
 public:
  ObjectReader(const Json& object, std::string pointer) : object_(object), pointer_(std::move(pointer)) {
    if (!object_.is_object()) throw FieldError{pointer_.empty() ? "/" : pointer_, "expected an object, found " + typeName(object_)};
  }

  bool has(const std::string& key) const { return object_.contains(key); }
  std::string pointerOf(const std::string& key) const { return pointer_ + "/" + key; }

  const Json* find(const std::string& key) {
    known_.insert(key);
    auto it = object_.find(key);
    return it == object_.end() ? nullptr : &*it;
  }
  const Json& require(const std::string& key) {
    const Json* value = find(key);
    if (!value) throw FieldError{pointer_.empty() ? "/" : pointer_, "missing required field \"" + key + "\""};
    return *value;
  }

  std::string string(const std::string& key, const std::string& fallback) {
    const Json* value = find(key);
    if (!value) return fallback;
    if (!value->is_string()) throw FieldError{pointerOf(key), "expected a string, found " + typeName(*value)};
    return value->get<std::string>();
  }

  // A finite number in [low, high] (open at either end when the flag says so).
  double number(const std::string& key, double fallback, double low, double high, bool lowOpen = false, bool highOpen = false) {
    const Json* value = find(key);
    return value ? checkedNumber(*value, pointerOf(key), low, high, lowOpen, highOpen) : fallback;
  }

  static double checkedNumber(const Json& value, const std::string& pointer, double low, double high, bool lowOpen,
                              bool highOpen) {
    if (!value.is_number()) throw FieldError{pointer, "expected a number, found " + typeName(value)};
    const double v = value.get<double>();
    const bool below = lowOpen ? !(v > low) : !(v >= low);
    const bool above = highOpen ? !(v < high) : !(v <= high);
    if (!std::isfinite(v) || below || above)
      throw FieldError{pointer, formatNumber(v) + " is out of range: allowed " + (lowOpen ? "(" : "[") + formatNumber(low) + ", " +
                                    formatNumber(high) + (highOpen ? ")" : "]")};
    return v;
  }

  // Three finite numbers, each in [low, high].
  static Vec3 checkedTriple(const Json& value, const std::string& pointer, double low, double high, bool highOpen = false) {
    if (!value.is_array() || value.size() != 3)
      throw FieldError{pointer, "expected an array of 3 numbers, found " + (value.is_array() ? "an array of " + std::to_string(value.size()) : typeName(value))};
    auto component = [&](int k) { return checkedNumber(value[k], pointer + "/" + std::to_string(k), low, high, false, highOpen); };
    return {component(0), component(1), component(2)};
  }
  Vec3 vector(const std::string& key, Vec3 fallback, double low = -1e30, double high = 1e30) {
    const Json* value = find(key);
    return value ? checkedTriple(*value, pointerOf(key), low, high) : fallback;
  }
  Rgb colour(const std::string& key, Rgb fallback, double high, bool highOpen) {
    const Json* value = find(key);
    if (!value) return fallback;
    Vec3 v = checkedTriple(*value, pointerOf(key), 0, high, highOpen);
    return {v.x, v.y, v.z};
  }

  bool boolean(const std::string& key, bool fallback) {
    const Json* value = find(key);
    if (!value) return fallback;
    if (!value->is_boolean()) throw FieldError{pointerOf(key), "expected true or false, found " + typeName(*value)};
    return value->get<bool>();
  }

  const Json& array(const std::string& key) {
    static const Json empty = Json::array();
    const Json* value = find(key);
    if (!value) return empty;
    if (!value->is_array()) throw FieldError{pointerOf(key), "expected an array, found " + typeName(*value)};
    return *value;
  }

  // Every field must have been read: an unknown one is a typo or a feature lambert lacks.
  void finish(const std::string& allowed) const {
    for (auto it = object_.begin(); it != object_.end(); ++it)
      if (!known_.count(it.key())) throw FieldError{pointerOf(it.key()), "unknown field (allowed here: " + allowed + ")"};
  }

 private:
  const Json& object_;
  std::string pointer_;
  std::set<std::string> known_;
};

double metresPerUnitOf(const std::string& unit, const std::string& pointer) {
  static const std::map<std::string, double> units = {{"m", 1}, {"cm", 0.01}, {"mm", 0.001}, {"in", 0.0254}, {"ft", 0.3048}};
  auto it = units.find(unit);
  if (it == units.end()) throw FieldError{pointer, "unknown unit \"" + unit + "\" (allowed: m, cm, mm, in, ft)"};
  return it->second;
}

// A surface polygon must be convex (seen along its mean normal) with a non-zero area, as the
// mesher's triangle fan assumes. It need not be exactly planar: the fan splits it (the published
// Cornell box's red wall is 1.6 mm off plane).
void checkPolygon(const std::vector<Vec3>& v, const std::string& pointer) {
  if (v.size() < 3) throw FieldError{pointer, "a polygon needs at least 3 vertices, found " + std::to_string(v.size())};
  const double size = polygonExtent(v);
  const Vec3 areaVector = polygonAreaVector(v);
  if (!(length(areaVector) > 1e-12 * size * size)) throw FieldError{pointer, "the polygon has no area (its vertices are collinear or repeated)"};
  if (std::size_t corner = firstConcaveCorner(v, normalize(areaVector)); corner < v.size())
    throw FieldError{pointer + "/" + std::to_string(corner), "the polygon is not convex at this vertex"};
}

// A scene's horizontal north: "north" if given (its y part dropped), else −z (east is then +x).
Vec3 readNorth(ObjectReader& r) {
  const Vec3 north = r.vector("north", {0, 0, -1});
  if (!(std::fabs(north.x) + std::fabs(north.z) > 0))
    throw FieldError{r.pointerOf("north"), "north must have a horizontal part (lambert is y-up): e.g. [0, 0, -1]"};
  return normalize(Vec3{north.x, 0, north.z});
}

// The sun's position from a place and a local time (light/sun.h): latitude, longitude, date,
// time, timeZone (hours east of UTC) and refraction (default true).
SunPosition readSunFromPlace(ObjectReader& r) {
  const double latitude = r.number("latitude", 0, -90, 90);
  const double longitude = r.number("longitude", 0, -180, 180);
  r.require("latitude"), r.require("longitude");
  const std::string date = r.string("date", ""), clock = r.string("time", "");
  if (date.empty()) throw FieldError{r.pointerOf("date"), "missing: the date as \"YYYY-MM-DD\""};
  if (clock.empty()) throw FieldError{r.pointerOf("time"), "missing: the local time as \"HH:MM\""};
  Result<LocalTime> time = parseLocalTime(date, clock);
  if (!time) throw FieldError{r.pointerOf("date"), time.error().message};
  time->timeZoneHours = r.number("timeZone", 0, -14, 14);
  Refraction refraction;
  refraction.apply = r.boolean("refraction", true);
  return sunPosition(latitude, longitude, *time, refraction);
}

// The sun's azimuth and elevation in degrees: from "sun" {latitude, ...} or sunAzimuth and
// sunElevation, or none (an empty optional) when neither is given.
std::optional<SunPosition> readSkySun(ObjectReader& r) {
  const bool place = r.has("sun"), angles = r.has("sunAzimuth") || r.has("sunElevation");
  if (place && angles) throw FieldError{r.pointerOf("sun"), "give the sun either as \"sun\" (a place and time) or as sunAzimuth and sunElevation, not both"};
  if (place) {
    ObjectReader sun(r.require("sun"), r.pointerOf("sun"));
    SunPosition position = readSunFromPlace(sun);
    sun.finish("latitude, longitude, date, time, timeZone, refraction");
    return position;
  }
  if (!angles) return std::nullopt;
  SunPosition position;
  position.azimuthDegrees = r.number("sunAzimuth", 0, -360, 360);
  position.zenithDegrees = 90 - r.number("sunElevation", 0, -90, 90);
  r.require("sunAzimuth"), r.require("sunElevation");
  return position;
}

// {"type": "sky", "cie": 1..15 | "overcast" (or "perez": {a, b, c, d, e}), "zenithLuminance": cd/m² | "horizontalIlluminance":
// lux, the sun, "north", "directions"}, or {"type": "sky", "radiance": [r, g, b] W/(m²·sr),
// "directions"}, a uniform environment (docs/scene-format.md).
Light readSkyLight(ObjectReader& r, Light light) {
  light.kind = LightKind::Sky;
  if (r.has("radiance")) {
    for (const char* daylight : {"cie", "zenithLuminance", "horizontalIlluminance", "sun", "sunAzimuth", "sunElevation", "north"})
      if (r.has(daylight))
        throw FieldError{r.pointerOf(daylight), std::string("a uniform environment (\"radiance\") is the same from every direction: ") +
                                                    daylight + " is for the CIE daylight skies"};
    Result<SkyModel> environment = SkyModel::uniformEnvironment(r.colour("radiance", {}, 1e12, false));
    if (!environment) throw FieldError{r.pointerOf("radiance"), environment.error().message};
    light.sky = std::make_shared<const SkyModel>(*environment);
    light.skyDirections = static_cast<int>(r.number("directions", kDefaultSkyDirections, 1, 1 << 24));
    r.finish("name, type, radiance, directions");
    return light;
  }
  if (r.has("perez") && r.has("cie")) throw FieldError{r.pointerOf("cie"), "give one of cie and perez, not both"};
  const Json& cie = r.has("perez") ? r.require("perez") : r.require("cie");
  const Vec3 north = readNorth(r);
  const std::optional<SunPosition> sun = readSkySun(r);
  const bool byZenith = r.has("zenithLuminance"), byHorizontal = r.has("horizontalIlluminance");
  if (byZenith == byHorizontal)
    throw FieldError{r.pointerOf(byZenith ? "horizontalIlluminance" : "zenithLuminance"),
                     "give exactly one of zenithLuminance (cd/m²) and horizontalIlluminance (lux)"};
  const double scale = byZenith ? r.number("zenithLuminance", 0, 0, 1e12) : r.number("horizontalIlluminance", 0, 0, 1e12, true);
  SkyModel sky = SkyModel::traditionalOvercast(1, north);
  if (r.has("perez")) {
    // {"a", "b", "c", "d", "e"}: Perez et al. 1993's coefficients of one hour (light/perez_sky.h
    // makes them from a weather file), optionally the clearness, brightness and bin they came from.
    if (!cie.is_object()) throw FieldError{r.pointerOf("perez"), "expected an object of the coefficients a, b, c, d and e"};
    PerezCoefficients p;
    double* fields[] = {&p.a, &p.b, &p.c, &p.d, &p.e};
    const char* names[] = {"a", "b", "c", "d", "e"};
    for (int k = 0; k < 5; ++k) {
      if (!cie.contains(names[k]) || !cie[names[k]].is_number() || !std::isfinite(cie[names[k]].get<double>()))
        throw FieldError{r.pointerOf("perez") + "/" + names[k], "expected a finite number"};
      *fields[k] = cie[names[k]].get<double>();
    }
    if (cie.contains("clearness") && cie["clearness"].is_number()) p.clearness = cie["clearness"].get<double>();
    if (cie.contains("brightness") && cie["brightness"].is_number()) p.brightness = cie["brightness"].get<double>();
    if (cie.contains("bin") && cie["bin"].is_number_integer()) p.bin = cie["bin"].get<int>();
    if (!sun) throw FieldError{r.pointerOf("perez"), "a Perez sky depends on the sun: give \"sun\" or sunAzimuth and sunElevation"};
    p.sunZenithRadians = (90 - sun->elevationDegrees()) * kPi / 180;
    if (cie.contains("sunZenithRadians") && cie["sunZenithRadians"].is_number()) p.sunZenithRadians = cie["sunZenithRadians"].get<double>();
    Result<SkyModel> made = SkyModel::perez(p, sun->azimuthDegrees, sun->elevationDegrees(), byZenith ? scale : 1, north);
    if (!made) throw FieldError{r.pointerOf("perez"), made.error().message};
    sky = *made;
  } else if (cie.is_string() && cie.get<std::string>() == "overcast") {
    if (sun) throw FieldError{r.pointerOf("cie"), "the traditional overcast sky does not depend on the sun: remove the sun, or use a CIE type 1–15"};
    sky = SkyModel::traditionalOvercast(byZenith ? scale : 1, north);
  } else {
    if (!cie.is_number_integer() || cie.get<long long>() < 1 || cie.get<long long>() > 15)
      throw FieldError{r.pointerOf("cie"), "expected a CIE standard sky type 1 to 15 or \"overcast\""};
    const int type = static_cast<int>(cie.get<long long>());
    const CieSkyParameters p = cieStandardSkyParameters(type);
    if (!sun && (p.c != 0 || p.e != 0))
      throw FieldError{r.pointerOf("cie"), "CIE sky type " + std::to_string(type) +
                                               " depends on the sun: give \"sun\" (latitude, longitude, date, time, timeZone) or sunAzimuth and sunElevation"};
    const SunPosition at = sun.value_or(SunPosition{});
    Result<SkyModel> made = SkyModel::cieStandard(type, at.azimuthDegrees, at.elevationDegrees(), byZenith ? scale : 1, north);
    if (!made) throw FieldError{r.pointerOf("cie"), made.error().message};
    sky = *made;
  }
  if (byHorizontal) sky = sky.withHorizontalIlluminance(scale);
  light.sky = std::make_shared<const SkyModel>(sky);
  light.skyDirections = static_cast<int>(r.number("directions", kDefaultSkyDirections, 1, 1 << 24));
  r.finish("name, type, cie, perez, zenithLuminance, horizontalIlluminance, sun, sunAzimuth, sunElevation, north, directions");
  return light;
}

// {"type": "sun", a place and time or azimuth and elevation, "illuminance": lux on a surface
// facing the sun (direct normal illuminance), "north"}: a directional light.
Light readSunLight(ObjectReader& r, const std::string& pointer, Light light) {
  light.kind = LightKind::Directional;
  const Vec3 north = readNorth(r);
  SunPosition sun;
  if (r.has("azimuth") || r.has("elevation")) {
    sun.azimuthDegrees = r.number("azimuth", 0, -360, 360);
    sun.zenithDegrees = 90 - r.number("elevation", 0, -90, 90);
    r.require("azimuth"), r.require("elevation");
  } else {
    sun = readSunFromPlace(r);
  }
  const double lux = r.number("illuminance", 0, 0, 1e12);
  r.require("illuminance");
  light.direction = -skyDirection(sun.azimuthDegrees, sun.elevationDegrees(), north);
  light.irradiance = Rgb::gray(sun.elevationDegrees() > 0 ? lux / kLumensPerWatt : 0);
  if (sun.elevationDegrees() <= 0)
    warning("scene light " + pointer + ": the sun is below the horizon (elevation " + formatNumber(sun.elevationDegrees()) +
            "°): it gives no direct light");
  r.finish("name, type, latitude, longitude, date, time, timeZone, refraction, azimuth, elevation, illuminance, north");
  return light;
}

// Each photometric file read once per scene, however many luminaires share it.
using PhotometryCache = std::map<std::string, std::shared_ptr<const Photometry>>;

// "maintenance": the maintenance factor as one number, or {"factor": MF}, or its CIE 97 parts
// {"lampLumen", "lampSurvival", "luminaire", "roomSurface"} (each in (0, 1], 1 where not given).
Maintenance readMaintenance(const Json& value, const std::string& pointer) {
  Maintenance m;
  if (value.is_number()) {
    m.lampLumen = value.get<double>();
    if (!(m.lampLumen > 0 && m.lampLumen <= 1))
      throw FieldError{pointer, "a maintenance factor lies in (0, 1]; e.g. 0.8 (CIE 97: 0.8 for a clean room, LED, three-year cleaning)"};
    return m;
  }
  ObjectReader r(value, pointer);
  if (r.has("factor")) {
    m.lampLumen = r.number("factor", 1, 0, 1, true);
    r.finish("factor");
    return m;
  }
  m.lampLumen = r.number("lampLumen", 1, 0, 1, true);
  m.lampSurvival = r.number("lampSurvival", 1, 0, 1, true);
  m.luminaire = r.number("luminaire", 1, 0, 1, true);
  m.roomSurface = r.number("roomSurface", 1, 0, 1, true);
  r.finish("factor, lampLumen, lampSurvival, luminaire, roomSurface");
  return m;
}

Light readLight(const Json& value, const std::string& pointer, const std::string& scenePath, PhotometryCache& photometries,
                const Maintenance& sceneMaintenance) {
  ObjectReader r(value, pointer);
  Light light;
  light.name = r.string("name", "light " + pointer.substr(pointer.rfind('/') + 1));
  const std::string type = r.string("type", "");
  const double maxVector = 1e30;
  // An electric light's maintenance factor: its own, else the scene's (folded in at the end).
  auto readOwnMaintenance = [&] {
    light.maintenance = r.has("maintenance") ? readMaintenance(r.require("maintenance"), r.pointerOf("maintenance")) : sceneMaintenance;
  };
  auto direction = [&] {
    Vec3 d = ObjectReader::checkedTriple(r.require("direction"), r.pointerOf("direction"), -maxVector, maxVector);
    if (!(length(d) > 0)) throw FieldError{r.pointerOf("direction"), "the direction must not be zero"};
    return normalize(d);
  };
  if (type == "point" || type == "spot") {
    light.kind = type == "point" ? LightKind::Point : LightKind::Spot;
    light.position = ObjectReader::checkedTriple(r.require("position"), r.pointerOf("position"), -maxVector, maxVector);
    Vec3 i = ObjectReader::checkedTriple(r.require("intensity"), r.pointerOf("intensity"), 0, maxVector);
    light.intensity = {i.x, i.y, i.z};
    if (light.kind == LightKind::Spot) {
      light.direction = direction();
      light.coneAngleDegrees = r.number("coneAngleDegrees", 30, 0, 90, true, false);
      light.falloffDegrees = r.number("falloffDegrees", std::fmin(5, light.coneAngleDegrees), 0, light.coneAngleDegrees);
      light.angularVelocity = r.vector("angularVelocity", {});
      readOwnMaintenance();
      r.finish("name, type, position, direction, intensity, coneAngleDegrees, falloffDegrees, angularVelocity, maintenance");
    } else {
      readOwnMaintenance();
      r.finish("name, type, position, intensity, maintenance");
    }
  } else if (type == "directional") {
    light.kind = LightKind::Directional;
    light.direction = direction();
    Vec3 e = ObjectReader::checkedTriple(r.require("irradiance"), r.pointerOf("irradiance"), 0, maxVector);
    light.irradiance = {e.x, e.y, e.z};
    light.angularVelocity = r.vector("angularVelocity", {});
    r.finish("name, type, direction, irradiance, angularVelocity");
  } else if (type == "sky") {
    return readSkyLight(r, light);
  } else if (type == "sun") {
    return readSunLight(r, pointer, light);
  } else if (type == "ies") {
    // A measured luminaire (docs/scene-format.md, docs/photometry.md "Luminaires").
    light.kind = LightKind::Luminaire;
    const Json& fileValue = r.require("file");
    if (!fileValue.is_string() || fileValue.get<std::string>().empty())
      throw FieldError{r.pointerOf("file"), "expected the path of an IES (.ies) or EULUMDAT (.ldt) file, found " + typeName(fileValue)};
    const std::string file = (std::filesystem::path(scenePath).parent_path() / fileValue.get<std::string>()).string();
    auto cached = photometries.find(file);
    if (cached == photometries.end()) {
      Result<Photometry> read = readPhotometry(file);
      if (!read) throw FieldError{r.pointerOf("file"), read.error().message};
      cached = photometries.emplace(file, std::make_shared<const Photometry>(std::move(*read))).first;
    }
    light.photometry = cached->second;
    light.position = ObjectReader::checkedTriple(r.require("position"), r.pointerOf("position"), -maxVector, maxVector);
    // Aimed either by a vector and a spin about it ("aim", "rotationDegrees") or by the LM-72
    // angles ("orient", "tilt", "roll", "spin"; docs/photometry.md "Aiming"), never both: a file
    // with both would leave one of them unread.
    const char* angleKeys[] = {"orient", "tilt", "roll", "spin"};
    const char* givenAngle = nullptr;
    for (const char* key : angleKeys)
      if (!givenAngle && r.has(key)) givenAngle = key;
    if (givenAngle && (r.has("aim") || r.has("rotationDegrees")))
      throw FieldError{r.pointerOf(givenAngle), std::string("aim a luminaire either by \"aim\" (with \"rotationDegrees\") or by the "
                                                            "angles \"orient\", \"tilt\", \"roll\", \"spin\", not both (this light has \"") +
                                                    (r.has("aim") ? "aim" : "rotationDegrees") + "\" too)"};
    if (givenAngle) {
      LuminaireAiming aiming;
      aiming.orientDegrees = r.number("orient", 0, -360, 360);
      aiming.tiltDegrees = r.number("tilt", 0, -360, 360);
      aiming.rollDegrees = r.number("roll", 0, -360, 360);
      aiming.spinDegrees = r.number("spin", 0, -360, 360);
      aimLuminaire(light, aiming);
    } else {
      light.direction = r.vector("aim", {0, -1, 0});
      if (!(length(light.direction) > 0)) throw FieldError{r.pointerOf("aim"), "the aim must not be zero"};
      light.direction = normalize(light.direction);
      light.rotationDegrees = r.number("rotationDegrees", 0, -360, 360);
    }
    const double multiplier = r.number("multiplier", 1, 0, 1e6);
    const Rgb colour = r.colour("color", {1, 1, 1}, 1e6, false);
    // White (1, 1, 1) has luminance 1 (Rec. 709 weights sum to 1): cd/683 W/sr per channel.
    light.intensity = colour * multiplier;
    const std::string model = r.string("model", "point");
    if (model == "area") {
      light.luminaireModel = LuminaireModel::Opening;
      const double perSide = r.number("openingSamples", 4, 1, 16);
      light.openingSamplesPerSide = static_cast<int>(perSide);
      if (perSide != light.openingSamplesPerSide)
        throw FieldError{r.pointerOf("openingSamples"), "expected a whole number of sources per side"};
    } else if (model != "point") {
      throw FieldError{r.pointerOf("model"), "unknown luminaire model \"" + model + "\" (allowed: point, the far field; area, the luminous opening)"};
    } else if (r.has("openingSamples")) {
      throw FieldError{r.pointerOf("openingSamples"), "applies to \"model\": \"area\" only"};
    }
    readOwnMaintenance();
    r.finish("name, type, file, position, aim, rotationDegrees, orient, tilt, roll, spin, multiplier, color, model, openingSamples, maintenance");
  } else {
    throw FieldError{r.pointerOf("type"), (type.empty() ? std::string("missing") : "unknown light type \"" + type + "\"") +
                                              " (allowed: point, spot, directional, ies, sky, sun)"};
  }
  light.intensity = light.intensity * light.maintenance.factor();
  return light;
}

Camera readCamera(const Json& value, const std::string& pointer) {
  ObjectReader r(value, pointer);
  Camera camera;
  camera.eye = ObjectReader::checkedTriple(r.require("eye"), r.pointerOf("eye"), -1e30, 1e30);
  camera.target = ObjectReader::checkedTriple(r.require("target"), r.pointerOf("target"), -1e30, 1e30);
  camera.up = r.vector("up", {0, 1, 0});
  camera.verticalFovDegrees = r.number("verticalFovDegrees", 40, 0, 180, true, true);
  r.finish("eye, target, up, verticalFovDegrees");
  if (!(length(camera.target - camera.eye) > 0)) throw FieldError{r.pointerOf("target"), "the target must differ from the eye"};
  if (!(length(cross(camera.target - camera.eye, camera.up)) > 0))
    throw FieldError{r.pointerOf("up"), "up must not be zero or parallel to the view direction"};
  return camera;
}

// A mesh transform: scale, then rotations about x, y and z (degrees), then translation, each
// step applied to the result of the one before (their product would round differently).
struct MeshTransform {
  std::array<Transform, 5> steps;
  bool mirrors = false;

  MeshTransform(const Vec3& scale, const Vec3& rotateDegrees, const Vec3& translate)
      : steps{Transform::scaling(scale), Transform::rotation(0, rotateDegrees.x), Transform::rotation(1, rotateDegrees.y),
              Transform::rotation(2, rotateDegrees.z), Transform::translation(translate)},
        mirrors(scale.x * scale.y * scale.z < 0) {}
  Vec3 direction(Vec3 d) const {
    for (const Transform& step : steps) d = step.direction(d);
    return d;
  }
  Vec3 point(Vec3 p) const {
    for (const Transform& step : steps) p = step.point(p);
    return p;
  }
};

// A mesh file (OBJ, PLY, glTF, MGF) by a path relative to the scene file, in the scene's units:
// OBJ and PLY numbers are taken to be in them, glTF's and MGF's metres are converted. Its surfaces, materials and
// lights are added, transformed; its camera is kept for a scene file that has none.
void addMesh(Scene& scene, const Json& value, const std::string& pointer, const std::string& scenePath,
             std::optional<Camera>& camera) {
  ObjectReader r(value, pointer);
  const std::string relative = r.string("path", "");
  if (relative.empty()) throw FieldError{pointer, "missing required field \"path\""};
  if (!isMeshFile(relative)) throw FieldError{r.pointerOf("path"), "\"" + relative + "\" is not a mesh file (.obj, .ply, .gltf, .glb, .mgf)"};
  Vec3 scale{1, 1, 1}, rotateDegrees, translate;
  if (r.has("transform")) {
    ObjectReader tr(r.require("transform"), r.pointerOf("transform"));
    if (tr.has("scale") && tr.find("scale")->is_number()) {
      const double s = tr.number("scale", 1, -1e30, 1e30);
      scale = {s, s, s};
    } else {
      scale = tr.vector("scale", {1, 1, 1});
    }
    if (scale.x * scale.y * scale.z == 0) throw FieldError{tr.pointerOf("scale"), "a scale of zero flattens the mesh"};
    rotateDegrees = tr.vector("rotateDegrees", {});
    translate = tr.vector("translate", {});
    tr.finish("scale, rotateDegrees, translate");
  }
  const MeshTransform t(scale, rotateDegrees, translate);
  LoadOptions load;
  load.creaseAngleDegrees = r.number("creaseAngleDegrees", 20, 0, 180);
  if (r.has("twoSided")) load.twoSided = r.boolean("twoSided", false);
  if (r.has("mgfDivisions")) {
    if (lowercaseExtension(relative) != ".mgf") throw FieldError{r.pointerOf("mgfDivisions"), "only for .mgf files"};
    load.mgfDivisions = static_cast<int>(r.number("mgfDivisions", 16, 3, 1024));
  }
  r.finish("path, transform, creaseAngleDegrees, twoSided, mgfDivisions");
  const bool gltf = lowercaseExtension(relative) == ".gltf" || lowercaseExtension(relative) == ".glb";
  const std::string extension = lowercaseExtension(relative);
  if (extension == ".obj" || extension == ".ply") load.metresPerUnit = scene.metresPerUnit;  // their numbers are in the scene's unit
  const std::string file = (std::filesystem::path(scenePath).parent_path() / relative).string();
  Result<Scene> mesh = loadScene(file, load);
  if (!mesh) throw FieldError{r.pointerOf("path"), mesh.error().message};
  const double toSceneUnits = mesh->metresPerUnit / scene.metresPerUnit;

  const int firstMaterial = static_cast<int>(scene.materials.size());
  scene.materials.insert(scene.materials.end(), mesh->materials.begin(), mesh->materials.end());
  const int firstSurface = static_cast<int>(scene.surfaces.size());
  for (Surface surface : mesh->surfaces) {
    for (Vec3& v : surface.vertices) v = t.point(v * toSceneUnits);
    // A mirror turns every face over; reversing all but the first corner keeps the fan (and so a
    // twin pair's triangles) the same.
    if (t.mirrors && surface.faces.empty()) std::reverse(surface.vertices.begin() + 1, surface.vertices.end());
    if (t.mirrors) {
      for (auto& face : surface.faces) std::reverse(face.begin() + 1, face.end());
      for (auto& uvs : surface.faceUvs) std::reverse(uvs.begin() + 1, uvs.end());
      for (auto& uvs : surface.faceLightmapUvs) std::reverse(uvs.begin() + 1, uvs.end());
    }
    surface.material += firstMaterial;
    if (surface.twin >= 0) surface.twin += firstSurface;
    scene.surfaces.push_back(std::move(surface));
  }
  for (Light light : mesh->lights) {
    light.position = t.point(light.position * toSceneUnits);
    light.direction = normalize(t.direction(light.direction));
    scene.lights.push_back(light);
  }
  // Only a glTF can have a camera, and only one it gives is kept: without it, the scene file has
  // none either, and is drawn from the default view the bare file gets (the loader's stand-in,
  // cameraViewingScene's view from outside, showed a room from beyond its wall).
  if (!camera && gltf && mesh->cameraGiven) {
    Camera c = mesh->camera;
    c.eye = t.point(c.eye * toSceneUnits);
    c.target = t.point(c.target * toSceneUnits);
    c.up = normalize(t.direction(c.up));
    camera = c;
  }
}

SuggestedSettings readDefaults(const Json& value, const std::string& pointer) {
  ObjectReader r(value, pointer);
  SuggestedSettings d;
  if (r.has("patches") && r.has("maxEdge")) throw FieldError{pointer + "/maxEdge", "give either \"patches\" or \"maxEdge\", not both"};
  const double patches = r.number("patches", 0, 1, 200000);
  if (patches != std::floor(patches)) throw FieldError{pointer + "/patches", "expected a whole number of patches"};
  d.patches = static_cast<std::size_t>(patches);
  d.maxEdgeLength = r.number("maxEdge", 0, 0, 1e12, true);
  d.solver = r.string("solver", "");
  if (!d.solver.empty() && d.solver != "direct" && d.solver != "gs" && d.solver != "jacobi" && d.solver != "shoot")
    throw FieldError{pointer + "/solver", "\"" + d.solver + "\" is not a solver (allowed: direct, gs, jacobi, shoot)"};
  d.tolerance = r.number("tolerance", 0, 0, 1, true, true);
  r.finish("patches, maxEdge, solver, tolerance");
  return d;
}

Scene readScene(const Json& document, const std::string& path) {
  ObjectReader r(document, "");
  if (r.has("version")) {
    const double version = r.number("version", kFormatVersion, 1, 1e9);
    if (version != kFormatVersion)
      throw FieldError{"/version", "version " + formatNumber(version) + " is not supported (this lambert reads version 1)"};
  }
  Scene scene;
  scene.name = r.string("name", std::filesystem::path(path).stem().string());
  if (r.has("unit") && r.has("metresPerUnit")) throw FieldError{"/metresPerUnit", "give either \"unit\" or \"metresPerUnit\", not both"};
  scene.metresPerUnit = r.has("unit") ? metresPerUnitOf(r.string("unit", "m"), "/unit") : r.number("metresPerUnit", 1, 0, 1e12, true);

  // Materials by name; the emission lives on the material.
  std::map<std::string, int> materialIndex;
  std::vector<Rgb> materialEmission;
  const Json& materials = r.array("materials");
  for (std::size_t m = 0; m < materials.size(); ++m) {
    const std::string pointer = "/materials/" + std::to_string(m);
    ObjectReader mr(materials[m], pointer);
    Material material;
    material.name = mr.string("name", "");
    if (material.name.empty()) throw FieldError{pointer, "missing required field \"name\" (surfaces refer to materials by name)"};
    if (materialIndex.count(material.name)) throw FieldError{pointer + "/name", "a second material named \"" + material.name + "\""};
    material.albedo = mr.colour("albedo", Rgb::gray(0.5), 1, !mr.has("texture"));
    const Rgb emission = mr.colour("emittedRadiance", {}, 1e30, false);
    material.twoSided = mr.boolean("twoSided", false);
    if (const std::string texture = mr.string("texture", ""); !texture.empty()) {
      Result<std::shared_ptr<const Texture>> read = readTexture((std::filesystem::path(path).parent_path() / texture).string());
      if (!read) throw FieldError{pointer + "/texture", read.error().message};
      material.texture = *read;
      if (material.albedo.maxComponent() * material.texture->peak >= 1)
        throw FieldError{pointer + "/albedo", "albedo × the texture's brightest texel must stay below 1"};
    }
    if (const std::string texture = mr.string("emissionTexture", ""); !texture.empty()) {
      if (!mr.has("emittedRadiance"))
        throw FieldError{pointer + "/emissionTexture", "an emission texture multiplies \"emittedRadiance\": give it too ([1, 1, 1] for the texture as it is)"};
      Result<std::shared_ptr<const Texture>> read = readTexture((std::filesystem::path(path).parent_path() / texture).string());
      if (!read) throw FieldError{pointer + "/emissionTexture", read.error().message};
      material.emissionTexture = *read;
    }
    mr.finish("name, albedo, emittedRadiance, twoSided, texture, emissionTexture");
    materialIndex[material.name] = static_cast<int>(scene.materials.size());
    scene.materials.push_back(material);
    materialEmission.push_back(emission);
  }

  const Json& surfaces = r.array("surfaces");
  for (std::size_t s = 0; s < surfaces.size(); ++s) {
    const std::string pointer = "/surfaces/" + std::to_string(s);
    ObjectReader sr(surfaces[s], pointer);
    Surface surface;
    surface.name = sr.string("name", "surface " + std::to_string(s));
    const std::string material = sr.string("material", "");
    auto it = materialIndex.find(material);
    if (it == materialIndex.end())
      throw FieldError{pointer + "/material", material.empty() ? "missing required field \"material\"" : "no material named \"" + material + "\""};
    surface.material = it->second;
    surface.emittedRadiance = materialEmission[static_cast<std::size_t>(it->second)];
    const Json& vertices = sr.require("vertices");
    if (!vertices.is_array()) throw FieldError{pointer + "/vertices", "expected an array of [x, y, z], found " + typeName(vertices)};
    for (std::size_t k = 0; k < vertices.size(); ++k)
      surface.vertices.push_back(ObjectReader::checkedTriple(vertices[k], pointer + "/vertices/" + std::to_string(k), -1e30, 1e30));
    checkPolygon(surface.vertices, pointer + "/vertices");
    const Json& uvs = sr.array("uvs");
    if (const Material& m = scene.materials[static_cast<std::size_t>(surface.material)]; !uvs.empty() || m.texture || m.emissionTexture) {
      if (uvs.size() != surface.vertices.size())
        throw FieldError{pointer + "/uvs", uvs.empty() ? "its material has a texture: give texture coordinates [u, v] per vertex"
                                                       : "expected one [u, v] per vertex (" + std::to_string(surface.vertices.size()) +
                                                             "), found " + std::to_string(uvs.size())};
      std::vector<Uv> corners;
      for (std::size_t k = 0; k < uvs.size(); ++k) {
        const std::string at = pointer + "/uvs/" + std::to_string(k);
        if (!uvs[k].is_array() || uvs[k].size() != 2) throw FieldError{at, "expected [u, v], found " + typeName(uvs[k])};
        corners.push_back({ObjectReader::checkedNumber(uvs[k][0], at + "/0", -1e9, 1e9, false, false),
                           ObjectReader::checkedNumber(uvs[k][1], at + "/1", -1e9, 1e9, false, false)});
      }
      surface.faceUvs = {std::move(corners)};
    }
    // A second set, for lightmaps (mesh/lightmap_uvs.h): one [u, v] in [0, 1] per vertex.
    if (const Json& lightmapUvs = sr.array("lightmapUvs"); !lightmapUvs.empty()) {
      if (lightmapUvs.size() != surface.vertices.size())
        throw FieldError{pointer + "/lightmapUvs", "expected one [u, v] per vertex (" + std::to_string(surface.vertices.size()) + "), found " +
                                                       std::to_string(lightmapUvs.size())};
      std::vector<Uv> corners;
      for (std::size_t k = 0; k < lightmapUvs.size(); ++k) {
        const std::string at = pointer + "/lightmapUvs/" + std::to_string(k);
        if (!lightmapUvs[k].is_array() || lightmapUvs[k].size() != 2) throw FieldError{at, "expected [u, v], found " + typeName(lightmapUvs[k])};
        corners.push_back({ObjectReader::checkedNumber(lightmapUvs[k][0], at + "/0", 0, 1, false, false),
                           ObjectReader::checkedNumber(lightmapUvs[k][1], at + "/1", 0, 1, false, false)});
      }
      surface.faceLightmapUvs = {std::move(corners)};
    }
    sr.finish("name, material, vertices, uvs, lightmapUvs");
    scene.surfaces.push_back(std::move(surface));
  }
  const Json& lights = r.array("lights");
  PhotometryCache photometries;
  // The maintenance factor of every electric light that gives none of its own.
  const Maintenance maintenance = r.has("maintenance") ? readMaintenance(r.require("maintenance"), "/maintenance") : Maintenance{};
  for (std::size_t l = 0; l < lights.size(); ++l)
    scene.lights.push_back(readLight(lights[l], "/lights/" + std::to_string(l), path, photometries, maintenance));

  std::optional<Camera> meshCamera;
  const Json& meshes = r.array("meshes");
  {
    // Meshes that share a file (two OBJs and their one MTL) would report its problems once each.
    const WarningCapture once(WarningCapture::Forward::onceEach);
    for (std::size_t m = 0; m < meshes.size(); ++m) addMesh(scene, meshes[m], "/meshes/" + std::to_string(m), path, meshCamera);
  }
  if (scene.surfaces.empty()) throw FieldError{"/surfaces", "the scene has no surfaces (give \"surfaces\" or \"meshes\")"};
  scene.camera = r.has("camera") ? readCamera(r.require("camera"), "/camera") : meshCamera ? *meshCamera : cameraViewingScene(scene);
  scene.cameraGiven = r.has("camera") || meshCamera.has_value();
  if (r.has("exposure")) scene.exposureStops = r.number("exposure", 0, -64, 64);
  if (r.has("defaults")) scene.defaults = readDefaults(r.require("defaults"), "/defaults");
  r.finish("version, name, unit, metresPerUnit, materials, surfaces, meshes, lights, maintenance, camera, exposure, defaults");
  return scene;
}

// dump(2) puts every number on a line of its own; a [x, y, z] reads better on one, for people
// reading and editing the file. Lines: "[", three numbers ("…," twice), "]" or "],".
std::string withTriplesOnOneLine(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  auto trimmed = [](const std::string& line) { return line.substr(line.find_first_not_of(' ')); };
  auto isNumber = [](const std::string& t) {
    return !t.empty() && t.find_first_not_of("0123456789+-.eE") == std::string::npos;
  };
  std::string out;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const std::string& line = lines[k];
    if (k + 4 < lines.size() && !line.empty() && line.back() == '[') {
      const std::string a = trimmed(lines[k + 1]), b = trimmed(lines[k + 2]), c = trimmed(lines[k + 3]), end = trimmed(lines[k + 4]);
      if (a.back() == ',' && b.back() == ',' && isNumber(a.substr(0, a.size() - 1)) && isNumber(b.substr(0, b.size() - 1)) &&
          isNumber(c) && (end == "]" || end == "],")) {
        out += line + a + " " + b + " " + c + end + "\n";
        k += 4;
        continue;
      }
    }
    out += line + "\n";
  }
  if (!out.empty()) out.pop_back();
  return out;
}

OrderedJson triple(const Vec3& v) { return OrderedJson::array({v.x, v.y, v.z}); }
OrderedJson triple(const Rgb& c) { return OrderedJson::array({c.r, c.g, c.b}); }

// Visibility rays are traced in single precision (Embree): a scene whose size or distance from the
// origin is far outside float's comfortable range traces nothing meaningful (areas and distances
// squared overflow or underflow, and every face looks degenerate). Refused, with the size found.
constexpr double kMaxSceneCoordinate = 1e12, kMinSceneSize = 1e-6;
Status checkSceneExtent(const Scene& scene, const std::string& path) {
  double largest = 0;
  Vec3 low{1e300, 1e300, 1e300}, high{-1e300, -1e300, -1e300};
  for (const Surface& surface : scene.surfaces)
    for (const Vec3& v : surface.vertices) {
      largest = std::fmax(largest, std::fmax(std::fabs(v.x), std::fmax(std::fabs(v.y), std::fabs(v.z))));
      low = {std::fmin(low.x, v.x), std::fmin(low.y, v.y), std::fmin(low.z, v.z)};
      high = {std::fmax(high.x, v.x), std::fmax(high.y, v.y), std::fmax(high.z, v.z)};
    }
  if (scene.surfaces.empty()) return Ok{};
  const double size = length(high - low);
  if (!(largest <= kMaxSceneCoordinate))
    return Error{path + ": a coordinate of " + formatNumber(largest) + " units: lambert traces rays in single precision and reads coordinates up to " +
                 formatNumber(kMaxSceneCoordinate) + " (check the file's unit, or scale the scene down)"};
  if (!(size >= kMinSceneSize))
    return Error{path + ": the scene is " + formatNumber(size) + " units across: lambert needs at least " + formatNumber(kMinSceneSize) +
                 " (its faces have no area in single precision; check the file's unit, or scale the scene up)"};
  return Ok{};
}

}  // namespace

Result<Scene> parseSceneFile(const std::string& text, const std::string& path) {
  Json document;
  try {
    document = Json::parse(text);
  } catch (const Json::parse_error& e) {
    // The byte offset, as line:column of the text.
    const std::size_t offset = std::min<std::size_t>(e.byte == 0 ? 0 : e.byte - 1, text.size());
    std::size_t line = 1, column = 1;
    for (std::size_t k = 0; k < offset; ++k) {
      if (text[k] == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
    // nlohmann's text after its own "… line L, column C: " prefix (the first ": " after "column"):
    // the explanation and what it last read, e.g. "invalid literal; last read: '[N'" for a NaN.
    std::string what = e.what();
    if (auto at = what.find("column"); at != std::string::npos)
      if (auto colon = what.find(": ", at); colon != std::string::npos) what = what.substr(colon + 2);
    return Error{path + ":" + std::to_string(line) + ":" + std::to_string(column) + ": not valid JSON: " + what};
  } catch (const Json::exception& e) {  // a number too large for a double, and the like
    std::string what = e.what();
    if (auto bracket = what.find("] "); bracket != std::string::npos) what = what.substr(bracket + 2);
    return Error{path + ": not valid JSON: " + what};
  }
  try {
    return readScene(document, path);
  } catch (const FieldError& e) {
    return Error{path + ": " + e.pointer + ": " + e.message};
  }
}

Result<Scene> readSceneFile(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return Error{path + ": no such scene file"};
  Result<std::string> text = readWholeFile(path);
  if (!text) return text.error();
  return parseSceneFile(*text, path);
}

std::string sceneFileText(const Scene& scene) {
  OrderedJson doc;
  doc["version"] = kFormatVersion;
  doc["name"] = scene.name;
  std::string unitName;
  for (const char* unit : {"m", "cm", "mm", "in", "ft"})
    if (metresPerUnitOf(unit, "") == scene.metresPerUnit) unitName = unit;
  if (unitName.empty())
    doc["metresPerUnit"] = scene.metresPerUnit;
  else
    doc["unit"] = unitName;
  // One material per (material, emission) pair in use, in the scene's order of materials.
  std::vector<std::pair<int, Rgb>> kinds;
  for (int m = 0; m < static_cast<int>(scene.materials.size()); ++m)
    for (const Surface& s : scene.surfaces)
      if (s.material == m && std::find(kinds.begin(), kinds.end(), std::pair{m, s.emittedRadiance}) == kinds.end())
        kinds.emplace_back(m, s.emittedRadiance);
  std::vector<std::size_t> kindOf;
  for (const Surface& s : scene.surfaces)
    kindOf.push_back(static_cast<std::size_t>(std::find(kinds.begin(), kinds.end(), std::pair{s.material, s.emittedRadiance}) - kinds.begin()));
  std::vector<std::string> names;
  OrderedJson materials = OrderedJson::array();
  for (const auto& [index, emission] : kinds) {
    std::string name = scene.materials[static_cast<std::size_t>(index)].name;
    for (int copy = 2; std::find(names.begin(), names.end(), name) != names.end(); ++copy)
      name = scene.materials[static_cast<std::size_t>(index)].name + " " + std::to_string(copy);
    names.push_back(name);
    const Material& material = scene.materials[static_cast<std::size_t>(index)];
    LAMBERT_CHECK(!material.texture && !material.emissionTexture);  // a texture file is not written back
    OrderedJson m{{"name", name}, {"albedo", triple(material.albedo)}};
    if (emission.maxComponent() > 0) m["emittedRadiance"] = triple(emission);
    if (material.twoSided) m["twoSided"] = true;
    materials.push_back(std::move(m));
  }
  doc["materials"] = std::move(materials);
  OrderedJson surfaces = OrderedJson::array();
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    LAMBERT_CHECK(scene.surfaces[s].faces.empty());  // inline surfaces are single polygons
    if (scene.surfaces[s].twin >= 0 && static_cast<std::size_t>(scene.surfaces[s].twin) < s) continue;  // made again on reading
    OrderedJson vertices = OrderedJson::array();
    for (const Vec3& v : scene.surfaces[s].vertices) vertices.push_back(triple(v));
    surfaces.push_back({{"name", scene.surfaces[s].name}, {"material", names[kindOf[s]]}, {"vertices", std::move(vertices)}});
  }
  doc["surfaces"] = std::move(surfaces);
  OrderedJson lights = OrderedJson::array();
  for (const Light& light : scene.lights) {
    OrderedJson l{{"name", light.name}};
    // The light as new: its maintenance factor is written apart (and folded in again on reading).
    const Vec3 initial = Vec3{light.intensity.r, light.intensity.g, light.intensity.b} / light.maintenance.factor();
    switch (light.kind) {
      case LightKind::Point:
        l["type"] = "point";
        l["position"] = triple(light.position);
        l["intensity"] = triple(initial);
        break;
      case LightKind::Spot:
        l["type"] = "spot";
        l["position"] = triple(light.position);
        l["direction"] = triple(light.direction);
        l["intensity"] = triple(initial);
        l["coneAngleDegrees"] = light.coneAngleDegrees;
        l["falloffDegrees"] = light.falloffDegrees;
        l["angularVelocity"] = triple(light.angularVelocity);
        break;
      case LightKind::Directional:
        l["type"] = "directional";
        l["direction"] = triple(light.direction);
        l["irradiance"] = triple(light.irradiance);
        l["angularVelocity"] = triple(light.angularVelocity);
        break;
      case LightKind::Sky:
        l["type"] = "sky";
        if (light.sky->isUniformEnvironment()) {
          l["radiance"] = triple(light.sky->radiance({0, 1, 0}));
          l["directions"] = light.skyDirections;
          break;
        }
        if (light.sky->isTraditionalOvercast()) {
          l["cie"] = "overcast";
        } else if (light.sky->isPerez()) {
          const PerezCoefficients& p = light.sky->perezCoefficients();
          l["perez"] = {{"a", p.a}, {"b", p.b}, {"c", p.c}, {"d", p.d}, {"e", p.e}, {"clearness", p.clearness},
                        {"brightness", p.brightness}, {"bin", p.bin}, {"sunZenithRadians", p.sunZenithRadians}};
          l["sunAzimuth"] = light.sky->sunAzimuthDegrees();
          l["sunElevation"] = light.sky->sunElevationDegrees();
        } else {
          l["cie"] = light.sky->cieType();
          l["sunAzimuth"] = light.sky->sunAzimuthDegrees();
          l["sunElevation"] = light.sky->sunElevationDegrees();
        }
        l["zenithLuminance"] = light.sky->zenithLuminance();
        l["north"] = triple(light.sky->north());
        l["directions"] = light.skyDirections;
        break;
      case LightKind::Luminaire:
        LAMBERT_CHECK(light.photometry != nullptr);
        l["type"] = "ies";
        // Absolute: the written scene file need not lie beside the photometric file.
        l["file"] = std::filesystem::absolute(light.photometry->path).lexically_normal().string();
        l["position"] = triple(light.position);
        {
          // Its aim as the LM-72 angles a luminaire schedule gives (roll 0: the aim-point form);
          // read back, they give its frame to rounding (about 1e-15).
          const LuminaireAiming aiming = aimingOfDirection(light.direction, light.rotationDegrees);
          l["orient"] = aiming.orientDegrees;
          l["tilt"] = aiming.tiltDegrees;
          l["roll"] = aiming.rollDegrees;
          l["spin"] = aiming.spinDegrees;
        }
        l["color"] = triple(initial);
        if (light.luminaireModel == LuminaireModel::Opening) {
          l["model"] = "area";
          l["openingSamples"] = light.openingSamplesPerSide;
        }
        break;
    }
    if (light.maintenance != Maintenance{}) {
      const Maintenance& m = light.maintenance;
      l["maintenance"] = {{"lampLumen", m.lampLumen}, {"lampSurvival", m.lampSurvival}, {"luminaire", m.luminaire}, {"roomSurface", m.roomSurface}};
    }
    lights.push_back(std::move(l));
  }
  doc["lights"] = std::move(lights);
  if (scene.cameraGiven)
    doc["camera"] = {{"eye", triple(scene.camera.eye)},
                     {"target", triple(scene.camera.target)},
                     {"up", triple(scene.camera.up)},
                     {"verticalFovDegrees", scene.camera.verticalFovDegrees}};
  if (scene.exposureStops) doc["exposure"] = *scene.exposureStops;
  const SuggestedSettings& d = scene.defaults;
  OrderedJson defaults = OrderedJson::object();
  if (d.patches > 0) defaults["patches"] = d.patches;
  if (d.maxEdgeLength > 0) defaults["maxEdge"] = d.maxEdgeLength;
  if (!d.solver.empty()) defaults["solver"] = d.solver;
  if (d.tolerance > 0) defaults["tolerance"] = d.tolerance;
  if (!defaults.empty()) doc["defaults"] = std::move(defaults);
  return withTriplesOnOneLine(doc.dump(2)) + "\n";
}

Status writeSceneFile(const std::string& path, const Scene& scene) {
  const std::string text = sceneFileText(scene);
  return writeFileAtomically(path, std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

bool isMeshFile(const std::string& path) {
  const std::string extension = lowercaseExtension(path);
  return extension == ".obj" || extension == ".ply" || extension == ".gltf" || extension == ".glb" || extension == ".mgf";
}

Result<Scene> loadScene(const std::string& nameOrPath, const LoadOptions& options) {
  const std::string extension = lowercaseExtension(nameOrPath);
  const bool unitless = extension == ".obj" || extension == ".ply";
  if (options.metresPerUnit > 0 && !unitless)
    return Error{nameOrPath + ": a unit is for OBJ and PLY files, whose numbers have none; this scene states its own"};
  if (std::optional<Scene> builtin = builtinScene(nameOrPath)) return *builtin;
  auto withTwins = [&options, &nameOrPath](Result<Scene> scene) {
    if (!scene) return scene;
    if (Status size = checkSceneExtent(*scene, nameOrPath); !size) return Result<Scene>(size.error());
    if (options.twoSided)
      for (Material& material : scene->materials) material.twoSided = *options.twoSided;
    addTwins(*scene);
    return scene;
  };
  if (extension == ".json") return withTwins(readSceneFile(nameOrPath));
  if (extension == ".gltf" || extension == ".glb") return withTwins(readGltf(nameOrPath, {options.creaseAngleDegrees}));
  if (extension == ".mgf") {
    MgfOptions mgf;
    mgf.divisions = options.mgfDivisions;
    mgf.regions.creaseAngleDegrees = options.creaseAngleDegrees;
    mgf.includeRoot = options.includeRoot;
    return withTwins(readMgf(nameOrPath, mgf));
  }
  if (extension == ".ply")
    return withTwins(readPly(nameOrPath, options.metresPerUnit > 0 ? options.metresPerUnit : 1, {options.creaseAngleDegrees}));
  if (extension == ".obj") {
    ObjOptions obj;
    obj.metresPerUnit = options.metresPerUnit > 0 ? options.metresPerUnit : 1;
    obj.regions.creaseAngleDegrees = options.creaseAngleDegrees;
    return withTwins(readObj(nameOrPath, obj));
  }
  std::string names;
  for (const std::string& n : builtinSceneNames()) names += (names.empty() ? "" : ", ") + n;
  return Error{"unknown scene '" + nameOrPath + "' (built-in scenes: " + names + "; or a scene file: .json, .obj, .ply, .gltf, .glb, .mgf)"};
}

}  // namespace lambert
