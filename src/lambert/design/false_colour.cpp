#include "lambert/design/false_colour.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <stb/stb_easy_font.h>

namespace lambert {
namespace {

using Colour = std::array<std::uint8_t, 3>;
constexpr Colour kBlack{0, 0, 0}, kWhite{255, 255, 255}, kGrey{210, 210, 210};

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
  // A line `thickness` pixels wide from (x0, y0) to (x1, y1).
  void line(double x0, double y0, double x1, double y1, int thickness, const Colour& c) {
    const int steps = std::max(1, static_cast<int>(std::ceil(std::max(std::fabs(x1 - x0), std::fabs(y1 - y0)) * 2)));
    for (int k = 0; k <= steps; ++k) {
      const double t = static_cast<double>(k) / steps;
      const int x = static_cast<int>(std::floor(x0 + (x1 - x0) * t)), y = static_cast<int>(std::floor(y0 + (y1 - y0) * t));
      fill(x - thickness / 2, y - thickness / 2, x - thickness / 2 + thickness, y - thickness / 2 + thickness, c);
    }
  }
  void ring(double cx, double cy, double radius, int thickness, const Colour& c) {
    const int steps = std::max(16, static_cast<int>(radius * 8));
    for (int k = 0; k < steps; ++k) {
      const double a = 2 * 3.14159265358979 * k / steps, b = 2 * 3.14159265358979 * (k + 1) / steps;
      line(cx + radius * std::cos(a), cy + radius * std::sin(a), cx + radius * std::cos(b), cy + radius * std::sin(b), thickness, c);
    }
  }
  // Text at (x, y), its top-left corner, each font pixel `scale` pixels (stb_easy_font's quads).
  void text(int x, int y, const std::string& s, int scale, const Colour& c) {
    std::vector<char> buffer((s.size() + 4) * 1024);  // stb_easy_font: up to ~20 quads of 64 bytes a character
    std::string copy = s;
    const int quads = stb_easy_font_print(0, 0, copy.data(), nullptr, buffer.data(), static_cast<int>(buffer.size()));
    for (int q = 0; q < quads; ++q) {
      const float* v0 = reinterpret_cast<const float*>(buffer.data() + q * 64);
      const float* v2 = reinterpret_cast<const float*>(buffer.data() + q * 64 + 32);
      fill(x + static_cast<int>(std::lround(v0[0] * scale)), y + static_cast<int>(std::lround(v0[1] * scale)),
           x + static_cast<int>(std::lround(v2[0] * scale)), y + static_cast<int>(std::lround(v2[1] * scale)), c);
    }
  }
  // The same on a white box, centred on (cx, cy).
  void label(double cx, double cy, const std::string& s, int scale) {
    const int w = textWidth(s, scale), h = 7 * scale;
    const int x = static_cast<int>(std::lround(cx - w / 2.0)), y = static_cast<int>(std::lround(cy - h / 2.0));
    fill(x - 2, y - 2, x + w + 2, y + h + 1, kWhite);
    text(x, y, s, scale, kBlack);
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

// The page's right and up in the scene, both in the plane (module comment).
struct PageAxes {
  Vec3 right, up;
  bool plan = false;  // a horizontal plane, drawn from above
};
PageAxes pageAxes(const CalculationGrid& grid) {
  Vec3 n = normalize(cross(grid.axisU, grid.axisV));
  if (!grid.points.empty() && dot(n, grid.points.front().normal) < 0) n = -n;
  if (std::fabs(n.y) > 0.99) return {{1, 0, 0}, {0, 0, -1}, true};
  const Vec3 up = normalize(Vec3{0, 1, 0} - n * n.y);
  return {normalize(cross(up, n)), up, false};
}

// A tick step of 1, 2 or 5 × 10^k for about `count` ticks over `span`.
double tickStep(double span, int count) {
  const std::vector<double> levels = roundLevels(span, count);
  return levels.empty() ? span : levels.front();
}

// One page axis: its label and, for each tick, its value and its position along the axis (0..1).
struct AxisTicks {
  std::string name;
  std::vector<std::pair<double, double>> ticks;  // value in metres, position 0..1 along the page
};
// The page axis `along` spans [lo, hi] (scene units from `origin`, i.e. origin + along·t).
AxisTicks axisTicks(const Vec3& origin, const Vec3& along, double lo, double hi, double metresPerUnit, int count) {
  static const char* kNames[] = {"x", "y", "z"};
  AxisTicks axis;
  int k = -1;
  for (int a = 0; a < 3; ++a)
    if (std::fabs(along[a]) > 0.999) k = a;
  // Page position f ∈ [0, 1] ↔ t = lo + f (hi − lo) ↔ value (metres).
  double v0, v1;
  if (k >= 0) {
    axis.name = std::string(kNames[k]) + " (m)";
    v0 = (origin[k] + along[k] * lo) * metresPerUnit, v1 = (origin[k] + along[k] * hi) * metresPerUnit;
  } else {
    axis.name = "distance (m)";
    v0 = 0, v1 = (hi - lo) * metresPerUnit;
  }
  const double span = std::fabs(v1 - v0);
  if (!(span > 0)) return axis;
  const double step = tickStep(span, count);
  const double first = std::ceil(std::min(v0, v1) / step - 1e-9) * step;
  for (double v = first; v <= std::max(v0, v1) + 1e-9 * span; v += step) {
    const double value = std::fabs(v) < 1e-9 * step ? 0.0 : v;
    axis.ticks.push_back({value, (value - v0) / (v1 - v0)});
  }
  return axis;
}

std::string formatMetres(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", std::round(v * 1000) / 1000);
  return buffer;
}

}  // namespace

std::array<double, 2> FalseColourImage::pixelOf(const Vec3& p) const {
  const Vec3 d = p - planeOrigin;
  return {planeLeft + dot(d, pixelRight) / dot(pixelRight, pixelRight), planeTop + dot(d, pixelDown) / dot(pixelDown, pixelDown)};
}

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

  // The plane's extent on the page: its grid's corners along the page's right and up.
  const PageAxes page = pageAxes(grid);
  double rLo = INFINITY, rHi = -INFINITY, uLo = INFINITY, uHi = -INFINITY;
  for (double a : {0.0, grid.spacingU * grid.nu})
    for (double b : {0.0, grid.spacingV * grid.nv}) {
      const Vec3 corner = grid.axisU * a + grid.axisV * b;
      rLo = std::min(rLo, dot(corner, page.right)), rHi = std::max(rHi, dot(corner, page.right));
      uLo = std::min(uLo, dot(corner, page.up)), uHi = std::max(uHi, dot(corner, page.up));
    }
  const double pixelSize = std::max(rHi - rLo, uHi - uLo) / std::max(options.planePixels, 16);
  const int pw = std::max(1, static_cast<int>(std::lround((rHi - rLo) / pixelSize)));
  const int ph = std::max(1, static_cast<int>(std::lround((uHi - uLo) / pixelSize)));
  const double mpu = options.metresPerUnit > 0 ? options.metresPerUnit : 1;
  const AxisTicks across = axisTicks(grid.origin, page.right, rLo, rLo + pw * pixelSize, mpu, std::max(2, pw / 90));
  const AxisTicks upward = axisTicks(grid.origin, page.up, uHi - ph * pixelSize, uHi, mpu, std::max(2, ph / 70));

  const int scale = 2, margin = 16, lineHeight = 12 * scale, titleHeight = 2 * lineHeight + margin, legendWidth = 150;
  int tickLabelWidth = 0;
  for (auto [value, f] : upward.ticks) tickLabelWidth = std::max(tickLabelWidth, Canvas::textWidth(formatMetres(value), scale));
  const int axisWidth = std::max(tickLabelWidth, lineHeight) + lineHeight + 14;  // the axis title, the labels, the ticks
  const int planeLeft = margin + axisWidth, planeTop = titleHeight;
  const int bottomHeight = 8 + 2 * lineHeight + margin;
  const GridStatistics stats = gridStatistics(values);
  const std::string title = options.title.empty() ? grid.name : options.title;
  const std::string unit = std::string(" ").append(options.unit);
  const std::string& symbol = options.figureSymbol;
  const std::string figures = symbol + "avg " + formatValue(stats.average) + unit + "   " + symbol + "min " + formatValue(stats.minimum) + unit +
                              "   " + symbol + "max " + formatValue(stats.maximum) + unit +
                              (options.uniformityFigures ? "   U0 " + formatValue(stats.uniformity) + "   Emin/Emax " + formatValue(stats.minOverMax) : "") +
                              "   " + std::to_string(stats.points) + " points";
  const int textWidth = std::max(Canvas::textWidth(title, scale), Canvas::textWidth(figures, scale)) + 2 * margin;
  const int arrowHeight = page.plan ? 110 : 0;  // the arrow and its N, whichever way north points, clear of the legend
  Canvas canvas(std::max(planeLeft + pw + margin + legendWidth, textWidth),
                planeTop + std::max(ph, 120 + arrowHeight) + bottomHeight);
  out.planeLeft = planeLeft, out.planeTop = planeTop, out.planeWidth = pw, out.planeHeight = ph;
  out.planeOrigin = grid.origin + page.right * rLo + page.up * uHi;
  out.pixelRight = page.right * pixelSize;
  out.pixelDown = page.up * -pixelSize;

  // The field at plane pixel (x, y): bilinear between the cell centres that have points (the
  // nearest such centre's value where a neighbour is missing); NaN outside the grid's cells.
  auto valueAt = [&](int i, int j) -> double {
    if (i < 0 || j < 0 || i >= grid.nu || j >= grid.nv) return NAN;
    const int p = grid.pointOfCell[static_cast<std::size_t>(j) * grid.nu + i];
    return p < 0 ? NAN : values[p];
  };
  std::vector<double> field(static_cast<std::size_t>(pw) * ph, NAN);
  std::vector<char> inside(field.size(), 0);  // within the grid's rectangle
  for (int y = 0; y < ph; ++y)
    for (int x = 0; x < pw; ++x) {
      const Vec3 d = out.pixelRight * (x + 0.5) + out.pixelDown * (y + 0.5) + page.right * rLo + page.up * uHi;
      const double u = dot(d, grid.axisU) / grid.spacingU - 0.5, v = dot(d, grid.axisV) / grid.spacingV - 0.5;
      if (u < -0.5 || v < -0.5 || u > grid.nu - 0.5 || v > grid.nv - 0.5) continue;
      inside[static_cast<std::size_t>(y) * pw + x] = 1;
      const int ci = std::clamp(static_cast<int>(std::lround(u)), 0, grid.nu - 1), cj = std::clamp(static_cast<int>(std::lround(v)), 0, grid.nv - 1);
      if (std::isnan(valueAt(ci, cj))) continue;
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
      field[static_cast<std::size_t>(y) * pw + x] = weights > 0 ? weighted / weights : valueAt(ci, cj);
    }
  for (int y = 0; y < ph; ++y)
    for (int x = 0; x < pw; ++x) {
      const std::size_t k = static_cast<std::size_t>(y) * pw + x;
      if (inside[k]) canvas.set(planeLeft + x, planeTop + y, std::isnan(field[k]) ? kGrey : turboColour(field[k] / top));
    }
  // Isolux lines: where the field crosses a level between a pixel and its right or lower neighbour.
  std::vector<std::vector<std::pair<int, int>>> onLevel(out.isoluxLevels.size());
  for (int y = 0; y < ph; ++y)
    for (int x = 0; x < pw; ++x) {
      const double f = field[static_cast<std::size_t>(y) * pw + x];
      if (std::isnan(f)) continue;
      for (std::size_t l = 0; l < out.isoluxLevels.size(); ++l) {
        const double level = out.isoluxLevels[l];
        bool crosses = false;
        for (auto [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
          if (x + dx >= pw || y + dy >= ph) continue;
          const double g = field[static_cast<std::size_t>(y + dy) * pw + x + dx];
          if (!std::isnan(g) && (f < level) != (g < level)) crosses = true;
        }
        if (!crosses) continue;
        canvas.set(planeLeft + x, planeTop + y, level / top < 0.12 ? kWhite : kBlack);
        onLevel[l].push_back({x, y});
      }
    }
  // Each level's value on its line: at the line's pixel nearest the plane's top-left (clear of the
  // border), and again at the pixel farthest from that one where the line runs on.
  const int clear = 14;
  for (std::size_t l = 0; l < onLevel.size(); ++l) {
    std::vector<std::pair<int, int>> candidates;
    for (auto [x, y] : onLevel[l])
      if (x > clear && y > clear && x < pw - clear && y < ph - clear) candidates.push_back({x, y});
    if (candidates.empty()) continue;
    const auto first = candidates[candidates.size() / 2];
    auto farthest = first;
    double farthestDistance = 0;
    for (auto p : candidates) {
      const double d = std::hypot(p.first - first.first, p.second - first.second);
      if (d > farthestDistance) farthestDistance = d, farthest = p;
    }
    const std::string text = formatValue(out.isoluxLevels[l]);
    canvas.label(planeLeft + first.first, planeTop + first.second, text, 1 + (pw >= 400));
    if (farthestDistance > std::max(pw, ph) / 3.0) canvas.label(planeLeft + farthest.first, planeTop + farthest.second, text, 1 + (pw >= 400));
  }
  // A frame round the plane, and the axes: ticks and values along the bottom and the left side.
  canvas.line(planeLeft - 1, planeTop - 1, planeLeft + pw, planeTop - 1, 1, kBlack);
  canvas.line(planeLeft - 1, planeTop + ph, planeLeft + pw, planeTop + ph, 1, kBlack);
  canvas.line(planeLeft - 1, planeTop - 1, planeLeft - 1, planeTop + ph, 1, kBlack);
  canvas.line(planeLeft + pw, planeTop - 1, planeLeft + pw, planeTop + ph, 1, kBlack);
  for (auto [value, f] : across.ticks) {
    const int x = planeLeft + static_cast<int>(std::lround(f * pw));
    canvas.fill(x, planeTop + ph, x + 1, planeTop + ph + 6, kBlack);
    const std::string s = formatMetres(value);
    canvas.text(x - Canvas::textWidth(s, scale) / 2, planeTop + ph + 9, s, scale, kBlack);
  }
  canvas.text(planeLeft + pw / 2 - Canvas::textWidth(across.name, scale) / 2, planeTop + ph + 9 + lineHeight, across.name, scale, kBlack);
  for (auto [value, f] : upward.ticks) {
    const int y = planeTop + ph - static_cast<int>(std::lround(f * ph));
    canvas.fill(planeLeft - 7, y, planeLeft - 1, y + 1, kBlack);
    const std::string s = formatMetres(value);
    canvas.text(planeLeft - 9 - Canvas::textWidth(s, scale), y - 6, s, scale, kBlack);
  }
  // The vertical axis's name, written letter above letter beside the labels.
  for (std::size_t c = 0; c < upward.name.size(); ++c)
    canvas.text(margin - 4, planeTop + ph / 2 - static_cast<int>(upward.name.size()) * 7 + static_cast<int>(c) * 14, upward.name.substr(c, 1), scale,
                kBlack);
  // Luminaires on a plan: a ring at the point under (or over) each, a stroke along its aim's
  // horizontal part, its label.
  if (page.plan)
    for (const PlanLuminaire& l : options.luminaires) {
      const auto [px, py] = out.pixelOf(l.position);
      if (px < planeLeft - 8 || py < planeTop - 8 || px > planeLeft + pw + 8 || py > planeTop + ph + 8) continue;
      canvas.ring(px, py, 7, 4, kWhite);
      canvas.ring(px, py, 7, 2, kBlack);
      const Vec3 aim = normalize(l.aim);
      const double ax = dot(aim, page.right), ay = -dot(aim, page.up), sideways = std::hypot(ax, ay);
      if (sideways > 0.02) {
        const double reach = 7 + 18 * sideways;
        canvas.line(px, py, px + ax / sideways * reach, py + ay / sideways * reach, 2, kBlack);
      } else {
        canvas.fill(static_cast<int>(px) - 1, static_cast<int>(py) - 1, static_cast<int>(px) + 2, static_cast<int>(py) + 2, kBlack);
      }
      if (!l.label.empty()) canvas.label(px + 12 + Canvas::textWidth(l.label, scale) / 2.0, py - 14, l.label, scale);
    }
  // Title: the name, then the statistics.
  canvas.text(margin, margin / 2, title, scale, kBlack);
  canvas.text(margin, margin / 2 + lineHeight, figures, scale, kBlack);
  // A plan's north arrow, above the legend.
  const int legendX = planeLeft + pw + margin;
  if (page.plan) {
    const Vec3 north = normalize(Vec3{options.north.x, 0, options.north.z});
    const double nx = dot(north, page.right), ny = -dot(north, page.up);
    const double cx = legendX + 40, cy = planeTop + 50, r = 30;
    canvas.ring(cx, cy, r, 1, kBlack);
    canvas.line(cx - nx * r * 0.8, cy - ny * r * 0.8, cx + nx * r, cy + ny * r, 3, kBlack);
    const double hx = -ny, hy = nx;  // across the arrow
    canvas.line(cx + nx * r, cy + ny * r, cx + nx * r * 0.55 + hx * 9, cy + ny * r * 0.55 + hy * 9, 3, kBlack);
    canvas.line(cx + nx * r, cy + ny * r, cx + nx * r * 0.55 - hx * 9, cy + ny * r * 0.55 - hy * 9, 3, kBlack);
    canvas.label(cx + nx * (r + 14), cy + ny * (r + 14), "N", scale);
  }
  // Legend: the colour bar from 0 (bottom) to the top of the scale, its levels marked.
  const int barX = legendX, barTop = planeTop + arrowHeight, barHeight = std::max(ph - arrowHeight, 120), barWidth = 24;
  for (int y = 0; y < barHeight && barTop + y < canvas.height; ++y)
    canvas.fill(barX, barTop + y, barX + barWidth, barTop + y + 1, turboColour(1 - (y + 0.5) / barHeight));
  std::vector<double> labels = out.isoluxLevels;
  labels.insert(labels.begin(), 0.0);
  labels.push_back(top);
  for (double level : labels) {
    const int y = barTop + static_cast<int>(std::lround((1 - level / top) * (barHeight - 1)));
    canvas.fill(barX + barWidth, y, barX + barWidth + 6, y + 1, kBlack);
    canvas.text(barX + barWidth + 9, y - 5, formatValue(level) + unit, scale, kBlack);
  }
  out.width = canvas.width;
  out.height = canvas.height;
  out.rgb = std::move(canvas.rgb);
  return out;
}

}  // namespace lambert
