#include "lambert/mesh/uv_overlap_grid.h"

#include <algorithm>
#include <cmath>

namespace lambert {
namespace {

// Whether two triangles' interiors overlap by more than `tolerance` (a separating-axis test over
// the six edge normals: touching along an edge or at a corner is no overlap). Either winding.
bool trianglesOverlap(const Vec2* a, const Vec2* b, double tolerance) {
  for (int which = 0; which < 2; ++which) {
    const Vec2* t = which == 0 ? a : b;
    for (int e = 0; e < 3; ++e) {
      const Vec2 d = t[(e + 1) % 3] - t[e];
      const double len = std::hypot(d.x, d.y);
      if (!(len > 0)) continue;
      const Vec2 axis{-d.y / len, d.x / len};
      double aLo = INFINITY, aHi = -INFINITY, bLo = INFINITY, bHi = -INFINITY;
      for (int k = 0; k < 3; ++k) {
        const double pa = axis.x * a[k].x + axis.y * a[k].y, pb = axis.x * b[k].x + axis.y * b[k].y;
        aLo = std::min(aLo, pa), aHi = std::max(aHi, pa), bLo = std::min(bLo, pb), bHi = std::max(bHi, pb);
      }
      if (aHi - bLo <= tolerance || bHi - aLo <= tolerance) return false;
    }
  }
  return true;
}

}  // namespace

template <class F>
void OverlapGrid::forCells(const Vec2* t, F&& f) {
  double xl = std::min({t[0].x, t[1].x, t[2].x}), xh = std::max({t[0].x, t[1].x, t[2].x});
  double yl = std::min({t[0].y, t[1].y, t[2].y}), yh = std::max({t[0].y, t[1].y, t[2].y});
  auto cell = [](double v, int n) { return std::clamp(static_cast<int>(std::floor(v)), 0, n - 1); };
  const int x0 = cell((xl - lo_.x) * sx_, nx_), x1 = cell((xh - lo_.x) * sx_, nx_);
  const int y0 = cell((yl - lo_.y) * sy_, ny_), y1 = cell((yh - lo_.y) * sy_, ny_);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      if (!f(buckets_[static_cast<std::size_t>(y) * nx_ + x])) return;
}

OverlapGrid::OverlapGrid(Vec2 lo, Vec2 hi, std::size_t expectedTriangles, double tolerance) : lo_(lo), tolerance_(tolerance) {
  const double w = std::max(hi.x - lo.x, 1e-300), h = std::max(hi.y - lo.y, 1e-300);
  const double cells = std::clamp(static_cast<double>(expectedTriangles), 1.0, 262144.0);
  const double cell = std::sqrt(w * h / cells);
  nx_ = std::clamp(static_cast<int>(w / cell) + 1, 1, 1024);
  ny_ = std::clamp(static_cast<int>(h / cell) + 1, 1, 1024);
  sx_ = nx_ / w, sy_ = ny_ / h;
  buckets_.resize(static_cast<std::size_t>(nx_) * ny_);
}

long OverlapGrid::overlapping(const Vec2* t) {
  ++query_;
  long found = -1;
  forCells(t, [&](std::vector<std::uint32_t>& bucket) {
    for (std::uint32_t id : bucket) {
      if (stamp_[id] == query_) continue;
      stamp_[id] = query_;
      if (trianglesOverlap(t, &triangles_[3 * static_cast<std::size_t>(id)], tolerance_)) {
        found = owners_[id];
        return false;
      }
    }
    return true;
  });
  return found;
}

void OverlapGrid::insert(const Vec2* t, long owner) {
  const auto id = static_cast<std::uint32_t>(owners_.size());
  triangles_.insert(triangles_.end(), t, t + 3);
  owners_.push_back(owner);
  stamp_.push_back(0);
  forCells(t, [&](std::vector<std::uint32_t>& bucket) {
    bucket.push_back(id);
    return true;
  });
}

}  // namespace lambert
