#include "lambert/mesh/vertex_radiosity.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/Dense>

#include "lambert/core/error.h"

namespace lambert {

VertexInterpolation::VertexInterpolation(const Mesh& mesh) : numPatches_(mesh.numPatches()) {
  const std::size_t numVertices = mesh.numVertices();
  // The open part of each patch: its radiosity is B / f, over its open area.
  patchScale_.resize(numPatches_);
  std::vector<double> openArea(numPatches_);
  for (std::size_t i = 0; i < numPatches_; ++i) {
    const double f = mesh.patches[i].openFraction;
    patchScale_[i] = f > 0 ? 1 / f : 0;
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

  averageStart_.assign(numVertices + 1, 0);
  std::vector<std::uint32_t> ring;
  for (std::uint32_t v = 0; v < numVertices; ++v) {
    double area = 0;
    for (std::uint32_t i : around[v]) area += openArea[i];
    if (area > 0) {  // else wholly covered: never seen, left at zero
      for (std::uint32_t i : around[v]) averageTerms_.push_back({i, openArea[i] / area});
    }
    averageStart_[v + 1] = static_cast<std::uint32_t>(averageTerms_.size());
    if (area <= 0 || !border[v]) continue;

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
    double scale = 0;
    for (std::uint32_t i : ring) scale = std::fmax(scale, length(mesh.patches[i].centroid - mesh.positions[v]));
    std::vector<Eigen::Vector3d> rows;
    Eigen::Matrix3d normalMatrix = Eigen::Matrix3d::Zero();
    for (std::uint32_t i : ring) {
      Vec3 d = (mesh.patches[i].centroid - mesh.positions[v]) / scale;  // unit-free, well conditioned
      rows.emplace_back(1, dot(d, tangent), dot(d, bitangent));
      normalMatrix += openArea[i] * rows.back() * rows.back().transpose();
    }
    Eigen::FullPivLU<Eigen::Matrix3d> lu(normalMatrix);
    lu.setThreshold(1e-8);
    if (lu.rank() < 3) continue;  // too few patches, or all in a line: keep the average
    // The fit's value at the vertex, e0ᵀ M⁻¹ Σ w_i row_i B_i, is linear in the B_i: keep the
    // weights w_i (M⁻¹ e0)ᵀ row_i.
    const Eigen::Vector3d m = lu.solve(Eigen::Vector3d::UnitX());
    Fit fit{v, static_cast<std::uint32_t>(fitTerms_.size()), 0};
    for (std::size_t k = 0; k < ring.size(); ++k) fitTerms_.push_back({ring[k], openArea[ring[k]] * m.dot(rows[k])});
    fit.end = static_cast<std::uint32_t>(fitTerms_.size());
    fits_.push_back(fit);
  }
}

std::vector<Rgb> VertexInterpolation::apply(const std::vector<Rgb>& radiosity) const {
  LAMBERT_CHECK(radiosity.size() == numPatches_);
  const std::size_t numVertices = averageStart_.size() - 1;
  std::vector<Rgb> result(numVertices);
  for (std::size_t v = 0; v < numVertices; ++v)
    for (std::uint32_t k = averageStart_[v]; k < averageStart_[v + 1]; ++k)
      result[v] += radiosity[averageTerms_[k].patch] * (averageTerms_[k].weight * patchScale_[averageTerms_[k].patch]);
  for (const Fit& fit : fits_) {
    Rgb value, lo, hi;
    for (std::uint32_t k = fit.begin; k < fit.end; ++k) {
      const Term& t = fitTerms_[k];
      const Rgb b = radiosity[t.patch] * patchScale_[t.patch];
      value += b * t.weight;
      for (int c = 0; c < 3; ++c) {
        lo[c] = k == fit.begin ? b[c] : std::fmin(lo[c], b[c]);
        hi[c] = k == fit.begin ? b[c] : std::fmax(hi[c], b[c]);
      }
    }
    for (int c = 0; c < 3; ++c) {
      const double range = hi[c] - lo[c];
      result[fit.vertex][c] = std::clamp(value[c], std::fmax(0.0, lo[c] - range), hi[c] + range);
    }
  }
  return result;
}

std::vector<Rgb> vertexRadiosity(const Mesh& mesh, const std::vector<Rgb>& radiosity) {
  return VertexInterpolation(mesh).apply(radiosity);
}

std::vector<std::uint32_t> vertexSitePatches(const Mesh& mesh) {
  std::vector<std::uint32_t> chosen(mesh.numVertices(), kNoSitePatch);
  for (std::uint32_t p = 0; p < mesh.numPatches(); ++p) {
    const Patch& patch = mesh.patches[p];
    for (std::uint32_t v : mesh.cornerIndices(p)) {
      const std::uint32_t current = chosen[v];
      if (current == kNoSitePatch) {
        chosen[v] = p;
        continue;
      }
      const Patch& other = mesh.patches[current];
      if (patch.openFraction > other.openFraction || (patch.openFraction == other.openFraction && patch.area < other.area))
        chosen[v] = p;
    }
  }
  return chosen;
}

std::vector<VertexSite> vertexSites(const Mesh& mesh, double nudge) {
  const std::size_t n = mesh.numVertices();
  std::vector<Vec3> normalSum(n);
  for (std::size_t p = 0; p < mesh.numPatches(); ++p)
    for (std::uint32_t corner : mesh.cornerIndices(p)) normalSum[corner] += mesh.patches[p].normal * mesh.patches[p].area;
  const std::vector<std::uint32_t> patchOf = vertexSitePatches(mesh);
  std::vector<VertexSite> sites(n);
  for (std::size_t i = 0; i < n; ++i) {
    sites[i].point = mesh.positions[i];
    if (patchOf[i] == kNoSitePatch || !(lengthSquared(normalSum[i]) > 0)) continue;
    sites[i].normal = normalize(normalSum[i]);
    const Vec3 toCentroid = mesh.patches[patchOf[i]].centroid - mesh.positions[i];
    const double distance = length(toCentroid);
    if (distance > 0) sites[i].point += toCentroid * (std::fmin(nudge, 0.5 * distance) / distance);
  }
  return sites;
}

PatchInterpolation::PatchInterpolation(const Mesh& mesh, std::span<const Rgb> vertexValues, std::span<const Rgb> patchFactor)
    : records_(mesh.numPatches()) {
  for (std::size_t i = 0; i < mesh.numPatches(); ++i) {
    const Patch& patch = mesh.patches[i];
    Record& r = records_[i];
    r.numCorners = std::min<std::uint32_t>(patch.numCorners, 4);
    const Rgb factor = patchFactor.empty() ? Rgb{1, 1, 1} : patchFactor[i];
    for (std::uint32_t k = 0; k < r.numCorners; ++k) {
      const Vec3& p = mesh.positions[patch.vertices[k]];
      const Rgb v = vertexValues[patch.vertices[k]] * factor;
      r.corners[3 * k] = static_cast<float>(p.x), r.corners[3 * k + 1] = static_cast<float>(p.y), r.corners[3 * k + 2] = static_cast<float>(p.z);
      r.values[3 * k] = static_cast<float>(v.r), r.values[3 * k + 1] = static_cast<float>(v.g), r.values[3 * k + 2] = static_cast<float>(v.b);
    }
  }
}

Rgb PatchInterpolation::at(std::uint32_t patch, const Vec3& x) const {
  const Record& r = records_[patch];
  const auto corner = [&](std::uint32_t k) { return Vec3{r.corners[3 * k], r.corners[3 * k + 1], r.corners[3 * k + 2]}; };
  const auto value = [&](std::uint32_t k) { return Rgb{r.values[3 * k], r.values[3 * k + 1], r.values[3 * k + 2]}; };
  const Vec3 a = corner(0);
  double bestInside = -INFINITY;
  Rgb best;
  for (std::uint32_t j = 1; j + 1 < r.numCorners; ++j) {
    const Vec3 b = corner(j), c = corner(j + 1);
    const Vec3 n = cross(b - a, c - a);
    const double twiceArea = dot(n, n);
    if (!(twiceArea > 0)) continue;
    // Barycentrics by signed sub-areas projected onto the triangle's normal.
    double wa = dot(cross(b - x, c - x), n) / twiceArea;
    double wb = dot(cross(c - x, a - x), n) / twiceArea;
    double wc = dot(cross(a - x, b - x), n) / twiceArea;
    const double inside = std::min(wa, std::min(wb, wc));
    if (inside <= bestInside) continue;
    bestInside = inside;
    wa = std::max(wa, 0.0), wb = std::max(wb, 0.0), wc = std::max(wc, 0.0);
    const double sum = wa + wb + wc;
    best = (value(0) * wa + value(j) * wb + value(j + 1) * wc) / sum;
  }
  return best;
}

}  // namespace lambert
