#pragma once
// `lambert report`: one self-contained HTML page per scene for a lighting designer — the scene and
// its solve, its lights in photometric units (cd, lm) and its emitting surfaces (cd/m²), every
// calculation grid with its figures (E_avg, E_min, E_max, U₀, E_min/E_max), its false-colour
// picture with isolux lines and a histogram of its values, and the illuminance at given points.
// Pictures are embedded (PNG data URIs) and plots are inline SVG, so the page is one file that
// any browser opens offline.
#include <string>

#include "lambert/core/error.h"
#include "lambert/core/stats.h"
#include "lambert/design/lighting.h"

namespace lambert {

class SolutionView;

struct ReportInput {
  const SolutionView* solution = nullptr;
  const LightingResults* lighting = nullptr;
  const PointsTable* points = nullptr;  // with lighting->points; none: no points section
  Stats figures;                        // the solve's figures, shown as a table
  std::string generator;                // e.g. "lambert 0.9.0"
};

Result<std::string> lightingReportHtml(const ReportInput& input);

// Standard base64 (RFC 4648 §4, with padding), for data URIs.
std::string base64(const std::vector<std::uint8_t>& bytes);

}  // namespace lambert
