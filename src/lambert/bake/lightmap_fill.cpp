#include "lambert/bake/lightmap_fill.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <utility>

#include "lambert/core/parallel.h"

namespace lambert {

LightmapFill LightmapFill::plan(const Scene& scene, const LightmapUvs& uvs, const std::vector<std::vector<std::uint8_t>>& covered,
                                int rings) {
  LightmapFill fill;
  const int size = uvs.size;
  fill.size_ = size;
  const std::uint64_t perAtlas = static_cast<std::uint64_t>(size) * size;
  const auto isCovered = [&](std::uint64_t global) { return covered[global / perAtlas][global % perAtlas] != 0; };

  // Seams: the pairs met at half-texel steps along every edge two faces of a surface share but
  // place apart.
  struct Side {
    std::uint32_t face, a, b;  // the face, and the positions of the edge's ends among its corners
  };
  std::vector<std::pair<std::uint64_t, std::uint64_t>> pairs;
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
        const int steps = std::max(1, static_cast<int>(std::ceil(2 * span)));
        const auto texelAt = [&](const Uv& p, const Uv& q, double t, std::uint64_t atlas) {
          const int x = std::clamp(static_cast<int>(std::floor((p.u + (q.u - p.u) * t) * size)), 0, size - 1);
          const int y = std::clamp(static_cast<int>(std::floor((p.v + (q.v - p.v) * t) * size)), 0, size - 1);
          return atlas * perAtlas + static_cast<std::uint64_t>(y) * size + x;
        };
        for (int i = 0; i <= steps; ++i) {
          // Half a step in from the ends, where the texels are the edge's own.
          const double t = (i + 0.5) / (steps + 1);
          const std::uint64_t p = texelAt(hereA, hereB, t, atlasHere), q = texelAt(thereA, thereB, t, atlasThere);
          if (p != q && isCovered(p) && isCovered(q)) pairs.push_back({p, q});
        }
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  for (const auto& [a, b] : pairs) {
    fill.seamTexel_.push_back(a);
    fill.seamTexel_.push_back(b);
  }
  std::sort(fill.seamTexel_.begin(), fill.seamTexel_.end());
  fill.seamTexel_.erase(std::unique(fill.seamTexel_.begin(), fill.seamTexel_.end()), fill.seamTexel_.end());
  const auto indexOf = [&](std::uint64_t texel) {
    return static_cast<std::uint32_t>(std::lower_bound(fill.seamTexel_.begin(), fill.seamTexel_.end(), texel) - fill.seamTexel_.begin());
  };
  fill.pairsOf_.assign(fill.seamTexel_.size(), 0);
  for (const auto& [a, b] : pairs) {
    fill.pairA_.push_back(indexOf(a));
    fill.pairB_.push_back(indexOf(b));
    ++fill.pairsOf_[fill.pairA_.back()];
    ++fill.pairsOf_[fill.pairB_.back()];
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
  // Seams: every pair's mean, then each texel the mean of its pairs'.
  std::vector<Rgb> sum(seamTexel_.size());
  for (std::size_t p = 0; p < pairA_.size(); ++p) {
    const Rgb mean = (value(seamTexel_[pairA_[p]]) + value(seamTexel_[pairB_[p]])) * 0.5;
    sum[pairA_[p]] += mean;
    sum[pairB_[p]] += mean;
  }
  for (std::size_t i = 0; i < seamTexel_.size(); ++i) value(seamTexel_[i]) = sum[i] * (1.0 / pairsOf_[i]);
  // Padding, ring by ring: a ring's sources were all filled before it.
  for (std::size_t ring = 0; ring + 1 < ringStart_.size(); ++ring)
    parallelFor(ringStart_[ring], ringStart_[ring + 1], [&](std::size_t i) {
      Rgb mean;
      for (std::uint32_t k = fromStart_[i]; k < fromStart_[i + 1]; ++k) mean += value(from_[k]);
      value(padded_[i]) = mean * (1.0 / (fromStart_[i + 1] - fromStart_[i]));
    }, 4096);
}

}  // namespace lambert
