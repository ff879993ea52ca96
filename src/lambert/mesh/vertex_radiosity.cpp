#include "lambert/mesh/vertex_radiosity.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/Dense>

#include "lambert/core/error.h"

namespace lambert {

std::vector<Rgb> vertexRadiosity(const Mesh& mesh, const std::vector<Rgb>& radiosity) {
  LAMBERT_CHECK(radiosity.size() == mesh.numPatches());
  const std::size_t numVertices = mesh.numVertices();
  // The open part of each patch: its radiosity and its area.
  std::vector<Rgb> patchRadiosity(radiosity.size());
  std::vector<double> openArea(radiosity.size());
  for (std::size_t i = 0; i < radiosity.size(); ++i) {
    const double f = mesh.patches[i].openFraction;
    patchRadiosity[i] = f > 0 ? radiosity[i] / f : Rgb{};
    openArea[i] = mesh.patches[i].area * f;
  }

  // Patches around each vertex, and which vertices lie on a border (an edge of one patch only).
  std::vector<std::vector<std::uint32_t>> around(numVertices);
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edgeUses;
  for (std::uint32_t i = 0; i < mesh.numPatches(); ++i) {
    auto corners = mesh.cornerIndices(i);
    for (std::size_t k = 0; k < corners.size(); ++k) {
      around[corners[k]].push_back(i);
      std::uint32_t a = corners[k], b = corners[(k + 1) % corners.size()];
      ++edgeUses[{std::min(a, b), std::max(a, b)}];
    }
  }
  std::vector<char> border(numVertices, 0);
  for (const auto& [edge, uses] : edgeUses)
    if (uses == 1) border[edge.first] = border[edge.second] = 1;

  std::vector<Rgb> result(numVertices);
  std::vector<std::uint32_t> ring;
  for (std::size_t v = 0; v < numVertices; ++v) {
    if (around[v].empty()) continue;
    Rgb weighted;
    double area = 0;
    for (std::uint32_t i : around[v]) {
      weighted += patchRadiosity[i] * openArea[i];
      area += openArea[i];
    }
    if (area <= 0) continue;  // wholly covered: never seen
    result[v] = weighted / area;
    if (!border[v]) continue;

    // Two rings of patches, for a gradient the one-sided first ring alone cannot pin down.
    ring.clear();
    for (std::uint32_t i : around[v])
      for (std::uint32_t corner : mesh.cornerIndices(i))
        for (std::uint32_t j : around[corner])
          if (openArea[j] > 0) ring.push_back(j);
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());

    Vec3 tangent, bitangent;
    orthonormalBasis(mesh.patches[around[v].front()].normal, tangent, bitangent);
    Eigen::Matrix3d normalMatrix = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d rhs = Eigen::Matrix3d::Zero();  // one column per channel
    Rgb lo = patchRadiosity[ring.front()], hi = lo;
    double scale = 0;
    for (std::uint32_t i : ring) {
      Vec3 d = mesh.patches[i].centroid - mesh.positions[v];
      scale = std::fmax(scale, length(d));
    }
    for (std::uint32_t i : ring) {
      Vec3 d = (mesh.patches[i].centroid - mesh.positions[v]) / scale;  // unit-free, well conditioned
      Eigen::Vector3d row(1, dot(d, tangent), dot(d, bitangent));
      const double w = openArea[i];
      normalMatrix += w * row * row.transpose();
      for (int c = 0; c < 3; ++c) {
        rhs.col(c) += w * patchRadiosity[i][c] * row;
        lo[c] = std::fmin(lo[c], patchRadiosity[i][c]);
        hi[c] = std::fmax(hi[c], patchRadiosity[i][c]);
      }
    }
    Eigen::FullPivLU<Eigen::Matrix3d> lu(normalMatrix);
    lu.setThreshold(1e-8);
    if (lu.rank() < 3) continue;  // too few patches, or all in a line: keep the average
    Eigen::Matrix3d fit = lu.solve(rhs);
    for (int c = 0; c < 3; ++c) {
      double range = hi[c] - lo[c];
      result[v][c] = std::clamp(fit(0, c), std::fmax(0.0, lo[c] - range), hi[c] + range);
    }
  }
  return result;
}

std::vector<VertexSite> vertexSites(const Mesh& mesh, double nudge) {
  const std::size_t n = mesh.numVertices();
  std::vector<Vec3> centroidSum(n), normalSum(n);
  std::vector<std::uint32_t> uses(n, 0);
  for (std::size_t p = 0; p < mesh.numPatches(); ++p) {
    const Patch& patch = mesh.patches[p];
    for (std::uint32_t corner : mesh.cornerIndices(p)) {
      centroidSum[corner] += patch.centroid;
      normalSum[corner] += patch.normal * patch.area;
      ++uses[corner];
    }
  }
  std::vector<VertexSite> sites(n);
  for (std::size_t i = 0; i < n; ++i) {
    sites[i].point = mesh.positions[i];
    if (uses[i] == 0 || !(lengthSquared(normalSum[i]) > 0)) continue;
    sites[i].normal = normalize(normalSum[i]);
    const Vec3 toCentroid = centroidSum[i] / uses[i] - mesh.positions[i];
    const double distance = length(toCentroid);
    if (distance > 0) sites[i].point += toCentroid * (std::fmin(nudge, 0.5 * distance) / distance);
  }
  return sites;
}

}  // namespace lambert
