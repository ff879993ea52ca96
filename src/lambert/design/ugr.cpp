#include "lambert/design/ugr.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "lambert/core/photometric.h"
#include "lambert/core/rgb.h"
#include "lambert/light/lights.h"

namespace lambert {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDegree = kPi / 180;

// CIE 117-1995 Table 4.1: Guth's position index, rows T/R = 0, 0.1, …, 3.0, columns H/R = 0, 0.1,
// …, 1.9; NaN where the table is blank (high above the line of sight: outside the field of view).
// T/R = 2.7, H/R = 0.6 reads 7.50 in the published table (its neighbours suggest 7.05); kept as
// published, as the tools that follow the standard keep it.
constexpr int kGuthRows = 31, kGuthColumns = 20;
constexpr double kGuth[kGuthRows][kGuthColumns] = {
    {1.00, 1.26, 1.53, 1.90, 2.35, 2.86, 3.50, 4.20, 5.00, 6.00, 7.00, 8.10, 9.25, 10.35, 11.70, 13.15, 14.70, 16.20, kNaN, kNaN},
    {1.05, 1.22, 1.46, 1.80, 2.20, 2.75, 3.40, 4.10, 4.80, 5.80, 6.80, 8.00, 9.10, 10.30, 11.60, 13.00, 14.60, 16.10, kNaN, kNaN},
    {1.12, 1.30, 1.50, 1.80, 2.20, 2.66, 3.18, 3.88, 4.60, 5.50, 6.50, 7.60, 8.75, 9.85, 11.20, 12.70, 14.00, 15.70, kNaN, kNaN},
    {1.22, 1.38, 1.60, 1.97, 2.25, 2.70, 3.25, 3.90, 4.60, 5.45, 6.45, 7.40, 8.40, 9.50, 10.85, 12.10, 13.70, 15.00, kNaN, kNaN},
    {1.32, 1.47, 1.70, 1.96, 2.35, 2.80, 3.30, 3.90, 4.60, 5.40, 6.40, 7.30, 8.30, 9.40, 10.60, 11.90, 13.20, 14.60, 16.00, kNaN},
    {1.43, 1.60, 1.82, 2.10, 2.48, 2.91, 3.40, 3.98, 4.70, 5.50, 6.40, 7.30, 8.30, 9.40, 10.50, 11.75, 13.00, 14.40, 15.70, kNaN},
    {1.55, 1.72, 1.98, 2.30, 2.65, 3.10, 3.60, 4.10, 4.80, 5.50, 6.40, 7.35, 8.40, 9.40, 10.50, 11.70, 13.00, 14.10, 15.40, kNaN},
    {1.70, 1.88, 2.12, 2.48, 2.87, 3.30, 3.78, 4.30, 4.88, 5.60, 6.50, 7.40, 8.50, 9.50, 10.50, 11.70, 12.85, 14.00, 15.20, kNaN},
    {1.82, 2.00, 2.32, 2.70, 3.08, 3.50, 3.92, 4.50, 5.10, 5.75, 6.60, 7.50, 8.60, 9.50, 10.60, 11.75, 12.80, 14.00, 15.10, kNaN},
    {1.96, 2.20, 2.54, 2.90, 3.30, 3.70, 4.20, 4.75, 5.30, 6.00, 6.75, 7.70, 8.70, 9.65, 10.75, 11.80, 12.90, 14.00, 15.00, 16.00},
    {2.11, 2.40, 2.75, 3.10, 3.50, 3.91, 4.40, 5.00, 5.60, 6.20, 7.00, 7.90, 8.80, 9.75, 10.80, 11.90, 12.95, 14.00, 15.00, 16.00},
    {2.30, 2.55, 2.92, 3.30, 3.72, 4.20, 4.70, 5.25, 5.80, 6.55, 7.20, 8.15, 9.00, 9.90, 10.95, 12.00, 13.00, 14.00, 15.00, 16.00},
    {2.40, 2.75, 3.12, 3.50, 3.90, 4.35, 4.85, 5.50, 6.05, 6.70, 7.50, 8.30, 9.20, 10.00, 11.02, 12.10, 13.10, 14.00, 15.00, 16.00},
    {2.55, 2.90, 3.30, 3.70, 4.20, 4.65, 5.20, 5.70, 6.30, 7.00, 7.70, 8.55, 9.35, 10.20, 11.20, 12.25, 13.20, 14.00, 15.00, 16.00},
    {2.70, 3.10, 3.50, 3.90, 4.35, 4.85, 5.35, 5.85, 6.50, 7.25, 8.00, 8.70, 9.50, 10.40, 11.40, 12.40, 13.25, 14.05, 15.00, 16.00},
    {2.85, 3.15, 3.65, 4.10, 4.55, 5.00, 5.50, 6.20, 6.80, 7.50, 8.20, 8.85, 9.70, 10.55, 11.50, 12.50, 13.30, 14.05, 15.02, 16.00},
    {2.95, 3.40, 3.80, 4.25, 4.75, 5.20, 5.75, 6.30, 7.00, 7.65, 8.40, 9.00, 9.80, 10.80, 11.75, 12.60, 13.40, 14.20, 15.10, 16.00},
    {3.10, 3.55, 4.00, 4.50, 4.90, 5.40, 5.95, 6.50, 7.20, 7.80, 8.50, 9.20, 10.00, 10.85, 11.85, 12.75, 13.45, 14.20, 15.10, 16.00},
    {3.25, 3.70, 4.20, 4.65, 5.10, 5.60, 6.10, 6.75, 7.40, 8.00, 8.65, 9.35, 10.10, 11.00, 11.90, 12.80, 13.50, 14.20, 15.10, 16.00},
    {3.43, 3.86, 4.30, 4.75, 5.20, 5.70, 6.30, 6.90, 7.50, 8.17, 8.80, 9.50, 10.20, 11.00, 12.00, 12.82, 13.55, 14.20, 15.10, 16.00},
    {3.50, 4.00, 4.50, 4.90, 5.35, 5.80, 6.40, 7.10, 7.70, 8.30, 8.90, 9.60, 10.40, 11.10, 12.00, 12.85, 13.60, 14.30, 15.10, 16.00},
    {3.60, 4.17, 4.65, 5.05, 5.50, 6.00, 6.60, 7.20, 7.82, 8.45, 9.00, 9.75, 10.50, 11.20, 12.10, 12.90, 13.70, 14.35, 15.10, 16.00},
    {3.75, 4.25, 4.72, 5.20, 5.60, 6.10, 6.70, 7.35, 8.00, 8.55, 9.15, 9.85, 10.60, 11.30, 12.10, 12.90, 13.70, 14.40, 15.15, 16.00},
    {3.85, 4.35, 4.80, 5.25, 5.70, 6.22, 6.80, 7.40, 8.10, 8.65, 9.30, 9.90, 10.70, 11.40, 12.20, 12.95, 13.70, 14.40, 15.20, 16.00},
    {3.95, 4.40, 4.90, 5.35, 5.80, 6.30, 6.90, 7.50, 8.20, 8.80, 9.40, 10.00, 10.80, 11.50, 12.25, 13.00, 13.75, 14.45, 15.20, 16.00},
    {4.00, 4.50, 4.96, 5.40, 5.85, 6.40, 6.95, 7.55, 8.25, 8.85, 9.50, 10.05, 10.85, 11.55, 12.30, 13.00, 13.80, 14.50, 15.25, 16.00},
    {4.07, 4.55, 5.05, 5.47, 5.95, 6.46, 7.00, 7.65, 8.35, 8.95, 9.55, 10.10, 10.90, 11.60, 12.32, 13.00, 13.80, 14.50, 15.25, 16.00},
    {4.10, 4.60, 5.10, 5.53, 6.00, 6.50, 7.50, 7.70, 8.40, 9.00, 9.60, 10.16, 10.92, 11.63, 12.35, 13.00, 13.80, 14.50, 15.25, 16.00},
    {4.15, 4.62, 5.15, 5.56, 6.05, 6.55, 7.08, 7.73, 8.45, 9.05, 9.65, 10.20, 10.95, 11.65, 12.35, 13.00, 13.80, 14.50, 15.25, 16.00},
    {4.20, 4.65, 5.17, 5.60, 6.07, 6.57, 7.12, 7.75, 8.50, 9.10, 9.70, 10.23, 10.95, 11.65, 12.35, 13.00, 13.80, 14.50, 15.25, 16.00},
    {4.22, 4.67, 5.20, 5.65, 6.12, 6.60, 7.15, 7.80, 8.55, 9.12, 9.70, 10.23, 10.95, 11.65, 12.35, 13.00, 13.80, 14.50, 15.25, 16.00},
};

// The exact form factor between two directly opposed parallel a × b rectangles a distance c
// apart (Howell's catalogue, C-11).
double parallelRectanglesFactor(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double x1 = std::sqrt(1 + x * x), y1 = std::sqrt(1 + y * y);
  return 2 / (kPi * x * y) *
         (std::log(x1 * y1 / std::sqrt(1 + x * x + y * y)) + x * y1 * std::atan(x / y1) + y * x1 * std::atan(y / x1) -
          x * std::atan(x) - y * std::atan(y));
}

// Gaussian elimination with partial pivoting of a 3 × 3 system.
std::array<double, 3> solve3(std::array<std::array<double, 3>, 3> a, std::array<double, 3> b) {
  for (int i = 0; i < 3; ++i) {
    int pivot = i;
    for (int r = i + 1; r < 3; ++r)
      if (std::fabs(a[r][i]) > std::fabs(a[pivot][i])) pivot = r;
    std::swap(a[i], a[pivot]);
    std::swap(b[i], b[pivot]);
    for (int r = 0; r < 3; ++r) {
      if (r == i) continue;
      const double f = a[r][i] / a[i][i];
      for (int c = i; c < 3; ++c) a[r][c] -= f * a[i][c];
      b[r] -= f * b[i];
    }
  }
  return {b[0] / a[0][0], b[1] / a[1][1], b[2] / a[2][2]};
}

// The flux the array sends onto the reference plane, from a grid of the distribution's directions.
struct DirectionCell {
  double flux;            // lm in the cell (I sin γ Δγ ΔC)
  double tanCos, tanSin;  // tan γ cos C, tan γ sin C: the horizontal offset of its ray per unit drop
};

struct DistributionGrid {
  std::vector<DirectionCell> downward;  // γ < 90°
  double downwardFlux = 0, upwardFlux = 0;
};

// Midpoint rule over 0.5° × 1° cells of the sphere (the flux integral Photometry uses).
DistributionGrid distributionGrid(const Photometry& p) {
  constexpr int kGamma = 360, kC = 360;
  const double dGamma = kPi / kGamma, dC = 2 * kPi / kC;
  DistributionGrid grid;
  grid.downward.reserve(kGamma / 2 * kC);
  for (int g = 0; g < kGamma; ++g) {
    const double gamma = (g + 0.5) * dGamma;
    const double solidAngle = std::sin(gamma) * dGamma * dC;
    for (int c = 0; c < kC; ++c) {
      const double cAngle = (c + 0.5) * dC;
      const double flux = p.candela(cAngle / kDegree, gamma / kDegree) * solidAngle;
      if (gamma < kPi / 2) {
        grid.downwardFlux += flux;
        const double t = std::tan(gamma);
        if (flux > 0) grid.downward.push_back({flux, t * std::cos(cAngle), t * std::sin(cAngle)});
      } else {
        grid.upwardFlux += flux;
      }
    }
  }
  return grid;
}

// How many of the positions first + k·step (k = 0..count−1) lie within [lo, hi].
int countWithin(double first, double step, int count, double lo, double hi) {
  const double eps = 1e-9 * step;
  const int from = std::max(0, static_cast<int>(std::ceil((lo - first - eps) / step)));
  const int to = std::min(count - 1, static_cast<int>(std::floor((hi - first + eps) / step)));
  return std::max(0, to - from + 1);
}

struct Array {
  int nx = 0, ny = 0;
  double spacing = 0, x0 = 0, y0 = 0;  // first positions: x across (centred on the observer), y along
};

Array standardArray(double x, double y, double spacing) {
  Array a;
  a.spacing = spacing;
  a.nx = static_cast<int>(std::floor(x / spacing + 1e-9));
  a.ny = static_cast<int>(std::floor(y / spacing + 1e-9));
  a.x0 = -(a.nx - 1) * spacing / 2;
  a.y0 = y / 2 - (a.ny - 1) * spacing / 2;
  return a;
}

double lampFlux(const Photometry& p) { return p.lampLumens > 0 ? p.lampLumens : p.luminousFlux(); }

Result<UgrTableEntry> tableEntry(const Photometry& photometry, const DistributionGrid& grid, const UgrRoom& room,
                                 const UgrReflectances& reflectances, UgrViewing viewing, const UgrTableOptions& options) {
  const double h = options.heightAboveEye;
  if (!(h > 0) || !(options.spacingOverHeight > 0) || !(room.xOverH > 0) || !(room.yOverH > 0))
    return Error{"UGR table: the height, spacing and room sides must be positive"};
  const double phi = lampFlux(photometry);
  if (!(phi > 0)) return Error{"UGR table: the photometry of \"" + photometry.path + "\" has no luminous flux"};
  if (!(projectedLuminousArea(photometry, 0, 0) > 0) && !(projectedLuminousArea(photometry, 0, 90) > 0))
    return Error{"UGR table: the photometric file \"" + photometry.path +
                 "\" gives no luminous opening size; UGR needs the luminous area (its luminance)"};
  const double x = room.xOverH * h, y = room.yOverH * h, spacing = options.spacingOverHeight * h;
  const Array a = standardArray(x, y, spacing);
  if (a.nx < 1 || a.ny < 1) return Error{"UGR table: the spacing leaves the room without a luminaire"};
  const double scale = 1000 / phi;  // to the reference lamp flux Φ0 = 1000 lm

  // The luminaire's axes in the room (x across the line of sight, y along it, z up; the
  // luminaire aimed down, C counter-clockwise seen from above).
  const bool crosswise = viewing == UgrViewing::Crosswise;
  const Vec3 c0 = crosswise ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 c90 = crosswise ? Vec3{0, 1, 0} : Vec3{-1, 0, 0};

  UgrTableEntry e;
  e.luminaires = a.nx * a.ny;
  for (int i = 0; i < a.nx; ++i)
    for (int j = 0; j < a.ny; ++j) {
      const double lx = a.x0 + i * spacing, ly = a.y0 + j * spacing;
      const double r = ly, t = std::fabs(lx);
      const double p = guthPositionIndex(h / r, t / r);
      if (std::isnan(p)) continue;
      // From the luminaire to the eye (at the room's origin, h below).
      const Vec3 toEye = normalize(Vec3{-lx, -ly, -h});
      const double gamma = std::acos(std::clamp(-toEye.z, -1.0, 1.0)) / kDegree;
      double c = std::atan2(dot(toEye, c90), dot(toEye, c0)) / kDegree;
      if (c < 0) c += 360;
      const double area = projectedLuminousArea(photometry, c, gamma);
      if (!(area > 0)) continue;
      const double intensity = scale * photometry.candela(c, gamma);
      const double distanceSquared = lx * lx + ly * ly + h * h;
      // L² ω / p² = (I / A_p)² (A_p / r²) / p².
      e.glareSum += intensity * intensity / (area * distanceSquared * p * p);
      ++e.counted;
    }

  // The direct shares: a ray leaving a luminaire at (lx, ly) in direction (C, γ) meets the
  // reference plane h below at (lx, ly) + h tan γ (cos C c0 + sin C c90); count the luminaires whose
  // ray lands inside the room.
  double floorFlux = 0;
  for (const DirectionCell& d : grid.downward) {
    const double dx = h * (d.tanCos * c0.x + d.tanSin * c90.x), dy = h * (d.tanCos * c0.y + d.tanSin * c90.y);
    const int inX = countWithin(a.x0 + dx, spacing, a.nx, -x / 2, x / 2);
    if (inX == 0) continue;
    const int inY = countWithin(a.y0 + dy, spacing, a.ny, 0, y);
    floorFlux += d.flux * inX * inY;
  }
  e.directFloor = floorFlux / (e.luminaires * phi);
  e.directWalls = grid.downwardFlux / phi - e.directFloor;
  e.directCeiling = grid.upwardFlux / phi;
  const std::array<double, 3> transfer = ugrTransferFactors(x, y, h, reflectances);
  e.transferFloor = transfer[0];
  e.transferWalls = transfer[1];
  e.transferCeiling = transfer[2];
  const double wallArea = 2 * h * (x + y);
  const double b = 1000.0 * e.luminaires / wallArea;  // CIE 190 eq. 7, at Φ0 = 1000 lm
  const double indirectWall = b * (e.directFloor * e.transferFloor + e.directWalls * e.transferWalls + e.directCeiling * e.transferCeiling);
  e.backgroundLuminance = indirectWall / kPi;
  if (!(e.backgroundLuminance > 0)) return Error{"UGR table: no light reaches the walls indirectly (all reflectances zero?)"};
  e.ugr = 8 * std::log10(0.25 * e.glareSum / e.backgroundLuminance);
  return e;
}

}  // namespace

double guthPositionIndex(double heightOverDistance, double lateralOverDistance) {
  const double hr = std::fabs(heightOverDistance) * 10, tr = std::fabs(lateralOverDistance) * 10;
  if (!(hr <= kGuthColumns - 1 + 1e-9) || !(tr <= kGuthRows - 1 + 1e-9)) return kNaN;
  const int col = std::min(static_cast<int>(hr), kGuthColumns - 2), row = std::min(static_cast<int>(tr), kGuthRows - 2);
  const double u = std::clamp(hr - col, 0.0, 1.0), v = std::clamp(tr - row, 0.0, 1.0);
  // A corner that takes no weight does not matter even where the table is blank there.
  double sum = 0;
  const double weights[4] = {(1 - u) * (1 - v), u * (1 - v), (1 - u) * v, u * v};
  const double values[4] = {kGuth[row][col], kGuth[row][col + 1], kGuth[row + 1][col], kGuth[row + 1][col + 1]};
  for (int k = 0; k < 4; ++k) {
    if (weights[k] == 0) continue;
    if (std::isnan(values[k])) return kNaN;
    sum += weights[k] * values[k];
  }
  return sum;
}

double projectedLuminousArea(const Photometry& p, double cDegrees, double gammaDegrees) {
  const double length = std::fabs(p.openingLength), width = std::fabs(p.openingWidth), height = std::fabs(p.openingHeight);
  const double gamma = gammaDegrees * kDegree, c = cDegrees * kDegree;
  const double face = p.round ? kPi / 4 * length * width : length * width;
  double area = face * std::max(0.0, std::cos(gamma));
  if (height > 0) {
    // The sides seen from C: a box shows its faces across c0 (width × height) and across c90
    // (length × height); a cylinder (ellipse) its silhouette width across the view.
    const double sc = std::fabs(std::sin(c)), cc = std::fabs(std::cos(c));
    const double across = p.round ? std::sqrt(length * length * sc * sc + width * width * cc * cc) : width * cc + length * sc;
    area += height * across * std::fabs(std::sin(gamma));
  }
  return area;
}

double backgroundLuminanceFromIndirect(double indirectVerticalIlluminanceLux) { return indirectVerticalIlluminanceLux / kPi; }

Result<UgrResult> unifiedGlareRating(std::span<const Light> lights, double metresPerUnit, const UgrObserver& observer) {
  if (!(observer.backgroundLuminance > 0) || !std::isfinite(observer.backgroundLuminance))
    return Error{"UGR: the background luminance must be positive and finite (cd/m²), found " + std::to_string(observer.backgroundLuminance)};
  if (!(metresPerUnit > 0)) return Error{"UGR: metresPerUnit must be positive"};
  const Vec3 horizontal{observer.viewDirection.x, 0, observer.viewDirection.z};
  if (!(length(horizontal) > 1e-12)) return Error{"UGR: the view direction has no horizontal part (the line of sight is horizontal)"};
  const Vec3 ahead = normalize(horizontal);
  const Vec3 side = cross(ahead, Vec3{0, 1, 0});

  UgrResult result;
  result.backgroundLuminance = observer.backgroundLuminance;
  result.sources.resize(lights.size());
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const Light& light = lights[i];
    GlareSource& s = result.sources[i];
    if (light.kind != LightKind::Luminaire || !light.photometry) {
      s.status = GlareSourceStatus::NotALuminaire;
      continue;
    }
    const Vec3 d = (light.position - observer.eye) * metresPerUnit;
    s.distanceAhead = dot(d, ahead);
    s.lateral = std::fabs(dot(d, side));
    s.height = d.y;
    if (!(s.distanceAhead > 0)) {
      s.status = GlareSourceStatus::BehindObserver;
      continue;
    }
    if (s.height < 0) {
      s.status = GlareSourceStatus::BelowEyeLevel;
      continue;
    }
    s.positionIndex = guthPositionIndex(s.height / s.distanceAhead, s.lateral / s.distanceAhead);
    if (std::isnan(s.positionIndex)) {
      s.status = GlareSourceStatus::OutsideFieldOfView;
      continue;
    }
    const Photometry& p = *light.photometry;
    if (!(projectedLuminousArea(p, 0, 0) > 0) && !(projectedLuminousArea(p, 0, 90) > 0))
      return Error{"UGR: luminaire \"" + light.name + "\" (light " + std::to_string(i) + ", file \"" + p.path +
                   "\") is in the field of view but its photometric file gives no luminous opening size; UGR needs "
                   "its luminous area (give the file the luminaire's dimensions)"};
    const double distance = length(d);
    const Vec3 outward = d / -distance;  // from the luminaire to the eye
    double c = 0, gamma = 0;
    photometricAngles(luminaireFrame(light), outward, c, gamma);
    s.projectedArea = projectedLuminousArea(p, c, gamma);
    if (!(s.projectedArea > 0)) {
      s.status = GlareSourceStatus::NotVisible;
      continue;
    }
    // The photometric intensity: the light's W/sr back to cd through the luminance weights, as
    // the lux of its irradiance are (core/photometric.h).
    s.candela = kLumensPerWatt * luminaireIntensity(light, outward).luminance();
    s.luminance = s.candela / s.projectedArea;
    s.solidAngle = s.projectedArea / (distance * distance);
    s.status = GlareSourceStatus::Counted;
    result.glareSum += s.term();
    if (s.solidAngle < 3e-4 || s.solidAngle > 0.1) ++result.outsideValidityRange;
  }
  result.ugr = result.glareSum > 0 ? 8 * std::log10(0.25 * result.glareSum / observer.backgroundLuminance)
                                   : -std::numeric_limits<double>::infinity();
  return result;
}

std::array<double, 3> ugrTransferFactors(double x, double y, double h, const UgrReflectances& rho) {
  const double floorArea = x * y, wallArea = 2 * h * (x + y);
  const double fFC = parallelRectanglesFactor(x, y, h);  // floor → ceiling = ceiling → floor
  const double fFW = 1 - fFC;
  const double fWF = floorArea * fFW / wallArea;  // reciprocity; walls → ceiling the same
  const double fWW = 1 - 2 * fWF;
  // Surfaces 0 floor, 1 walls, 2 ceiling; factor[i][j] from i to j. The flux each receives,
  // Φ_j = Φ0_j + Σ_i ρ_i Φ_i F_ij.
  const double factor[3][3] = {{0, fFW, fFC}, {fWF, fWW, fWF}, {fFC, fFW, 0}};
  const double reflectance[3] = {rho.floor, rho.walls, rho.ceiling};
  std::array<std::array<double, 3>, 3> m{};
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) m[j][i] = (i == j ? 1.0 : 0.0) - reflectance[i] * factor[i][j];
  std::array<double, 3> t{};
  for (int k = 0; k < 3; ++k) {
    std::array<double, 3> first{};
    first[k] = 1;
    const std::array<double, 3> received = solve3(m, first);
    t[k] = received[1] - first[1];  // what the walls receive beyond the first flux
  }
  return t;
}

Result<UgrTableEntry> ugrTableEntry(const Photometry& photometry, const UgrRoom& room, const UgrReflectances& reflectances,
                                    UgrViewing viewing, const UgrTableOptions& options) {
  return tableEntry(photometry, distributionGrid(photometry), room, reflectances, viewing, options);
}

Result<UgrTable> ugrTable(const Photometry& photometry, const UgrTableOptions& options) {
  const DistributionGrid grid = distributionGrid(photometry);
  UgrTable table;
  table.lampLumens = lampFlux(photometry);
  for (int v = 0; v < 2; ++v)
    for (std::size_t r = 0; r < kUgrTableRooms.size(); ++r)
      for (std::size_t k = 0; k < kUgrTableReflectances.size(); ++k) {
        Result<UgrTableEntry> e = tableEntry(photometry, grid, kUgrTableRooms[r], kUgrTableReflectances[k], static_cast<UgrViewing>(v), options);
        if (!e) return e.error();
        table.uncorrected[v][r][k] = e->ugr;
      }
  table.fluxCorrection = 8 * std::log10(table.lampLumens / 1000);
  return table;
}

}  // namespace lambert
