#pragma once
// A calculation grid's illuminance drawn as a lighting designer's plan: the plane in false colour
// (bilinear between the grid's points), isolux lines at round levels with their values on them,
// axes in metres, a legend with the colour scale and its levels, a title with E_avg, E_min, E_max
// and U₀, and on a horizontal plane a north arrow and the luminaires' symbols at their places.
// 8-bit sRGB, for a PNG, an HTML report or a PDF page.
//
// Orientation. A horizontal plane is drawn as a plan, seen from above whichever way it faces (a
// ceiling as a reflected ceiling plan): the scene's +x to the right and −z up the page (lambert's
// convention: x east, north −z), the north arrow pointing to the scene's north where a sky or sun
// gives another. A vertical or sloping plane is drawn as seen from the side its points face, the
// scene's up (+y) up the page. Axis labels are the scene's coordinates in metres (the file's
// unit × metresPerUnit) where an axis of the page runs along one of the scene's axes, else the
// distance along the page from the plane's edge.
//
// Colours: Google's Turbo map (Mikhailov 2019, its published polynomial fit), 0 dark blue to the
// scale's top dark red. Isolux lines: a pixel is on the line of level ℓ where the field crosses ℓ
// between it and its right or lower neighbour, drawn in black (white on the darkest colours), each
// level's value written on its line (on a white box) at up to two places far apart. Cells the grid
// leaves out (outside a surface's faces) are light grey. Text: stb_easy_font.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "lambert/design/calculation_grid.h"

namespace lambert {

// A luminaire as a plan shows it: a ring at its position (projected on the plane along the plane's
// normal), a stroke along its aim's horizontal part (as long as the aim is tilted, full length
// at 90°), and its label beside it.
struct PlanLuminaire {
  Vec3 position;              // scene frame and units
  Vec3 aim{0, -1, 0};         // unit: its photometric nadir
  std::string label;          // e.g. "L1"
};

struct FalseColourOptions {
  int planePixels = 640;     // the plane's longer side, pixels (the axes, legend and title come around it)
  double scaleMaximum = 0;   // lux at the top of the colour scale; 0: the grid's maximum rounded up
  std::vector<double> isoluxLevels;  // lux; empty: round levels over the scale (about six)
  std::string title;         // first line of the title (the grid's name when empty)
  std::string unit = "lx";   // the values' unit, as the legend labels it (e.g. "%" for daylight factors)
  // The title's figures: <symbol>avg, <symbol>min, <symbol>max of the values, then (an
  // illuminance's) U0 and Emin/Emax unless uniformityFigures is false (a percentage of hours has none).
  std::string figureSymbol = "E";
  bool uniformityFigures = true;
  double metresPerUnit = 1;  // the scene's unit, for the axes
  Vec3 north{0, 0, -1};      // the scene's north (horizontal), for the arrow
  std::vector<PlanLuminaire> luminaires;  // drawn on a horizontal plane only
};

struct FalseColourImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // 8-bit sRGB, row-major, top row first
  std::vector<double> isoluxLevels;
  double scaleMaximum = 0;
  // Where the plane lies in the picture: its pixels' top-left corner and size, and the scene point
  // at the centre of each pixel, planeOrigin + pixelRight·(x + ½) + pixelDown·(y + ½) for plane pixel (x, y).
  int planeLeft = 0, planeTop = 0, planeWidth = 0, planeHeight = 0;
  Vec3 planeOrigin, pixelRight, pixelDown;
  // The picture pixel (column, row) where the scene point p, projected on the plane, is drawn.
  std::array<double, 2> pixelOf(const Vec3& p) const;
};

// values: one per grid point (lux, or % for daylight factors).
FalseColourImage falseColourImage(const CalculationGrid& grid, std::span<const double> values, const FalseColourOptions& options = {});

// Round levels for a scale from 0 to `maximum`: steps of 1, 2 or 5 × 10^k, about `count` of them.
std::vector<double> roundLevels(double maximum, int count = 6);

// Turbo's sRGB colour at t in [0, 1] (clamped), each channel 0..255.
std::array<std::uint8_t, 3> turboColour(double t);

}  // namespace lambert
