#include "lambert/bake/lightmap_fill.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>
#include <utility>

#include <Eigen/Sparse>

#include "lambert/core/parallel.h"

namespace lambert {

struct LightmapFill::SeamSystem {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
};

namespace {

constexpr double kSeamWeight = 8;        // λ: a seam point's two reads
constexpr double kCoveredWeight = 1;     // w of a texel a face covers
constexpr double kPaddingWeight = 0.25;  // w of a padding texel
constexpr double kPointsPerTexel = 3;    // seam points per texel of the edge's length

// A bilinear read at lightmap coordinate uv (texel centres at (x + ½)/size, clamped to the edge,
// as render/lightmap_image.h's sampleLightmap and a GPU's LINEAR filter read): four texels of
// the atlas and their weights.
struct Read {
  std::array<std::uint64_t, 4> texel;
  std::array<double, 4> weight;
};

Read bilinearRead(const Uv& uv, std::uint64_t atlas, int size) {
  const double x = uv.u * size - 0.5, y = uv.v * size - 0.5;
  const double x0 = std::floor(x), y0 = std::floor(y), fx = x - x0, fy = y - y0;
  const std::uint64_t base = atlas * static_cast<std::uint64_t>(size) * size;
  const auto at = [&](double tx, double ty) {
    const int ix = std::clamp(static_cast<int>(tx), 0, size - 1), iy = std::clamp(static_cast<int>(ty), 0, size - 1);
    return base + static_cast<std::uint64_t>(iy) * size + ix;
  };
  return {{at(x0, y0), at(x0 + 1, y0), at(x0, y0 + 1), at(x0 + 1, y0 + 1)},
          {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy}};
}

}  // namespace

LightmapFill LightmapFill::plan(const Scene& scene, const LightmapUvs& uvs, const std::vector<std::vector<std::uint8_t>>& covered,
                                int rings) {
  LightmapFill fill;
  const int size = uvs.size;
  fill.size_ = size;
  const std::uint64_t perAtlas = static_cast<std::uint64_t>(size) * size;
  const auto isCovered = [&](std::uint64_t global) { return covered[global / perAtlas][global % perAtlas] != 0; };

  // Seams: the points every third of a texel along every edge two faces of a surface share but
  // place apart, each a row read_A − read_B of the system.
  struct Side {
    std::uint32_t face, a, b;  // the face, and the positions of the edge's ends among its corners
  };
  std::vector<std::array<std::pair<std::uint64_t, double>, 8>> rows;
  for (std::uint32_t s = 0; s < scene.surfaces.size(); ++s) {
    const std::vector<std::vector<std::uint32_t>> faces = surfaceFaces(scene.surfaces[s]);
    std::unordered_map<std::uint64_t, Side> firstSide;
    for (std::uint32_t f = 0; f < faces.size(); ++f) {
      const std::vector<std::uint32_t>& face = faces[f];
      for (std::uint32_t k = 0; k < face.size(); ++k) {
        const std::uint32_t a = face[k], b = face[(k + 1) % face.size()];
        const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
        const Side here{f, k, static_cast<std::uint32_t>((k + 1) % face.size())};
        auto [it, inserted] = firstSide.try_emplace(key, here);
        if (inserted) continue;
        const Side there = it->second;
        // Orient the other side's ends like this one's.
        const bool same = faces[there.face][there.a] == a;
        const Uv& hereA = uvs.uv[s][f][here.a];
        const Uv& hereB = uvs.uv[s][f][here.b];
        const Uv& thereA = uvs.uv[s][there.face][same ? there.a : there.b];
        const Uv& thereB = uvs.uv[s][there.face][same ? there.b : there.a];
        const std::uint64_t atlasHere = uvs.atlas[s][f], atlasThere = uvs.atlas[s][there.face];
        if (atlasHere == atlasThere && hereA == thereA && hereB == thereB) continue;  // not a seam
        const double span = std::max(std::hypot(hereB.u - hereA.u, hereB.v - hereA.v), std::hypot(thereB.u - thereA.u, thereB.v - thereA.v)) * size;
        const int points = std::max(2, static_cast<int>(std::ceil(kPointsPerTexel * span)));
        const auto lerp = [](const Uv& p, const Uv& q, double t) { return Uv{p.u + (q.u - p.u) * t, p.v + (q.v - p.v) * t}; };
        for (int i = 0; i < points; ++i) {
          const double t = (i + 0.5) / points;
          const Read one = bilinearRead(lerp(hereA, hereB, t), atlasHere, size), other = bilinearRead(lerp(thereA, thereB, t), atlasThere, size);
          // A read that reaches no covered texel sits in empty space (a degenerate face): no row.
          bool oneCovered = false, otherCovered = false;
          for (int c = 0; c < 4; ++c) {
            oneCovered |= one.weight[c] > 0 && isCovered(one.texel[c]);
            otherCovered |= other.weight[c] > 0 && isCovered(other.texel[c]);
          }
          if (!oneCovered || !otherCovered) continue;
          std::array<std::pair<std::uint64_t, double>, 8> row;
          for (int c = 0; c < 4; ++c) {
            row[c] = {one.texel[c], one.weight[c]};
            row[4 + c] = {other.texel[c], -other.weight[c]};
          }
          rows.push_back(row);
        }
      }
    }
  }
  fill.seamPoints_ = rows.size();
  for (const auto& row : rows)
    for (const auto& [texel, weight] : row) fill.seamTexel_.push_back(texel);
  std::sort(fill.seamTexel_.begin(), fill.seamTexel_.end());
  fill.seamTexel_.erase(std::unique(fill.seamTexel_.begin(), fill.seamTexel_.end()), fill.seamTexel_.end());
  if (!rows.empty()) {
    const auto indexOf = [&](std::uint64_t texel) {
      return static_cast<int>(std::lower_bound(fill.seamTexel_.begin(), fill.seamTexel_.end(), texel) - fill.seamTexel_.begin());
    };
    // The normal equations: λ² AᵀA + diag(w²), A's rows the seam points.
    const int n = static_cast<int>(fill.seamTexel_.size());
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(rows.size() * 8);
    for (std::size_t r = 0; r < rows.size(); ++r)
      for (const auto& [texel, weight] : rows[r])
        if (weight != 0) entries.emplace_back(static_cast<int>(r), indexOf(texel), kSeamWeight * weight);
    Eigen::SparseMatrix<double> a(static_cast<Eigen::Index>(rows.size()), n);
    a.setFromTriplets(entries.begin(), entries.end());  // sums a texel both reads share
    Eigen::SparseMatrix<double> normal = Eigen::SparseMatrix<double>(a.transpose()) * a;
    for (int i = 0; i < n; ++i) {
      const double w = isCovered(fill.seamTexel_[static_cast<std::size_t>(i)]) ? kCoveredWeight : kPaddingWeight;
      fill.dataWeight2_.push_back(w * w);
      normal.coeffRef(i, i) += w * w;
    }
    auto system = std::make_shared<SeamSystem>();
    system->solver.compute(normal);  // symmetric positive definite: the data terms alone make it so
    fill.seams_ = std::move(system);
  }

  // Padding: per atlas, ring by ring, the empty texels next to filled ones and those neighbours.
  fill.ringStart_.push_back(0);
  fill.fromStart_.push_back(0);
  std::vector<std::vector<std::uint8_t>> filled = covered;
  for (int ring = 0; ring < rings; ++ring) {
    std::vector<std::uint64_t> newly;
    for (std::uint64_t atlas = 0; atlas < filled.size(); ++atlas)
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          if (filled[atlas][static_cast<std::size_t>(y) * size + x]) continue;
          const std::size_t before = fill.from_.size();
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int nx = x + dx, ny = y + dy;
              if (nx < 0 || ny < 0 || nx >= size || ny >= size || !filled[atlas][static_cast<std::size_t>(ny) * size + nx]) continue;
              fill.from_.push_back(atlas * perAtlas + static_cast<std::uint64_t>(ny) * size + nx);
            }
          if (fill.from_.size() == before) continue;
          fill.padded_.push_back(atlas * perAtlas + static_cast<std::uint64_t>(y) * size + x);
          fill.fromStart_.push_back(static_cast<std::uint32_t>(fill.from_.size()));
          newly.push_back(fill.padded_.back());
        }
    if (newly.empty()) break;
    for (std::uint64_t t : newly) filled[t / perAtlas][t % perAtlas] = 1;
    fill.ringStart_.push_back(static_cast<std::uint32_t>(fill.padded_.size()));
  }
  return fill;
}

void LightmapFill::apply(std::vector<Image>& atlases) const {
  const std::uint64_t perAtlas = static_cast<std::uint64_t>(size_) * size_;
  const auto value = [&](std::uint64_t global) -> Rgb& { return atlases[global / perAtlas].pixels[global % perAtlas]; };
  // Padding, ring by ring: a ring's sources were all filled before it.
  for (std::size_t ring = 0; ring + 1 < ringStart_.size(); ++ring)
    parallelFor(ringStart_[ring], ringStart_[ring + 1], [&](std::size_t i) {
      Rgb mean;
      for (std::uint32_t k = fromStart_[i]; k < fromStart_[i + 1]; ++k) mean += value(from_[k]);
      value(padded_[i]) = mean * (1.0 / (fromStart_[i + 1] - fromStart_[i]));
    }, 4096);
  // Seams: per channel, the texels nearest their values whose reads agree along every seam.
  if (!seams_) return;
  const Eigen::Index n = static_cast<Eigen::Index>(seamTexel_.size());
  Eigen::MatrixXd rhs(n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) rhs(i, c) = dataWeight2_[static_cast<std::size_t>(i)] * value(seamTexel_[static_cast<std::size_t>(i)])[c];
  const Eigen::MatrixXd stitched = seams_->solver.solve(rhs);
  for (Eigen::Index i = 0; i < n; ++i) {
    Rgb& texel = value(seamTexel_[static_cast<std::size_t>(i)]);
    // Irradiance is not negative: a texel the solve pulled below 0 (a read across a black shadow)
    // stays at 0.
    texel = {std::fmax(0.0, stitched(i, 0)), std::fmax(0.0, stitched(i, 1)), std::fmax(0.0, stitched(i, 2))};
  }
}

}  // namespace lambert
