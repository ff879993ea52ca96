#include "lambert/bake/adaptive_texels.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace lambert {
namespace {

constexpr std::uint32_t kNoTexel = std::numeric_limits<std::uint32_t>::max();
// Corners (and the texels between them) lie on one plane where their faces' normals agree to
// this: a bend between two faces of one surface is a crease the light need not follow linearly.
constexpr double kSamePlaneCosine = 0.999;

enum : std::uint8_t { kUnknown = 0, kInterpolated = 1, kGathered = 2 };

// A cell's fate: interpolated, or halved because its corners and centre do not lie on one plane
// of one surface, or because the light there is not what they interpolate.
enum class Verdict : std::uint8_t { kSplitBySurface, kSmooth, kSplitByLight };

struct Cell {
  std::uint32_t atlas;
  int x0, y0;
};

}  // namespace

Result<std::vector<Rgb>> adaptiveTexelValues(const LightmapTexels& texels, int size, int numAtlases, const TexelGather& gather,
                                             const AdaptiveTexelOptions& options, AdaptiveTexelStats* stats) {
  const int coarsest = options.coarsestStep;
  if (coarsest < 1 || (coarsest & (coarsest - 1)) != 0)
    return Error{"lightmap sampling: the coarsest step must be a power of two (it is " + std::to_string(coarsest) + ")"};
  const std::size_t n = texels.points.size();
  const std::uint64_t perAtlas = static_cast<std::uint64_t>(size) * size;
  std::vector<std::uint32_t> at(perAtlas * static_cast<std::uint64_t>(numAtlases), kNoTexel);
  for (std::size_t t = 0; t < n; ++t) at[texels.atlas[t] * perAtlas + texels.texel[t]] = static_cast<std::uint32_t>(t);
  const auto texelAt = [&](std::uint32_t atlas, int x, int y) {
    if (x < 0 || y < 0 || x >= size || y >= size) return kNoTexel;
    return at[atlas * perAtlas + static_cast<std::uint64_t>(y) * size + x];
  };
  const auto samePlane = [&](std::uint32_t a, std::uint32_t b) {
    return texels.points[a].surface == texels.points[b].surface &&
           dot(texels.points[a].normal, texels.points[b].normal) >= kSamePlaneCosine;
  };

  std::vector<Rgb> value(n);
  std::vector<std::uint8_t> state(n, kUnknown);
  AdaptiveTexelStats counts;
  counts.texels = n;
  // Gathers those of `asked` not gathered yet.
  const auto gatherAt = [&](const std::vector<std::uint32_t>& asked) -> Status {
    std::vector<std::uint32_t> batch;
    for (std::uint32_t t : asked)
      if (t != kNoTexel && state[t] != kGathered) {
        state[t] = kGathered;  // now, so that a texel two cells share enters the batch once
        batch.push_back(t);
      }
    if (batch.empty()) return Ok{};
    Result<std::vector<Rgb>> got = gather(batch);
    if (!got) return got.error();
    LAMBERT_CHECK(got->size() == batch.size());
    for (std::size_t i = 0; i < batch.size(); ++i) value[batch[i]] = (*got)[i];
    counts.gathered += batch.size();
    ++counts.passes;
    return Ok{};
  };

  // The coarsest cells that hold a texel.
  std::vector<Cell> cells;
  {
    const std::uint64_t perSide = static_cast<std::uint64_t>((size + coarsest - 1) / coarsest);
    std::vector<std::uint64_t> keys(n);
    for (std::size_t t = 0; t < n; ++t)
      keys[t] = (texels.atlas[t] * perSide + texels.texel[t] / size / coarsest) * perSide + texels.texel[t] % size / coarsest;
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    for (std::uint64_t k : keys)
      cells.push_back({static_cast<std::uint32_t>(k / (perSide * perSide)), static_cast<int>(k % perSide) * coarsest,
                       static_cast<int>(k / perSide % perSide) * coarsest});
  }
  // Whether the cell holds a texel whose state is below `valued`.
  const auto holdsBelow = [&](const Cell& c, int step, std::uint8_t valued) {
    for (int y = c.y0; y < c.y0 + step; ++y)
      for (int x = c.x0; x < c.x0 + step; ++x)
        if (const std::uint32_t t = texelAt(c.atlas, x, y); t != kNoTexel && state[t] < valued) return true;
    return false;
  };
  // Whether b lies within the tolerance of a, channel by channel, relative to `scale`.
  double floor = -1;  // floorShare × the first lattice's mean, set after its gather
  const auto agree = [&](const Rgb& a, const Rgb& b, double scale) {
    const double allowed = options.tolerance * std::fmax(scale, floor);
    return std::fabs(a.r - b.r) <= allowed && std::fabs(a.g - b.g) <= allowed && std::fabs(a.b - b.b) <= allowed;
  };

  for (int step = coarsest; !cells.empty(); step /= 2) {
    std::vector<std::uint32_t> corners;
    for (const Cell& c : cells)
      for (int k = 0; k < 4; ++k) corners.push_back(texelAt(c.atlas, c.x0 + (k & 1) * step, c.y0 + (k >> 1) * step));
    if (Status s = gatherAt(corners); !s) return s.error();
    if (floor < 0) {
      double mean = 0;
      std::size_t count = 0;
      for (std::uint32_t t : corners)
        if (t != kNoTexel) mean += value[t].maxComponent(), ++count;
      floor = options.floorShare * (count ? mean / static_cast<double>(count) : 0.0);
    }
    if (step == 1) break;  // every texel of a one-texel cell is its corner, gathered above
    // The cells whose corners and probes (the centre and the edges' midpoints: the halves'
    // corners, should the cell be halved) lie on one plane of one surface; then the probes' light
    // against what the corners interpolate there.
    const int h = step / 2;
    constexpr int kProbes = 5;
    const int probeX[kProbes] = {h, h, 0, step, h}, probeY[kProbes] = {h, 0, h, h, step};
    std::vector<Verdict> verdict(cells.size(), Verdict::kSplitBySurface);
    std::vector<std::uint32_t> probeTexels;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const std::uint32_t* corner = &corners[4 * i];
      bool onePlane = corner[0] != kNoTexel;
      for (int k = 0; k < 4 && onePlane; ++k) onePlane = corner[k] != kNoTexel && samePlane(corner[0], corner[k]);
      for (int k = 0; k < kProbes && onePlane; ++k) {
        const std::uint32_t p = texelAt(cells[i].atlas, cells[i].x0 + probeX[k], cells[i].y0 + probeY[k]);
        onePlane = p != kNoTexel && samePlane(corner[0], p);
      }
      if (!onePlane) continue;
      verdict[i] = Verdict::kSmooth;
      for (int k = 0; k < kProbes; ++k) probeTexels.push_back(texelAt(cells[i].atlas, cells[i].x0 + probeX[k], cells[i].y0 + probeY[k]));
    }
    if (Status s = gatherAt(probeTexels); !s) return s.error();
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (verdict[i] != Verdict::kSmooth) continue;
      const Cell& c = cells[i];
      const std::uint32_t* corner = &corners[4 * i];
      bool fits = true;
      for (int k = 0; k < kProbes && fits; ++k) {
        const double fx = static_cast<double>(probeX[k]) / step, fy = static_cast<double>(probeY[k]) / step;
        const Rgb predicted = value[corner[0]] * ((1 - fx) * (1 - fy)) + value[corner[1]] * (fx * (1 - fy)) +
                              value[corner[2]] * ((1 - fx) * fy) + value[corner[3]] * (fx * fy);
        const Rgb& seen = value[texelAt(c.atlas, c.x0 + probeX[k], c.y0 + probeY[k])];
        fits = agree(predicted, seen, std::fmax(predicted.maxComponent(), seen.maxComponent()));
      }
      if (!fits) {
        verdict[i] = Verdict::kSplitByLight;
        continue;
      }
      // Bilinear between the corners over the closed cell: a texel on an edge two smooth cells
      // share gets the same value from either (the edge's two corners alone weigh it).
      for (int y = c.y0; y <= c.y0 + step; ++y)
        for (int x = c.x0; x <= c.x0 + step; ++x) {
          const std::uint32_t t = texelAt(c.atlas, x, y);
          if (t == kNoTexel || state[t] == kGathered || !samePlane(corner[0], t)) continue;
          const double fx = static_cast<double>(x - c.x0) / step, fy = static_cast<double>(y - c.y0) / step;
          value[t] = value[corner[0]] * ((1 - fx) * (1 - fy)) + value[corner[1]] * (fx * (1 - fy)) +
                     value[corner[2]] * ((1 - fx) * fy) + value[corner[3]] * (fx * fy);
          state[t] = kInterpolated;
        }
    }
    // The other cells halved. Where the light split a cell, its edges too are taken again at the
    // finer step (a smooth neighbour interpolated them without what this cell saw); where only
    // the surfaces did, the halves that hold texels without a value (a chart's last row and
    // column lie on its smooth cells' closed edges).
    std::vector<Cell> finer;
    const int half = step / 2;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (verdict[i] == Verdict::kSmooth) continue;
      const std::uint8_t valued = verdict[i] == Verdict::kSplitByLight ? kGathered : kInterpolated;
      for (int k = 0; k < 4; ++k) {
        const Cell sub{cells[i].atlas, cells[i].x0 + (k & 1) * half, cells[i].y0 + (k >> 1) * half};
        if (holdsBelow(sub, half, valued)) finer.push_back(sub);
      }
    }
    cells = std::move(finer);
  }
  // Texels no smooth cell of their own plane reached (another surface's texel inside a cell).
  std::vector<std::uint32_t> rest;
  for (std::size_t t = 0; t < n; ++t)
    if (state[t] == kUnknown) rest.push_back(static_cast<std::uint32_t>(t));
  if (Status s = gatherAt(rest); !s) return s.error();
  counts.interpolated = n - counts.gathered;
  if (stats) *stats = counts;
  return value;
}

}  // namespace lambert
