#include "lambert/mesh/uv_packing.h"

// Each chart is a rectangle of whole texels: its footprint at the texel size (the
// texels its bounding box reaches) with paddingTexels more in each direction, the footprint
// ⌈padding / 2⌉ in from the rectangle's low sides. Any two charts' footprints are then
// paddingTexels apart, and each is ⌈padding / 2⌉ from the atlas's edges: every chart has at
// least half the padding of its own on every side for dilation (bilinear filtering reads one
// texel beyond a footprint), also where the atlas repeats. Rectangles are placed tallest first on a skyline, each at the lowest, then leftmost, place
// in either orientation (Jylänki 2010, "A thousand ways to pack the bin", SKYLINE-BL).
//
// Cost: O(charts × skyline segments) per packing; the automatic texel size packs about a dozen
// times.
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace lambert {
namespace {

// The skyline of one atlas: segments (x, y, width) left to right, y the top of what is placed
// below them (y grows down the atlas).
class Skyline {
 public:
  explicit Skyline(int size) : size_(size) { segments_.push_back({0, 0, size}); }

  // The lowest, then leftmost, place for a w × h rectangle in either orientation.
  bool place(int w, int h, int& x, int& y, bool& rotated) {
    int bestTop = INT32_MAX, bestX = 0, bestY = 0;
    std::size_t bestIndex = 0;
    bool bestRotated = false;
    for (int turn = 0; turn < (w == h ? 1 : 2); ++turn) {
      const int rw = turn ? h : w, rh = turn ? w : h;
      for (std::size_t i = 0; i < segments_.size(); ++i) {
        int top;
        if (!fits(i, rw, rh, top)) continue;
        if (top + rh < bestTop || (top + rh == bestTop && segments_[i].x < bestX)) {
          bestTop = top + rh, bestX = segments_[i].x, bestY = top, bestIndex = i, bestRotated = turn;
        }
      }
    }
    if (bestTop == INT32_MAX) return false;
    x = bestX, y = bestY, rotated = bestRotated;
    add(bestIndex, bestRotated ? h : w, bestY + (bestRotated ? w : h));
    return true;
  }

 private:
  struct Segment {
    int x, y, width;
  };
  bool fits(std::size_t i, int w, int h, int& top) const {
    if (segments_[i].x + w > size_) return false;
    int left = w;
    top = 0;
    for (std::size_t j = i; left > 0; ++j) {
      top = std::max(top, segments_[j].y);
      if (top + h > size_) return false;
      left -= segments_[j].width;
    }
    return true;
  }
  void add(std::size_t i, int w, int top) {
    const int x = segments_[i].x;
    segments_.insert(segments_.begin() + static_cast<std::ptrdiff_t>(i), {x, top, w});
    for (std::size_t j = i + 1; j < segments_.size();) {
      Segment& s = segments_[j];
      if (s.x >= x + w) break;
      const int cut = x + w - s.x;
      if (cut >= s.width) {
        segments_.erase(segments_.begin() + static_cast<std::ptrdiff_t>(j));
        continue;
      }
      s.x += cut, s.width -= cut;
      break;
    }
    for (std::size_t j = 0; j + 1 < segments_.size();) {
      if (segments_[j].y == segments_[j + 1].y) {
        segments_[j].width += segments_[j + 1].width;
        segments_.erase(segments_.begin() + static_cast<std::ptrdiff_t>(j + 1));
      } else {
        ++j;
      }
    }
  }
  int size_;
  std::vector<Segment> segments_;
};

}  // namespace

int footprint(double extent, double texelSize) {
  const double texels = extent / texelSize;
  return std::max(1, static_cast<int>(std::ceil(texels - 1e-9)));
}

bool pack(const std::vector<Chart>& charts, double texelSize, int size, int padding, std::size_t maxAtlases,
          std::vector<Placement>& placements, std::size_t& numAtlases, PackOrder order, bool scaleDown) {
  const int usable = size - padding % 2;  // the high sides keep ⌈padding / 2⌉ as the low ones
  if (usable - padding < 1) return false;
  struct Rect {
    int w, h;
    std::uint32_t chart;
  };
  std::vector<Rect> rects(charts.size());
  placements.assign(charts.size(), {});
  for (std::uint32_t c = 0; c < charts.size(); ++c) {
    double scale = 1;
    // A chart wider than an atlas is scaled down to fit (warned about by the caller).
    if (charts[c].width / texelSize > usable - padding) {
      if (!scaleDown) return false;
      scale = (usable - padding) / (charts[c].width / texelSize) * (1 - 1e-9);
    }
    placements[c].scale = scale;
    rects[c] = {footprint(charts[c].width * scale, texelSize) + padding, footprint(charts[c].height * scale, texelSize) + padding, c};
  }
  auto key = [order](const Rect& r) {
    const std::int64_t lo = std::min(r.w, r.h), hi = std::max(r.w, r.h);
    return order == PackOrder::ShortSide ? std::pair{lo, hi} : order == PackOrder::Area ? std::pair{lo * hi, hi} : std::pair{hi, lo};
  };
  std::stable_sort(rects.begin(), rects.end(), [&](const Rect& a, const Rect& b) { return key(a) > key(b); });
  std::vector<Skyline> atlases;
  for (const Rect& r : rects) {
    Placement& p = placements[r.chart];
    bool placed = false;
    // First fit over the last few atlases opened (the earlier ones are full but for slivers).
    for (std::size_t a = atlases.size() > 4 ? atlases.size() - 4 : 0; a < atlases.size() && !placed; ++a)
      if (atlases[a].place(r.w, r.h, p.x, p.y, p.rotated)) p.atlas = static_cast<std::uint32_t>(a), placed = true;
    if (placed) continue;
    if (atlases.size() >= maxAtlases) return false;
    atlases.emplace_back(usable);
    if (!atlases.back().place(r.w, r.h, p.x, p.y, p.rotated)) return false;
    p.atlas = static_cast<std::uint32_t>(atlases.size() - 1);
  }
  numAtlases = std::max<std::size_t>(atlases.size(), 1);
  return true;
}

double fittingTexelSize(const std::vector<Chart>& charts, double area, int size, int padding, PackOrder* fittingOrder) {
  std::vector<Placement> placements;
  std::size_t numAtlases = 0;
  PackOrder found = PackOrder::ShortSide;
  auto fits = [&](double t) {
    for (PackOrder order : kPackOrders)
      if (pack(charts, t, size, padding, 1, placements, numAtlases, order, false)) {
        found = order;
        return true;
      }
    return false;
  };
  double lo = std::sqrt(area / (static_cast<double>(size) * size));  // all texels covered: no smaller
  double hi = lo * 1.25;
  for (int k = 0; !fits(hi); ++k) {
    if (k == 40) return 0;
    lo = hi, hi *= 2;
  }
  PackOrder atHi = found;
  while (hi > lo * 1.002) {
    const double mid = std::sqrt(lo * hi);
    if (fits(mid)) hi = mid, atHi = found;
    else lo = mid;
  }
  if (fittingOrder) *fittingOrder = atHi;
  return hi;
}

}  // namespace lambert
