#pragma once
// A calculation grid's illuminance as lighting-design programs draw it: the plane in false colour
// (bilinear between the grid's points), isolux lines at round levels, a legend with the colour
// scale and its levels in lux, and a title with E_avg, E_min, E_max and U₀. 8-bit sRGB, for a PNG
// or an HTML report.
//
// Colours: Google's Turbo map (Mikhailov 2019, its published polynomial fit), E = 0 dark blue to
// the scale's top dark red. Isolux lines: a pixel is on the line of level ℓ where the field
// crosses ℓ between it and its right or lower neighbour, drawn in black (white on the darkest
// colours). Cells the grid leaves out (outside a surface's faces) are light grey. Text: stb_easy_font.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "lambert/design/calculation_grid.h"

namespace lambert {

struct FalseColourOptions {
  int planePixels = 640;     // the plane's longer side, pixels (the legend and title come on top)
  double scaleMaximum = 0;   // lux at the top of the colour scale; 0: the grid's maximum rounded up
  std::vector<double> isoluxLevels;  // lux; empty: round levels over the scale (about six)
  std::string title;         // first line of the title (the grid's name when empty)
  std::string unit = "lx";   // the values' unit, as the legend labels it (e.g. "%" for daylight factors)
};

struct FalseColourImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // 8-bit sRGB, row-major, top row first
  std::vector<double> isoluxLevels;
  double scaleMaximum = 0;
};

// values: one per grid point (lux, or % for daylight factors).
FalseColourImage falseColourImage(const CalculationGrid& grid, std::span<const double> values, const FalseColourOptions& options = {});

// Round levels for a scale from 0 to `maximum`: steps of 1, 2 or 5 × 10^k, about `count` of them.
std::vector<double> roundLevels(double maximum, int count = 6);

// Turbo's sRGB colour at t in [0, 1] (clamped), each channel 0..255.
std::array<std::uint8_t, 3> turboColour(double t);

}  // namespace lambert
