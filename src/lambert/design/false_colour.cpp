#include "lambert/design/false_colour.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <stb/stb_easy_font.h>

namespace lambert {
namespace {

using Colour = std::array<std::uint8_t, 3>;

struct Canvas {
  int width, height;
  std::vector<std::uint8_t> rgb;
  Canvas(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 255) {}
  void set(int x, int y, const Colour& c) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    std::uint8_t* p = rgb.data() + (static_cast<std::size_t>(y) * width + x) * 3;
    p[0] = c[0], p[1] = c[1], p[2] = c[2];
  }
  void fill(int x0, int y0, int x1, int y1, const Colour& c) {
    for (int y = std::max(y0, 0); y < std::min(y1, height); ++y)
      for (int x = std::max(x0, 0); x < std::min(x1, width); ++x) set(x, y, c);
  }
  // Text at (x, y), its top-left corner, each font pixel `scale` pixels (stb_easy_font's quads).
  void text(int x, int y, const std::string& s, int scale, const Colour& c) {
    std::vector<char> buffer(s.size() * 300 + 64);
    std::string copy = s;
    const int quads = stb_easy_font_print(0, 0, copy.data(), nullptr, buffer.data(), static_cast<int>(buffer.size()));
    for (int q = 0; q < quads; ++q) {
      const float* v0 = reinterpret_cast<const float*>(buffer.data() + q * 64);
      const float* v2 = reinterpret_cast<const float*>(buffer.data() + q * 64 + 32);
      fill(x + static_cast<int>(std::lround(v0[0] * scale)), y + static_cast<int>(std::lround(v0[1] * scale)),
           x + static_cast<int>(std::lround(v2[0] * scale)), y + static_cast<int>(std::lround(v2[1] * scale)), c);
    }
  }
  static int textWidth(const std::string& s, int scale) {
    std::string copy = s;
    return stb_easy_font_width(copy.data()) * scale;
  }
};

std::string formatValue(double v) {
  char buffer[32];
  if (v != 0 && std::fabs(v) < 10) std::snprintf(buffer, sizeof buffer, "%.3g", v);
  else std::snprintf(buffer, sizeof buffer, "%.0f", v);
  return buffer;
}

}  // namespace

std::array<std::uint8_t, 3> turboColour(double t) {
  // Mikhailov's polynomial fit to Turbo (Google AI blog, 2019): each channel a degree-5
  // polynomial in t.
  t = std::clamp(t, 0.0, 1.0);
  const double t2 = t * t, t3 = t2 * t, t4 = t3 * t, t5 = t4 * t;
  const double r = 0.13572138 + 4.61539260 * t - 42.66032258 * t2 + 132.13108234 * t3 - 152.94239396 * t4 + 59.28637943 * t5;
  const double g = 0.09140261 + 2.19418839 * t + 4.84296658 * t2 - 14.18503333 * t3 + 4.27729857 * t4 + 2.82956604 * t5;
  const double b = 0.10667330 + 12.64194608 * t - 60.58204836 * t2 + 110.36276771 * t3 - 89.90310912 * t4 + 27.34824973 * t5;
  auto byte = [](double x) { return static_cast<std::uint8_t>(std::lround(std::clamp(x, 0.0, 1.0) * 255)); };
  return {byte(r), byte(g), byte(b)};
}

std::vector<double> roundLevels(double maximum, int count) {
  if (!(maximum > 0) || count < 1) return {};
  const double raw = maximum / count;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  double step = decade;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * decade >= raw) {
      step = m * decade;
      break;
    }
  std::vector<double> levels;
  for (int k = 1; k * step < maximum * (1 - 1e-9); ++k) levels.push_back(k * step);
  return levels;
}

FalseColourImage falseColourImage(const CalculationGrid& grid, std::span<const double> values, const FalseColourOptions& options) {
  FalseColourImage out;
  double maximum = 0;
  for (double v : values) maximum = std::max(maximum, v);
  double top = options.scaleMaximum;
  if (!(top > 0)) {
    // The maximum rounded up to a step of the round levels (so that the scale ends on a level).
    const std::vector<double> guide = roundLevels(std::max(maximum, 1e-12), 6);
    const double step = guide.empty() ? maximum : guide.front();
    top = step > 0 ? std::ceil(maximum / step - 1e-9) * step : 1;
    if (!(top > 0)) top = 1;
  }
  out.scaleMaximum = top;
  out.isoluxLevels = options.isoluxLevels.empty() ? roundLevels(top, 6) : options.isoluxLevels;

  // The plane's pixels: the longer side planePixels, cells square on screen.
  const double lu = grid.spacingU * grid.nu, lv = grid.spacingV * grid.nv;
  const double pixelSize = std::max(lu, lv) / std::max(options.planePixels, 16);
  const int pw = std::max(1, static_cast<int>(std::lround(lu / pixelSize)));
  const int ph = std::max(1, static_cast<int>(std::lround(lv / pixelSize)));
  const int scale = 2, margin = 16, titleHeight = 2 * 12 * scale + margin, legendWidth = 150;
  const GridStatistics stats = gridStatistics(values);
  const std::string title = options.title.empty() ? grid.name : options.title;
  const std::string unit = std::string(" ").append(options.unit);
  const std::string figures = "Eavg " + formatValue(stats.average) + unit + "   Emin " + formatValue(stats.minimum) + unit + "   Emax " +
                              formatValue(stats.maximum) + unit + "   U0 " + formatValue(stats.uniformity) + "   Emin/Emax " +
                              formatValue(stats.minOverMax) + "   " + std::to_string(stats.points) + " points";
  const int textWidth = std::max(Canvas::textWidth(title, scale), Canvas::textWidth(figures, scale)) + 2 * margin;
  Canvas canvas(std::max(margin + pw + margin + legendWidth, textWidth), titleHeight + std::max(ph, 120) + margin + 12 * scale);

  // The field at plane pixel (x, y): bilinear between the cell centres that have points (the
  // nearest such centre's value where a neighbour is missing); NaN outside the grid's cells.
  auto valueAt = [&](int i, int j) -> double {
    if (i < 0 || j < 0 || i >= grid.nu || j >= grid.nv) return NAN;
    const int p = grid.pointOfCell[static_cast<std::size_t>(j) * grid.nu + i];
    return p < 0 ? NAN : values[p];
  };
  std::vector<double> field(static_cast<std::size_t>(pw) * ph, NAN);
  for (int y = 0; y < ph; ++y)
    for (int x = 0; x < pw; ++x) {
      // The image's y runs down the plane's v axis from its far side, so that +v is up on screen.
      const double u = (x + 0.5) / pw * grid.nu - 0.5, v = (ph - y - 0.5) / ph * grid.nv - 0.5;
      const int ci = static_cast<int>(std::lround(u)), cj = static_cast<int>(std::lround(v));
      if (std::isnan(valueAt(std::clamp(ci, 0, grid.nu - 1), std::clamp(cj, 0, grid.nv - 1)))) continue;
      const int i0 = static_cast<int>(std::floor(u)), j0 = static_cast<int>(std::floor(v));
      const double fu = u - i0, fv = v - j0;
      double weighted = 0, weights = 0;
      for (int dj = 0; dj < 2; ++dj)
        for (int di = 0; di < 2; ++di) {
          const double value = valueAt(i0 + di, j0 + dj);
          if (std::isnan(value)) continue;
          const double w = (di ? fu : 1 - fu) * (dj ? fv : 1 - fv);
          weighted += w * value;
          weights += w;
        }
      field[static_cast<std::size_t>(y) * pw + x] = weights > 0 ? weighted / weights : valueAt(std::clamp(ci, 0, grid.nu - 1), std::clamp(cj, 0, grid.nv - 1));
    }
  const Colour grey{210, 210, 210}, black{0, 0, 0}, white{255, 255, 255};
  for (int y = 0; y < ph; ++y)
    for (int x = 0; x < pw; ++x) {
      const double f = field[static_cast<std::size_t>(y) * pw + x];
      canvas.set(margin + x, titleHeight + y, std::isnan(f) ? grey : turboColour(f / top));
    }
  // Isolux lines: where the field crosses a level between a pixel and its right or lower neighbour.
  for (int y = 0; y < ph; ++y)
    for (int x = 0; x < pw; ++x) {
      const double f = field[static_cast<std::size_t>(y) * pw + x];
      if (std::isnan(f)) continue;
      for (double level : out.isoluxLevels) {
        bool crosses = false;
        for (auto [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
          if (x + dx >= pw || y + dy >= ph) continue;
          const double g = field[static_cast<std::size_t>(y + dy) * pw + x + dx];
          if (!std::isnan(g) && (f < level) != (g < level)) crosses = true;
        }
        if (crosses) canvas.set(margin + x, titleHeight + y, level / top < 0.12 ? white : black);
      }
    }
  // Title: the name, then the statistics.
  canvas.text(margin, margin / 2, title, scale, black);
  canvas.text(margin, margin / 2 + 12 * scale, figures, scale, black);
  // Legend: the colour bar from 0 (bottom) to the top of the scale, its levels marked.
  const int barX = margin + pw + margin, barTop = titleHeight, barHeight = std::max(ph, 120), barWidth = 24;
  for (int y = 0; y < barHeight && barTop + y < canvas.height; ++y)
    canvas.fill(barX, barTop + y, barX + barWidth, barTop + y + 1, turboColour(1 - (y + 0.5) / barHeight));
  std::vector<double> labels = out.isoluxLevels;
  labels.insert(labels.begin(), 0.0);
  labels.push_back(top);
  for (double level : labels) {
    const int y = barTop + static_cast<int>(std::lround((1 - level / top) * (barHeight - 1)));
    canvas.fill(barX + barWidth, y, barX + barWidth + 6, y + 1, black);
    canvas.text(barX + barWidth + 9, y - 5, formatValue(level) + unit, scale, black);
  }
  out.width = canvas.width;
  out.height = canvas.height;
  out.rgb = std::move(canvas.rgb);
  return out;
}

}  // namespace lambert
