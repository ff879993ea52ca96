#pragma once
// What a lightmap bake does after its texels are lit, as fixed maps over texel indices, so that a
// bake and every later update (bake/lightmap_updates.h) fill the same texels the same way:
//
//  - Seams. Texels on the two sides of a UV seam (an edge two faces of one surface share, placed
//    apart in the atlas) are one line of the surface: each such pair, found at half-texel steps
//    along the edge, is given the mean of the two, and a texel in several pairs the mean of its
//    pairs'. Without it, each side shows its own texels' light where the surface is continuous.
//  - Padding. Texels no face reaches take the mean of their filled 8-neighbours, ring by ring,
//    so that bilinear filtering and mipmaps at a chart's rim do not pull in the empty space
//    around it.
#include <cstdint>
#include <vector>

#include "lambert/core/image.h"
#include "lambert/mesh/lightmap_uvs.h"
#include "lambert/scene/scene.h"

namespace lambert {

class LightmapFill {
 public:
  // Texels are numbered over all atlases: atlas × size² + y × size + x. covered: per atlas, per
  // texel, 1 where a face covers it. rings: padding rings dilated.
  static LightmapFill plan(const Scene& scene, const LightmapUvs& uvs, const std::vector<std::vector<std::uint8_t>>& covered,
                           int rings);
  // Stitches the seams, then dilates into the padding, in place (images as the plan's atlases).
  void apply(std::vector<Image>& atlases) const;
  std::size_t seamPairs() const { return pairA_.size(); }
  std::size_t paddedTexels() const { return padded_.size(); }

 private:
  int size_ = 0;
  // Seams: the texels in any pair, each once, and the pairs as indices into them.
  std::vector<std::uint64_t> seamTexel_;
  std::vector<std::uint32_t> pairA_, pairB_, pairsOf_;  // pairsOf_: per seam texel, its pairs
  // Padding, ring by ring: ringStart_ into padded_; per padded texel its sources [fromStart_[i], fromStart_[i + 1]).
  std::vector<std::uint32_t> ringStart_;
  std::vector<std::uint64_t> padded_;
  std::vector<std::uint32_t> fromStart_;
  std::vector<std::uint64_t> from_;
};

}  // namespace lambert
