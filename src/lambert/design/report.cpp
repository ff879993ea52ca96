#include "lambert/design/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "lambert/core/atomic_file.h"
#include "lambert/core/photometric.h"
#include "lambert/core/text.h"
#include "lambert/io/png.h"
#include "lambert/light/emission.h"
#include "lambert/light/lights.h"
#include "lambert/light/photometry.h"
#include "lambert/light/sky.h"
#include "lambert/method/solution.h"

namespace lambert {
namespace {

// The shared helpers (report.h) by their short names here.
std::string fixed(double v, int digits = 1) { return reportFixed(v, digits); }
std::string general(double v) { return reportGeneral(v); }

std::string value(const Stats::Value& v) {
  if (const auto* i = std::get_if<std::int64_t>(&v)) return std::to_string(*i);
  if (const auto* d = std::get_if<double>(&v)) return general(*d);
  return std::get<std::string>(v);
}

ReportBlock heading(std::string text) { return reportHeading(std::move(text)); }
ReportBlock paragraph(std::string text) { return reportParagraph(std::move(text)); }
ReportBlock tableBlock(ReportTable table) { return reportTableBlock(std::move(table)); }

// The mean of a column (lux) over the grid's points.
double meanLux(const std::vector<PointIrradiance>& irradiance, Rgb PointIrradiance::*part) {
  double sum = 0;
  for (const PointIrradiance& e : irradiance) sum += illuminanceLux(e.*part);
  return irradiance.empty() ? 0 : sum / static_cast<double>(irradiance.size());
}

// A luminaire type: lights of one photometric file, output and maintenance.
struct LuminaireType {
  const Light* first = nullptr;
  std::vector<std::size_t> members;  // indices into the lights
};

std::string skyName(const SkyModel& sky) {
  if (sky.isUniformEnvironment()) return "uniform environment";
  if (sky.isTraditionalOvercast()) return "CIE traditional overcast (Moon and Spencer)";
  if (sky.isPerez()) {
    char text[96];
    std::snprintf(text, sizeof text, "Perez all-weather sky (clearness %.2f, brightness %.3f)", sky.perezCoefficients().clearness,
                  sky.perezCoefficients().brightness);
    return text;
  }
  return "CIE standard general sky, type " + std::to_string(sky.cieType());
}

}  // namespace

ReportBlock reportHeading(std::string text) { return {ReportBlock::Kind::Heading, std::move(text), {}, {}, {}}; }
ReportBlock reportParagraph(std::string text) { return {ReportBlock::Kind::Paragraph, std::move(text), {}, {}, {}}; }
ReportBlock reportTableBlock(ReportTable table) { return {ReportBlock::Kind::Table, {}, std::move(table), {}, {}}; }
ReportBlock reportImageBlock(const FalseColourImage& picture, std::string alt) {
  return {ReportBlock::Kind::Image, {}, {}, {picture.width, picture.height, picture.rgb, std::move(alt)}, {}};
}

std::string reportFixed(double v, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
  return buffer;
}

std::string reportGeneral(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.4g", v);
  return buffer;
}

std::string base64(const std::vector<std::uint8_t>& bytes) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t a = bytes[i], b = i + 1 < bytes.size() ? bytes[i + 1] : 0, c = i + 2 < bytes.size() ? bytes[i + 2] : 0;
    const std::uint32_t triple = (a << 16) | (b << 8) | c;
    out += alphabet[(triple >> 18) & 63];
    out += alphabet[(triple >> 12) & 63];
    out += i + 1 < bytes.size() ? alphabet[(triple >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? alphabet[triple & 63] : '=';
  }
  return out;
}

Result<LightingReport> lightingReport(const ReportInput& input) {
  if (!input.solution || !input.lighting) return Error{"a report needs a solution and its lighting results"};
  const SolutionView& solution = *input.solution;
  const Scene& scene = solution.scene();
  const LightingResults& lighting = *input.lighting;
  const std::vector<Light>& lights = solution.lights();
  const std::vector<std::string> labels = lightLabels(lights);
  const double mpu = scene.metresPerUnit, m2 = mpu * mpu;
  const Bounds bounds = sceneBounds(scene);
  const double length = (bounds.hi.x - bounds.lo.x) * mpu, depth = (bounds.hi.z - bounds.lo.z) * mpu, height = (bounds.hi.y - bounds.lo.y) * mpu;
  const double floorArea = length * depth;

  LightingReport report;
  report.title = scene.name + " — lighting report";
  report.subtitle = "Written by " + input.generator + (input.date.empty() ? "" : " on " + input.date) +
                    (input.sceneFile.empty() ? "" : " from " + input.sceneFile) + ".";

  // Luminaire types: one per photometric file and output (colour × multiplier × maintenance), and
  // one per point or spot light of its own intensity.
  std::vector<LuminaireType> types;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const Light& light = lights[i];
    if (light.kind != LightKind::Luminaire && light.kind != LightKind::Point && light.kind != LightKind::Spot) continue;
    auto same = std::find_if(types.begin(), types.end(), [&](const LuminaireType& t) {
      return t.first->kind == light.kind && t.first->photometry == light.photometry && t.first->intensity == light.intensity &&
             t.first->maintenance == light.maintenance && t.first->coneAngleDegrees == light.coneAngleDegrees;
    });
    if (same == types.end()) types.push_back({&light, {i}});
    else same->members.push_back(i);
  }
  auto typeName = [](std::size_t t) { return std::string(1, static_cast<char>('A' + t % 26)) + (t >= 26 ? std::to_string(t / 26) : ""); };
  double installedWatts = 0;
  bool everyWattageStated = !types.empty();
  for (const LuminaireType& t : types) {
    const double watts = t.first->photometry ? t.first->photometry->inputWatts : 0;
    if (!(watts > 0)) everyWattageStated = false;
    installedWatts += watts * static_cast<double>(t.members.size());
  }

  // Summary.
  ReportPage summary{"Summary", "summary", {}};
  bool anyMaintenance = false;
  for (const Light& light : lights) anyMaintenance |= light.maintenance.factor() != 1;
  summary.blocks.push_back(paragraph(
      std::string(anyMaintenance ? "Every illuminance is a maintained value: the lights' output as new times their maintenance factor MF "
                                   "(CIE 97: lamp lumen × lamp survival × luminaire × room surface maintenance), listed with the luminaires. "
                                 : "No maintenance factor is given (MF = 1): every illuminance is the value as new. ") +
      "Illuminance in lux = 683 lm/W × the Rec. 709 luminance of the RGB irradiance; direct light from the lights, skies, suns and "
      "emitting surfaces with their shadows, indirect light from the radiosity solution (docs/photometry.md). Each figure of a calculation "
      "surface is the mean, least or greatest of the column E of the CSV named on its page."));
  ReportTable grids{"Calculation surfaces", {"surface", "points", "spacing (m)", "Ē (lx)", "E min (lx)", "E max (lx)", "U₀ = E min/Ē", "E min/E max"}, {}, "grids"};
  const bool daylightFactors = lighting.skyHorizontalLux > 0;
  if (daylightFactors) grids.header.insert(grids.header.end(), {"DF mean (%)", "DF min (%)"});
  for (const MeasuredGrid& m : lighting.grids) {
    const GridStatistics& s = m.statistics;
    std::vector<std::string> row{m.grid.name, std::to_string(s.points), fixed(m.grid.spacingU * mpu, 2), fixed(s.average), fixed(s.minimum),
                                 fixed(s.maximum), fixed(s.uniformity, 2), fixed(s.minOverMax, 2)};
    if (daylightFactors) row.insert(row.end(), {fixed(m.daylight.average, 2), fixed(m.daylight.minimum, 2)});
    grids.rows.push_back(std::move(row));
  }
  if (grids.rows.empty()) summary.blocks.push_back(paragraph("No calculation surface was asked for."));
  else summary.blocks.push_back(tableBlock(std::move(grids)));
  if (daylightFactors)
    summary.blocks.push_back(paragraph("Daylight factor DF = 100 · E / E_h under the overcast sky that alone lights the scene, its unobstructed "
                                       "horizontal illuminance E_h = " + fixed(lighting.skyHorizontalLux, 0) + " lx."));
  summary.blocks.push_back(tableBlock({"Room (the scene's bounding box)", {"length x (m)", "depth z (m)", "height y (m)", "floor area (m²)"},
                                       {{fixed(length, 2), fixed(depth, 2), fixed(height, 2), fixed(floorArea, 2)}}, "room"}));
  ReportTable materials{"Surfaces and reflectances", {"material", "reflectance ρ (luminance)", "ρ red, green, blue", "area (m²)", "emitting"}, {}, "materials"};
  std::vector<double> materialArea(scene.materials.size(), 0);
  std::vector<char> materialEmits(scene.materials.size(), 0);
  for (const Surface& surface : scene.surfaces) {
    if (surface.material < 0 || static_cast<std::size_t>(surface.material) >= scene.materials.size()) continue;
    materialArea[surface.material] += surfaceArea(surface) * m2;
    materialEmits[surface.material] |= meanEmittedRadiance(scene, surface).maxComponent() > 0;
  }
  for (std::size_t k = 0; k < scene.materials.size(); ++k) {
    if (!(materialArea[k] > 0)) continue;
    const Material& mat = scene.materials[k];
    materials.rows.push_back({mat.name, fixed(mat.albedo.luminance(), 2) + (mat.texture ? " × texture" : ""),
                              fixed(mat.albedo.r, 2) + ", " + fixed(mat.albedo.g, 2) + ", " + fixed(mat.albedo.b, 2), fixed(materialArea[k], 2),
                              materialEmits[k] ? "yes" : ""});
  }
  summary.blocks.push_back(tableBlock(std::move(materials)));
  if (!types.empty()) {
    ReportTable power{"Power", {"luminaires", "installed power (W)", "floor area (m²)", "power density (W/m²)", "per 100 lx on the first surface (W/m²)"}, {}, "power"};
    std::size_t count = 0;
    for (const LuminaireType& t : types) count += t.members.size();
    const double density = floorArea > 0 ? installedWatts / floorArea : 0;
    const double perHundred = !lighting.grids.empty() && lighting.grids[0].statistics.average > 0 ? density * 100 / lighting.grids[0].statistics.average : 0;
    power.rows.push_back({std::to_string(count), everyWattageStated ? fixed(installedWatts, 1) : fixed(installedWatts, 1) + " (some not stated)",
                          fixed(floorArea, 2), fixed(density, 2), perHundred > 0 ? fixed(perHundred, 2) : "—"});
    summary.blocks.push_back(tableBlock(std::move(power)));
    if (!everyWattageStated)
      summary.blocks.push_back(paragraph("A luminaire whose photometric file states no input power counts 0 W here (point and spot lights always)."));
  }
  report.pages.push_back(std::move(summary));

  // Luminaires and daylight.
  ReportPage sources{"Light sources", "lights", {}};
  if (!types.empty()) {
    ReportTable schedule{"Luminaire schedule",
                         {"type", "count", "product", "file", "Φ as new (lm)", "MF", "Φ maintained (lm)", "power (W)", "lm/W"},
                         {},
                         "schedule"};
    ReportTable maintenance{"Maintenance factors (CIE 97)", {"type", "lamp lumen LLMF", "lamp survival LSF", "luminaire LMF", "room surface RSMF", "MF"}, {}, "maintenance"};
    for (std::size_t t = 0; t < types.size(); ++t) {
      const Light& light = *types[t].first;
      const double maintained = lightLumens(light), mf = light.maintenance.factor();
      const Photometry* p = light.photometry.get();
      const double watts = p ? p->inputWatts : 0;
      const std::string product = p ? (p->name.empty() ? "(not named)" : p->name) : light.kind == LightKind::Point ? "point light" : "spot light";
      schedule.rows.push_back({typeName(t), std::to_string(types[t].members.size()), product,
                               p ? std::filesystem::path(p->path).filename().string() : "—", fixed(maintained / mf, 1), fixed(mf, 3), fixed(maintained, 1),
                               watts > 0 ? fixed(watts, 1) : "not stated", watts > 0 ? fixed(maintained / mf / watts, 1) : "—"});
      const Maintenance& m = light.maintenance;
      maintenance.rows.push_back({typeName(t), fixed(m.lampLumen, 3), fixed(m.lampSurvival, 3), fixed(m.luminaire, 3), fixed(m.roomSurface, 3), fixed(mf, 3)});
    }
    sources.blocks.push_back(tableBlock(std::move(schedule)));
    sources.blocks.push_back(tableBlock(std::move(maintenance)));
    sources.blocks.push_back(paragraph("Flux as new: the photometric file's flux × the light's multiplier (or 4π·I for a point light, the cone's "
                                       "integral for a spot). Maintained flux: that × MF (MF = lamp lumen × lamp survival × luminaire × "
                                       "room surface maintenance factor)."));
    ReportTable mounting{"Mounting (aiming after IES LM-72: orient, tilt, roll, spin; docs/photometry.md)",
                         {"luminaire", "type", "x (m)", "y (m)", "z (m)", "height above floor (m)", "orient (°)", "tilt (°)", "spin (°)"},
                         {},
                         "mounting"};
    for (std::size_t t = 0; t < types.size(); ++t)
      for (std::size_t i : types[t].members) {
        const Light& light = lights[i];
        const LuminaireAiming aim = light.kind == LightKind::Point ? LuminaireAiming{} : aimingOfDirection(light.direction, light.rotationDegrees);
        mounting.rows.push_back({labels[i], typeName(t), fixed(light.position.x * mpu, 2), fixed(light.position.y * mpu, 2),
                                 fixed(light.position.z * mpu, 2), fixed((light.position.y - bounds.lo.y) * mpu, 2), fixed(aim.orientDegrees, 1),
                                 fixed(aim.tiltDegrees, 1), fixed(aim.spinDegrees, 1)});
      }
    sources.blocks.push_back(tableBlock(std::move(mounting)));
  }
  ReportTable emitters{"Emitting surfaces", {"surface", "luminance (cd/m²)", "area (m²)", "luminous flux (lm)"}, {}, "emitters"};
  for (const Surface& surface : scene.surfaces) {
    const Rgb radiance = meanEmittedRadiance(scene, surface);
    if (!(radiance.maxComponent() > 0)) continue;
    const double area = surfaceArea(surface) * m2, luminance = luminanceCandelasPerSquareMetre(radiance);
    emitters.rows.push_back({surface.name, fixed(luminance), general(area), fixed(kPi * luminance * area)});
  }
  if (!emitters.rows.empty()) sources.blocks.push_back(tableBlock(std::move(emitters)));
  ReportTable skies{"Daylight: skies", {"sky", "model", "zenith luminance (cd/m²)", "unobstructed horizontal illuminance (lx)", "sun azimuth (° from north, east +)", "sun elevation (°)"}, {}, "skies"};
  ReportTable suns{"Daylight: suns (directional lights)", {"sun", "azimuth (° from north, east +)", "elevation (°)", "normal illuminance (lx)"}, {}, "suns"};
  for (const Light& light : lights) {
    if (light.kind == LightKind::Sky && light.sky) {
      const SkyModel& sky = *light.sky;
      const bool withSun = !sky.isUniformEnvironment() && !sky.isTraditionalOvercast();
      skies.rows.push_back({light.name, skyName(sky), sky.isUniformEnvironment() ? "—" : fixed(sky.zenithLuminance(), 0), fixed(sky.horizontalIlluminance(), 0),
                            withSun ? fixed(sky.sunAzimuthDegrees(), 1) : "—", withSun ? fixed(sky.sunElevationDegrees(), 1) : "—"});
    }
    if (light.kind == LightKind::Directional) {
      const Vec3 toward = normalize(light.direction) * -1.0;  // toward the sun
      const double elevation = std::asin(std::clamp(toward.y, -1.0, 1.0)) * 180 / kPi;
      // Azimuth from the scene's north (−z), east (+x) positive, as the sky's.
      double azimuth = std::atan2(toward.x, -toward.z) * 180 / kPi;
      if (azimuth < 0) azimuth += 360;
      suns.rows.push_back({light.name, fixed(azimuth, 1), fixed(elevation, 1), fixed(illuminanceLux(light.irradiance), 0)});
    }
  }
  if (!skies.rows.empty()) sources.blocks.push_back(tableBlock(std::move(skies)));
  if (!suns.rows.empty()) sources.blocks.push_back(tableBlock(std::move(suns)));
  if (types.empty() && skies.rows.empty() && suns.rows.empty() && sources.blocks.empty())
    sources.blocks.push_back(paragraph("The scene has no light source."));
  report.pages.push_back(std::move(sources));

  // Glare.
  if (!lighting.glare.empty() || std::any_of(types.begin(), types.end(), [](const LuminaireType& t) { return t.first->photometry != nullptr; })) {
    ReportPage glare{"Glare (UGR)", "glare", {}};
    if (!lighting.glare.empty()) {
      ReportTable observers{"Unified glare rating at the observers (CIE 117)",
                            {"observer", "eye x, y, z (m)", "line of sight (° from east)", "L_b (cd/m²)", "luminaires counted", "UGR"},
                            {},
                            "ugr"};
      for (const GlareRating& g : lighting.glare) {
        int counted = 0;
        for (const GlareSource& s : g.rating.sources) counted += s.status == GlareSourceStatus::Counted;
        const Vec3& e = g.observer.eye;
        observers.rows.push_back({g.observer.name, fixed(e.x * mpu, 2) + ", " + fixed(e.y * mpu, 2) + ", " + fixed(e.z * mpu, 2),
                                  fixed(aimingOfDirection(g.observer.viewDirection, 0).orientDegrees, 0), fixed(g.rating.backgroundLuminance, 1), std::to_string(counted),
                                  std::isfinite(g.rating.ugr) ? (g.rating.ugr < 10 ? "< 10" : fixed(g.rating.ugr, 1)) : "no glare source in view"});
      }
      glare.blocks.push_back(tableBlock(std::move(observers)));
      glare.blocks.push_back(paragraph("UGR = 8 log10(0.25/L_b · Σ L² ω / p²) over the luminaires in the field of view (Guth's position index p), "
                                       "L_b = the indirect illuminance at the eye facing the line of sight / π. Below 10 glare is not rated; "
                                       "EN 12464-1 limits: 16 technical drawing, 19 offices, 22 industry."));
    }
    for (std::size_t t = 0; t < types.size(); ++t) {
      const Photometry* p = types[t].first->photometry.get();
      if (!p) continue;
      Result<UgrTable> table = ugrTable(*p);
      if (!table) {
        glare.blocks.push_back(paragraph("Type " + typeName(t) + ": no standard UGR table: " + table.error().message));
        continue;
      }
      const std::string name = p->name.empty() ? std::filesystem::path(p->path).filename().string() : p->name;
      glare.blocks.push_back(paragraph("Type " + typeName(t) + " (" + name + "): the standard UGR table (CIE 190) of its photometry, for a room of "
                                       "X × Y in multiples of H, the luminaires' height above the eye, spaced 0.25H, the observer at the middle "
                                       "of a wall; columns: the reflectances of ceiling/walls/floor cavity; corrected to the file's lamp flux " +
                                       fixed(table->lampLumens, 0) + " lm."));
      for (UgrViewing view : {UgrViewing::Crosswise, UgrViewing::Endwise}) {
        const bool crosswise = view == UgrViewing::Crosswise;
        ReportTable ugr{"Type " + typeName(t) + ", viewed " + (crosswise ? "crosswise (C0–C180 across the line of sight)" : "endwise (C0–C180 along it)"),
                        {"X × Y"},
                        {},
                        "ugr-table-" + typeName(t) + (crosswise ? "-crosswise" : "-endwise")};
        for (const UgrReflectances& r : kUgrTableReflectances)
          ugr.header.push_back(fixed(100 * r.ceiling, 0) + "/" + fixed(100 * r.walls, 0) + "/" + fixed(100 * r.floor, 0));
        for (std::size_t room = 0; room < kUgrTableRooms.size(); ++room) {
          std::vector<std::string> row{fixed(kUgrTableRooms[room].xOverH, 0) + "H × " + fixed(kUgrTableRooms[room].yOverH, 0) + "H"};
          for (std::size_t r = 0; r < kUgrTableReflectances.size(); ++r) row.push_back(fixed(table->value(view, room, r, true), 1));
          ugr.rows.push_back(std::move(row));
        }
        glare.blocks.push_back(tableBlock(std::move(ugr)));
      }
    }
    report.pages.push_back(std::move(glare));
  }

  // One page per calculation surface.
  const FalseColourOptions plan = planOptions(scene, lights);
  for (std::size_t g = 0; g < lighting.grids.size(); ++g) {
    const MeasuredGrid& m = lighting.grids[g];
    ReportPage page{m.grid.name, "surface-" + std::to_string(g + 1), {}};
    const std::string file = g < input.gridFiles.size() ? input.gridFiles[g] : "";
    page.blocks.push_back(paragraph(std::to_string(m.grid.points.size()) + " points, " + std::to_string(m.grid.nu) + " × " + std::to_string(m.grid.nv) +
                                    " cells of " + fixed(m.grid.spacingU * mpu, 2) + " × " + fixed(m.grid.spacingV * mpu, 2) + " m." +
                                    (file.empty() ? "" : " Its values: " + file + ", one row per point.")));
    const GridStatistics& s = m.statistics;
    ReportTable figures{"Maintained illuminance", {"figure", "value", "from"}, {}, "figures-" + std::to_string(g + 1)};
    figures.rows = {{"Ē (lx)", fixed(s.average), "mean of E"},
                    {"E min (lx)", fixed(s.minimum), "least of E"},
                    {"E max (lx)", fixed(s.maximum), "greatest of E"},
                    {"U₀ = E min/Ē", fixed(s.uniformity, 2), "E"},
                    {"E min/E max", fixed(s.minOverMax, 2), "E"},
                    {"direct, mean (lx)", fixed(meanLux(m.irradiance, &PointIrradiance::direct)), "mean of E_direct"},
                    {"of which sky, mean (lx)", fixed(meanLux(m.irradiance, &PointIrradiance::sky)), "mean of E_sky"},
                    {"of which sun, mean (lx)", fixed(meanLux(m.irradiance, &PointIrradiance::sun)), "mean of E_sun"},
                    {"indirect, mean (lx)", fixed(meanLux(m.irradiance, &PointIrradiance::indirect)), "mean of E_indirect"}};
    if (!m.daylightFactor.empty()) {
      figures.rows.push_back({"DF mean (%)", fixed(m.daylight.average, 2), "mean of DF"});
      figures.rows.push_back({"DF min (%)", fixed(m.daylight.minimum, 2), "least of DF"});
    }
    page.blocks.push_back(tableBlock(std::move(figures)));
    const FalseColourImage picture = falseColourImage(m.grid, m.lux, plan);
    page.blocks.push_back(reportImageBlock(picture, m.grid.name + " in false colour with isolux lines"));
    ReportHistogram histogram{std::vector<int>(20, 0), std::max(s.maximum, 1e-12), s.average, "lx", m.grid.name};
    for (double v : m.lux) histogram.counts[std::clamp(static_cast<int>(v / histogram.top * 20), 0, 19)]++;
    page.blocks.push_back(heading("Distribution of illuminance"));
    page.blocks.push_back({ReportBlock::Kind::Histogram, {}, {}, {}, std::move(histogram)});
    report.pages.push_back(std::move(page));
  }

  // Points.
  if (input.points && !lighting.points.empty()) {
    ReportPage page{"Points", "points", {}};
    if (!input.pointsFile.empty()) page.blocks.push_back(paragraph("The same values: " + input.pointsFile + "."));
    ReportTable points{"Illuminance at the points (lx)", input.points->header, {}, "points-table"};
    points.header.insert(points.header.end(), {"E_direct", "E_sky", "E_sun", "E_indirect", "E"});
    for (std::size_t i = 0; i < lighting.points.size() && i < input.points->rows.size(); ++i) {
      std::vector<std::string> row = input.points->rows[i];
      const PointIrradiance& e = lighting.points[i];
      row.insert(row.end(), {fixed(illuminanceLux(e.direct)), fixed(illuminanceLux(e.sky)), fixed(illuminanceLux(e.sun)),
                             fixed(illuminanceLux(e.indirect)), fixed(illuminanceLux(e.total()))});
      points.rows.push_back(std::move(row));
    }
    page.blocks.push_back(tableBlock(std::move(points)));
    report.pages.push_back(std::move(page));
  }

  // The solve.
  ReportPage solve{"Solution", "solve", {}};
  ReportTable figures{"The radiosity solution", {"figure", "value"}, {}, "solve-figures"};
  for (const Stats::Entry& e : input.figures.entries()) figures.rows.push_back({e.label, value(e.value) + (e.unit.empty() ? "" : " " + e.unit)});
  solve.blocks.push_back(tableBlock(std::move(figures)));
  report.pages.push_back(std::move(solve));
  return report;
}

}  // namespace lambert

namespace lambert {
namespace {

std::string escaped(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// A histogram as inline SVG: its bars from 0 to the top, the mean marked.
std::string histogramSvg(const ReportHistogram& histogram) {
  const int bins = static_cast<int>(histogram.counts.size()), width = 420, height = 160, left = 40, bottom = 24, plotTop = 22;
  const int most = std::max(1, *std::max_element(histogram.counts.begin(), histogram.counts.end()));
  std::string svg = "<svg class=\"histogram\" width=\"" + std::to_string(width) + "\" height=\"" + std::to_string(height) +
                    "\" role=\"img\" aria-label=\"histogram of " + escaped(histogram.name) + "\">";
  const double barWidth = double(width - left - 10) / bins, plotHeight = height - bottom - plotTop;
  for (int b = 0; b < bins; ++b) {
    const double h = plotHeight * histogram.counts[b] / most;
    svg += "<rect x=\"" + fixed(left + b * barWidth, 1) + "\" y=\"" + fixed(plotTop + plotHeight - h, 1) + "\" width=\"" + fixed(barWidth - 1, 1) +
           "\" height=\"" + fixed(h, 1) + "\" fill=\"#4a7ab8\"/>";
  }
  const double meanX = left + (width - left - 10) * histogram.mean / histogram.top;
  svg += "<line x1=\"" + fixed(meanX) + "\" x2=\"" + fixed(meanX) + "\" y1=\"" + std::to_string(plotTop - 6) + "\" y2=\"" + fixed(plotTop + plotHeight) +
         "\" stroke=\"#c0392b\" stroke-width=\"2\"/>";
  const bool labelLeft = meanX > 0.6 * width;  // right of the line unless it would run off the plot
  svg += "<text x=\"" + fixed(labelLeft ? meanX - 4 : meanX + 4) + "\" y=\"" + std::to_string(plotTop - 8) + "\" font-size=\"11\" fill=\"#c0392b\"" +
         (labelLeft ? " text-anchor=\"end\"" : "") + ">Ē " + general(histogram.mean) + " " + escaped(histogram.unit) + "</text>";
  svg += "<line x1=\"" + std::to_string(left) + "\" x2=\"" + std::to_string(width - 10) + "\" y1=\"" + fixed(plotTop + plotHeight) + "\" y2=\"" +
         fixed(plotTop + plotHeight) + "\" stroke=\"#333\"/>";
  svg += "<text x=\"" + std::to_string(left) + "\" y=\"" + std::to_string(height - 6) + "\" font-size=\"11\">0</text>";
  svg += "<text x=\"" + std::to_string(width - 10) + "\" y=\"" + std::to_string(height - 6) + "\" font-size=\"11\" text-anchor=\"end\">" +
         general(histogram.top) + " " + escaped(histogram.unit) + "</text>";
  svg += "<text x=\"4\" y=\"" + std::to_string(plotTop + 10) + "\" font-size=\"11\">" + std::to_string(most) + "</text></svg>";
  return svg;
}

}  // namespace

Result<std::string> reportHtml(const LightingReport& report) {
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + escaped(report.title) + "</title>\n";
  h += "<style>body{font-family:system-ui,sans-serif;margin:2em auto;max-width:1000px;color:#222}"
       "table{border-collapse:collapse;margin:0.3em 0 1.5em}td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}"
       "th{background:#f0f0f0}td:first-child,th:first-child{text-align:left}caption{text-align:left;font-weight:600;padding:4px 0}"
       "img{max-width:100%;border:1px solid #ddd}section{margin-bottom:2.5em;page-break-before:always}"
       "section:first-of-type{page-break-before:auto}.note{color:#666;font-size:0.9em}</style></head><body>\n";
  h += "<h1>" + escaped(report.title) + "</h1>\n<p class=\"note\">" + escaped(report.subtitle) + "</p>\n";
  for (const ReportPage& page : report.pages) {
    h += "<section id=\"" + escaped(page.id) + "\"><h2>" + escaped(page.title) + "</h2>\n";
    for (const ReportBlock& block : page.blocks) {
      switch (block.kind) {
        case ReportBlock::Kind::Heading: h += "<h3>" + escaped(block.text) + "</h3>\n"; break;
        case ReportBlock::Kind::Paragraph: h += "<p>" + escaped(block.text) + "</p>\n"; break;
        case ReportBlock::Kind::Table: {
          const ReportTable& t = block.table;
          h += "<table" + (t.id.empty() ? std::string() : " id=\"" + escaped(t.id) + "\"") + "><caption>" + escaped(t.caption) + "</caption><tr>";
          for (const std::string& c : t.header) h += "<th>" + escaped(c) + "</th>";
          h += "</tr>\n";
          for (const auto& row : t.rows) {
            h += "<tr>";
            for (const std::string& c : row) h += "<td>" + escaped(c) + "</td>";
            h += "</tr>\n";
          }
          h += "</table>\n";
          break;
        }
        case ReportBlock::Kind::Image: {
          Result<std::vector<std::uint8_t>> png = encodePng(block.image.width, block.image.height, block.image.rgb);
          if (!png) return png.error();
          h += "<img alt=\"" + escaped(block.image.alt) + "\" width=\"" + std::to_string(block.image.width) + "\" src=\"data:image/png;base64," +
               base64(*png) + "\">\n";
          break;
        }
        case ReportBlock::Kind::Histogram: h += histogramSvg(block.histogram) + "\n"; break;
      }
    }
    h += "</section>\n";
  }
  h += "</body></html>\n";
  return h;
}

Status writeReportFile(const LightingReport& report, const std::string& path) {
  const std::string extension = lowercaseExtension(path);
  if (extension == ".pdf") return writeReportPdf(report, path);
  if (extension != ".html" && extension != ".htm") return Error{path + ": a report is an HTML page or a PDF; give a path ending in .html or .pdf"};
  Result<std::string> html = reportHtml(report);
  if (!html) return html.error();
  return writeFileAtomically(path, std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(html->data()), html->size()));
}

}  // namespace lambert
