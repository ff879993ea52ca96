#pragma once
// `lambert report`: a lighting designer's report of a solved scene, as one self-contained HTML page
// and as a PDF, both drawn from one document of pages:
//  - a summary: every calculation surface's figures (Ē, E_min, E_max, U₀, E_min/E_max), the room
//    (its dimensions, its surfaces' reflectances and areas), the maintenance factors, the
//    installed power and power density (W/m², W/m² per 100 lx);
//  - the luminaires: a schedule of types (product, file, flux as new and maintained, maintenance
//    factor, stated wattage, count) and each one's mounting (position, height above the floor,
//    orient, tilt, spin: light/lights.h's aiming angles); emitting surfaces; daylight (the sky's
//    type, zenith luminance and horizontal illuminance, the sun's position and illuminance);
//  - glare: UGR (CIE 117) at the observers, and each luminaire type's standard UGR table (CIE 190);
//  - one page per calculation surface: its figures and their split (direct, sky, sun, indirect),
//    the CSV file and column they come from, the plan (design/false_colour.h) and a histogram;
//  - the points, and the solve's own figures.
// Every illuminance is a maintained value (Scene Maintenance, folded into the lights' output) and
// every figure of a surface or point is a mean, least or greatest of a column of the CSV named
// beside it (design/points_file.h), so that each can be checked.
#include <cstdint>
#include <string>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/stats.h"
#include "lambert/design/lighting.h"

namespace lambert {

class SolutionView;

// The report as pages of blocks, which both writers lay out in their own way.
struct ReportTable {
  std::string caption;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::string id;  // an HTML id, for tests and links; may be empty
};
struct ReportImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // 8-bit sRGB, top row first
  std::string alt;
};
struct ReportHistogram {
  std::vector<int> counts;  // bins of equal width from 0 to `top`
  double top = 0, mean = 0;
  std::string unit, name;
};
struct ReportBlock {
  enum class Kind { Heading, Paragraph, Table, Image, Histogram } kind = Kind::Paragraph;
  std::string text;  // Heading, Paragraph
  ReportTable table;
  ReportImage image;
  ReportHistogram histogram;
};
struct ReportPage {
  std::string title, id;
  std::vector<ReportBlock> blocks;
};
// Blocks and number formats for building pages, shared by the report's own pages and others
// (design/daylight_metrics.h).
ReportBlock reportHeading(std::string text);
ReportBlock reportParagraph(std::string text);
ReportBlock reportTableBlock(ReportTable table);
ReportBlock reportImageBlock(const FalseColourImage& picture, std::string alt);
std::string reportFixed(double v, int digits = 1);  // printf's %.*f
std::string reportGeneral(double v);                // printf's %.4g

struct LightingReport {
  std::string title, subtitle;
  std::vector<ReportPage> pages;
};

struct ReportInput {
  const SolutionView* solution = nullptr;
  const LightingResults* lighting = nullptr;
  const PointsTable* points = nullptr;  // with lighting->points; none: no points page
  Stats figures;                        // the solve's figures, shown as a table
  std::string generator;                // e.g. "lambert 0.9.0"
  std::string date;                     // e.g. "2026-12-08"
  std::string sceneFile;                // as the user named it
  std::vector<std::string> gridFiles;   // per grid of `lighting`, the CSV its figures come from
  std::string pointsFile;               // the CSV of the points' figures; empty: none written
};

Result<LightingReport> lightingReport(const ReportInput& input);
// One HTML page: pictures embedded as PNG data URIs, histograms as inline SVG.
Result<std::string> reportHtml(const LightingReport& report);
// A PDF (A4 portrait, through cairo): each report page starts a new sheet, and runs on to more
// where it is long; written atomically.
Status writeReportPdf(const LightingReport& report, const std::string& path);

// The report written to `path` as its extension says: .pdf (writeReportPdf) or .html/.htm (reportHtml,
// atomically); an Error for another extension, naming it.
Status writeReportFile(const LightingReport& report, const std::string& path);

// Standard base64 (RFC 4648 §4, with padding), for data URIs.
std::string base64(const std::vector<std::uint8_t>& bytes);

}  // namespace lambert
