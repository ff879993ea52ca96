#include "lambert/design/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "lambert/core/photometric.h"
#include "lambert/method/solution.h"
#include "lambert/io/png.h"
#include "lambert/light/emission.h"
#include "lambert/light/photometry.h"
#include "lambert/light/sky.h"

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

std::string fixed(double v, int digits = 1) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
  return buffer;
}

std::string general(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.4g", v);
  return buffer;
}

std::string value(const Stats::Value& v) {
  if (const auto* i = std::get_if<std::int64_t>(&v)) return std::to_string(*i);
  if (const auto* d = std::get_if<double>(&v)) return general(*d);
  return std::get<std::string>(v);
}

std::string lightKind(LightKind kind) {
  switch (kind) {
    case LightKind::Point: return "point";
    case LightKind::Spot: return "spot";
    case LightKind::Directional: return "directional";
    case LightKind::Sky: return "sky";
    case LightKind::Luminaire: return "luminaire";
  }
  return "light";
}

// A histogram of the grid's values as inline SVG: `bins` bars from 0 to the maximum, the mean marked.
std::string histogramSvg(const MeasuredGrid& m, const std::string& unit) {
  const int bins = 20, width = 420, height = 160, left = 40, bottom = 24;
  const double top = std::max(m.statistics.maximum, 1e-12);
  std::vector<int> count(bins, 0);
  for (double v : m.lux) count[std::clamp(static_cast<int>(v / top * bins), 0, bins - 1)]++;
  const int most = std::max(1, *std::max_element(count.begin(), count.end()));
  std::string svg = "<svg class=\"histogram\" width=\"" + std::to_string(width) + "\" height=\"" + std::to_string(height) +
                    "\" role=\"img\" aria-label=\"histogram of " + escaped(m.grid.name) + "\">";
  const int plotTop = 22;  // room above the bars for the mean's label
  const double barWidth = double(width - left - 10) / bins, plotHeight = height - bottom - plotTop;
  for (int b = 0; b < bins; ++b) {
    const double h = plotHeight * count[b] / most;
    svg += "<rect x=\"" + fixed(left + b * barWidth, 1) + "\" y=\"" + fixed(plotTop + plotHeight - h, 1) + "\" width=\"" +
           fixed(barWidth - 1, 1) + "\" height=\"" + fixed(h, 1) + "\" fill=\"#4a7ab8\"/>";
  }
  const double meanX = left + (width - left - 10) * m.statistics.average / top;
  svg += "<line x1=\"" + fixed(meanX) + "\" x2=\"" + fixed(meanX) + "\" y1=\"" + std::to_string(plotTop - 6) + "\" y2=\"" + fixed(plotTop + plotHeight) +
         "\" stroke=\"#c0392b\" stroke-width=\"2\"/>";
  const bool labelLeft = meanX > 0.6 * width;  // right of the line unless it would run off the plot
  svg += "<text x=\"" + fixed(labelLeft ? meanX - 4 : meanX + 4) + "\" y=\"" + std::to_string(plotTop - 8) +
         "\" font-size=\"11\" fill=\"#c0392b\"" + (labelLeft ? " text-anchor=\"end\"" : "") + ">E_avg " +
         general(m.statistics.average) + " " + unit + "</text>";
  svg += "<line x1=\"" + std::to_string(left) + "\" x2=\"" + std::to_string(width - 10) + "\" y1=\"" + fixed(plotTop + plotHeight) + "\" y2=\"" +
         fixed(plotTop + plotHeight) + "\" stroke=\"#333\"/>";
  svg += "<text x=\"" + std::to_string(left) + "\" y=\"" + std::to_string(height - 6) + "\" font-size=\"11\">0</text>";
  svg += "<text x=\"" + std::to_string(width - 10) + "\" y=\"" + std::to_string(height - 6) + "\" font-size=\"11\" text-anchor=\"end\">" +
         general(top) + " " + unit + "</text>";
  svg += "<text x=\"4\" y=\"" + std::to_string(plotTop + 10) + "\" font-size=\"11\">" + std::to_string(most) + "</text></svg>";
  return svg;
}

}  // namespace

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

Result<std::string> lightingReportHtml(const ReportInput& input) {
  if (!input.solution || !input.lighting) return Error{"a report needs a solution and its lighting results"};
  const SolutionView& solution = *input.solution;
  const Scene& scene = solution.scene();
  const LightingResults& lighting = *input.lighting;
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + escaped(scene.name) + " — lighting report</title>\n";
  h += "<style>body{font-family:system-ui,sans-serif;margin:2em auto;max-width:980px;color:#222}"
       "table{border-collapse:collapse;margin:0.5em 0 1.5em}td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}"
       "th{background:#f0f0f0}td.name,th.name{text-align:left}img{max-width:100%;border:1px solid #ddd}"
       "section{margin-bottom:2.5em}.note{color:#666;font-size:0.9em}</style></head><body>\n";
  h += "<h1>" + escaped(scene.name) + "</h1>\n<p class=\"note\">Lighting report written by " + escaped(input.generator) +
       ". Illuminance in lux = 683 lm/W × the Rec. 709 luminance of the RGB irradiance; direct light from the lights and "
       "emitting surfaces with their shadows, indirect light from the radiosity solution (docs/photometry.md).</p>\n";

  // Summary of every grid.
  h += "<section id=\"summary\"><h2>Calculation surfaces</h2>\n";
  if (lighting.grids.empty()) h += "<p>No calculation surface was asked for.</p>\n";
  else {
    h += "<table id=\"grids\"><tr><th class=\"name\">surface</th><th>points</th><th>spacing (m)</th><th>E<sub>avg</sub> (lx)</th>"
         "<th>E<sub>min</sub> (lx)</th><th>E<sub>max</sub> (lx)</th><th>U<sub>0</sub> = E<sub>min</sub>/E<sub>avg</sub></th>"
         "<th>E<sub>min</sub>/E<sub>max</sub></th></tr>\n";
    const bool daylight = lighting.skyHorizontalLux > 0;
    if (daylight) h.replace(h.rfind("</tr>\n"), 6, "<th>DF<sub>avg</sub> (%)</th><th>DF<sub>min</sub> (%)</th></tr>\n");
    for (const MeasuredGrid& m : lighting.grids) {
      const GridStatistics& s = m.statistics;
      const std::string df = daylight ? "<td>" + fixed(m.daylight.average, 2) + "</td><td>" + fixed(m.daylight.minimum, 2) + "</td>" : "";
      h += "<tr><td class=\"name\">" + escaped(m.grid.name) + "</td><td>" + std::to_string(s.points) + "</td><td>" +
           fixed(m.grid.spacingU * scene.metresPerUnit, 2) + "</td><td>" + fixed(s.average) + "</td><td>" + fixed(s.minimum) +
           "</td><td>" + fixed(s.maximum) + "</td><td>" + fixed(s.uniformity, 2) + "</td><td>" + fixed(s.minOverMax, 2) + "</td>" + df + "</tr>\n";
    }
    h += "</table>\n";
    if (daylight)
      h += "<p>Daylight factor DF = 100 · E / E<sub>h</sub> under the overcast sky that alone lights the scene, its unobstructed "
           "horizontal illuminance E<sub>h</sub> = " + fixed(lighting.skyHorizontalLux, 0) + " lx.</p>\n";
    h += "</section>\n";
  }
  for (std::size_t g = 0; g < lighting.grids.size(); ++g) {
    const MeasuredGrid& m = lighting.grids[g];
    const FalseColourImage picture = falseColourImage(m.grid, m.lux);
    Result<std::vector<std::uint8_t>> png = encodePng(picture.width, picture.height, picture.rgb);
    if (!png) return png.error();
    h += "<section class=\"grid\"><h2>" + escaped(m.grid.name) + "</h2>\n";
    h += "<img alt=\"" + escaped(m.grid.name) + " in false colour with isolux lines\" width=\"" + std::to_string(picture.width) +
         "\" src=\"data:image/png;base64," + base64(*png) + "\">\n";
    h += "<h3>Distribution of illuminance</h3>\n" + histogramSvg(m, "lx") + "\n";
    double direct = 0, indirect = 0;
    for (const PointIrradiance& e : m.irradiance) direct += illuminanceLux(e.direct), indirect += illuminanceLux(e.indirect);
    const double n = static_cast<double>(std::max<std::size_t>(m.irradiance.size(), 1));
    h += "<p>Mean direct " + fixed(direct / n) + " lx, mean indirect " + fixed(indirect / n) + " lx (" +
         fixed(direct + indirect > 0 ? 100 * indirect / (direct + indirect) : 0, 0) + "% indirect).</p></section>\n";
  }
  if (input.points && !lighting.points.empty()) {
    h += "<section id=\"points\"><h2>Points</h2>\n<table><tr>";
    for (const std::string& column : input.points->header) h += "<th>" + escaped(column) + "</th>";
    h += "<th>E<sub>direct</sub> (lx)</th><th>E<sub>indirect</sub> (lx)</th><th>E (lx)</th></tr>\n";
    for (std::size_t i = 0; i < lighting.points.size() && i < input.points->rows.size(); ++i) {
      h += "<tr>";
      for (const std::string& field : input.points->rows[i]) h += "<td>" + escaped(field) + "</td>";
      h += "<td>" + fixed(illuminanceLux(lighting.points[i].direct)) + "</td><td>" + fixed(illuminanceLux(lighting.points[i].indirect)) +
           "</td><td>" + fixed(illuminanceLux(lighting.points[i].total())) + "</td></tr>\n";
    }
    h += "</table></section>\n";
  }
  // Lights and emitters in photometric units.
  h += "<section id=\"lights\"><h2>Light sources</h2>\n";
  if (!solution.lights().empty()) {
    h += "<table><tr><th class=\"name\">light</th><th class=\"name\">type</th><th>position (scene units)</th><th>peak intensity (cd)</th>"
         "<th>luminous flux (lm)</th><th>illuminance (lx)</th></tr>\n";
    for (const Light& light : solution.lights()) {
      const bool placed = light.kind != LightKind::Directional && light.kind != LightKind::Sky;
      std::string candela = "—", flux = "—", lux = "—";
      if (light.kind == LightKind::Point || light.kind == LightKind::Spot) candela = fixed(kLumensPerWatt * light.intensity.luminance());
      if (light.kind == LightKind::Point) flux = fixed(4 * kPi * kLumensPerWatt * light.intensity.luminance());
      if (light.kind == LightKind::Luminaire && light.photometry) {
        candela = fixed(light.photometry->maxCandela() * light.intensity.luminance());
        flux = fixed(light.photometry->luminousFlux() * light.intensity.luminance());
      }
      if (light.kind == LightKind::Directional) lux = fixed(kLumensPerWatt * light.irradiance.luminance()) + " (normal)";
      if (light.kind == LightKind::Sky && light.sky) lux = fixed(light.sky->horizontalIlluminance()) + " (horizontal, unobstructed)";
      h += "<tr><td class=\"name\">" + escaped(light.name) + "</td><td class=\"name\">" + lightKind(light.kind) + "</td><td>" +
           (placed ? general(light.position.x) + ", " + general(light.position.y) + ", " + general(light.position.z) : std::string("—")) +
           "</td><td>" + candela + "</td><td>" + flux + "</td><td>" + lux + "</td></tr>\n";
    }
    h += "</table>\n";
  }
  bool anyEmitter = false;
  for (const Surface& surface : scene.surfaces) {
    const Rgb radiance = meanEmittedRadiance(scene, surface);
    if (!(radiance.maxComponent() > 0)) continue;
    if (!anyEmitter) {
      h += "<table><tr><th class=\"name\">emitting surface</th><th>luminance (cd/m²)</th><th>area (m²)</th><th>luminous flux (lm)</th></tr>\n";
      anyEmitter = true;
    }
    const double area = surfaceArea(surface) * scene.metresPerUnit * scene.metresPerUnit;
    const double luminance = luminanceCandelasPerSquareMetre(radiance);
    h += "<tr><td class=\"name\">" + escaped(surface.name) + "</td><td>" + fixed(luminance) + "</td><td>" + general(area) + "</td><td>" +
         fixed(kPi * luminance * area) + "</td></tr>\n";
  }
  if (anyEmitter) h += "</table>\n";
  if (solution.lights().empty() && !anyEmitter) h += "<p>The scene has no light source.</p>\n";
  h += "</section>\n";
  // The solve's figures.
  h += "<section id=\"solve\"><h2>Solution</h2>\n<table>";
  for (const Stats::Entry& e : input.figures.entries())
    h += "<tr><td class=\"name\">" + escaped(e.label) + "</td><td>" + escaped(value(e.value)) + (e.unit.empty() ? "" : " " + escaped(e.unit)) +
         "</td></tr>\n";
  h += "</table></section>\n</body></html>\n";
  return h;
}

}  // namespace lambert
