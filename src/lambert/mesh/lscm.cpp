#include "lambert/mesh/lscm.h"

// Per fan triangle, the Cauchy-Riemann residual of the map in the triangle's own frame, weighted
// by its area, two vertices pinned, solved by the normal equations (Eigen's SimplicialLDLT).
//
// Cost: one sparse factorisation of 2 × (the chart's vertices − 2) unknowns, about linear in the
// chart's faces. Fails (false) where the system is singular or the solve gives non-finite
// values; a map that flips or stretches a triangle is the caller's to refuse.
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <cmath>

namespace lambert {

bool conformalMap(const SurfaceGeometry& g, Chart& chart) {
  const Surface& s = *g.surface;
  std::vector<std::uint32_t> local;  // chart vertex → surface vertex
  std::vector<int> index(s.vertices.size(), -1);
  for (std::uint32_t f : chart.faces)
    for (std::uint32_t v : g.faces[f])
      if (index[v] < 0) index[v] = static_cast<int>(local.size()), local.push_back(v);
  const std::size_t n = local.size();
  if (n < 3) return false;
  // Pins: the vertex farthest from the first, and the one farthest from that.
  auto farthestFrom = [&](std::size_t from) {
    std::size_t best = 0;
    double bestD = -1;
    for (std::size_t k = 0; k < n; ++k)
      if (double d = length(s.vertices[local[k]] - s.vertices[local[from]]); d > bestD) bestD = d, best = k;
    return best;
  };
  const std::size_t pinA = farthestFrom(0), pinB = farthestFrom(pinA);
  if (pinA == pinB) return false;
  const double pinDistance = length(s.vertices[local[pinB]] - s.vertices[local[pinA]]);
  // Unknowns: u then v of each free vertex.
  std::vector<int> column(n, -1);
  int free = 0;
  for (std::size_t k = 0; k < n; ++k)
    if (k != pinA && k != pinB) column[k] = free++;
  const Vec2 pinned[2] = {{0, 0}, {pinDistance, 0}};
  auto pinOf = [&](std::size_t k) { return k == pinA ? pinned[0] : pinned[1]; };
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * free);
  double chartExtent = pinDistance;
  const double tiny = 1e-14 * chartExtent * chartExtent;
  // Each triangle adds (rowRe² + rowIm²) / (2 area) to the energy: accumulate AᵀA and Aᵀb.
  std::vector<std::pair<int, double>> rowRe, rowIm;
  for (std::uint32_t f : chart.faces) {
    const auto& face = g.faces[f];
    for (std::size_t k = 1; k + 1 < face.size(); ++k) {
      const std::uint32_t tv[3] = {face[0], face[k], face[k + 1]};
      const Vec3 p0 = s.vertices[tv[0]], e1 = s.vertices[tv[1]] - p0, e2 = s.vertices[tv[2]] - p0;
      const double l1 = length(e1);
      const double twiceArea = length(cross(e1, e2));
      if (!(twiceArea > tiny) || !(l1 > 0)) continue;
      // The triangle in its own frame: x along e1, y in its plane.
      const Vec2 q[3] = {{0, 0}, {l1, 0}, {dot(e2, e1) / l1, twiceArea / l1}};
      // W_j = q_{j+2} − q_{j+1} (as complex numbers); residual Σ_j W_j (u_j + i v_j).
      const double w = 1 / std::sqrt(twiceArea);
      rowRe.clear(), rowIm.clear();
      double bRe = 0, bIm = 0;
      for (int j = 0; j < 3; ++j) {
        const Vec2 W = q[(j + 2) % 3] - q[(j + 1) % 3];
        const std::size_t k2 = static_cast<std::size_t>(index[tv[j]]);
        // Re: Wx u − Wy v; Im: Wy u + Wx v.
        if (column[k2] >= 0) {
          rowRe.push_back({column[k2], w * W.x}), rowRe.push_back({free + column[k2], -w * W.y});
          rowIm.push_back({column[k2], w * W.y}), rowIm.push_back({free + column[k2], w * W.x});
        } else {
          const Vec2 p = pinOf(k2);
          bRe -= w * (W.x * p.x - W.y * p.y);
          bIm -= w * (W.y * p.x + W.x * p.y);
        }
      }
      for (const auto* row : {&rowRe, &rowIm}) {
        const double b = row == &rowRe ? bRe : bIm;
        for (const auto& [c1, a1] : *row) {
          rhs[c1] += a1 * b;
          for (const auto& [c2, a2] : *row) entries.emplace_back(c1, c2, a1 * a2);
        }
      }
    }
  }
  if (free == 0) return false;
  Eigen::SparseMatrix<double> normalMatrix(2 * free, 2 * free);
  normalMatrix.setFromTriplets(entries.begin(), entries.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normalMatrix);
  if (solver.info() != Eigen::Success) return false;
  const Eigen::VectorXd x = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !x.allFinite()) return false;
  chart.corners.clear();
  chart.cornerStart.assign(1, 0);
  for (std::uint32_t f : chart.faces) {
    for (std::uint32_t v : g.faces[f]) {
      const std::size_t k = static_cast<std::size_t>(index[v]);
      chart.corners.push_back(column[k] >= 0 ? Vec2{x[column[k]], x[free + column[k]]} : pinOf(k));
    }
    chart.cornerStart.push_back(static_cast<std::uint32_t>(chart.corners.size()));
  }
  return true;
}

}  // namespace lambert
