#pragma once
// What a lightmap bake does after its texels are lit, as fixed maps over texel indices, so that a
// bake and every later update (bake/lightmap_updates.h) fill the same texels the same way:
//
//  - Padding. Texels no face reaches take the mean of their filled 8-neighbours, ring by ring,
//    so that bilinear filtering and mipmaps at a chart's rim do not pull in the empty space
//    around it.
//  - Seams, after the padding. Along a UV seam (an edge two faces of one surface share, placed
//    apart in the atlas) the surface is one line, but a viewer reads each side from its own
//    chart: bilinearly, from texel centres that lie at other distances from the edge on each side
//    and from padding beyond it. Where the light changes within a texel (a contact shadow), the two
//    reads differed by up to 25% (Blender's Lightmap Pack, an island per quad). The texels under
//    the reads are moved as little as possible, in least squares, so that the two bilinear reads
//    agree at points every third of a texel along every seam (Sylvan 2016, "Fixing lightmap
//    seams"; Iwanicki 2013 in Call of Duty's lightmaps): minimise
//        Σ_points λ² (read_A − read_B)² + Σ_texels w_t² (x_t − baked_t)²,
//    λ = 8, w = 1 for a texel a face covers and 0.25 for padding (which takes most of the change).
//    The normal equations' matrix depends on the coordinates alone: factored once per plan
//    (sparse LDLᵀ), each apply solves it for three channels.
#include <cstdint>
#include <memory>
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
  // Dilates into the padding, then stitches the seams, in place (images as the plan's atlases).
  void apply(std::vector<Image>& atlases) const;
  std::size_t seamPoints() const { return seamPoints_; }
  // The texels the seams move (global numbers, ascending): a caller that applies the fill again
  // to lightmaps it changed in part must give these their unstitched values first (the solve
  // starts from what it is given, and a second solve would smooth them again).
  const std::vector<std::uint64_t>& seamTexels() const { return seamTexel_; }
  std::size_t paddedTexels() const { return padded_.size(); }

 private:
  struct SeamSystem;  // the factored normal equations (Eigen), shared by copies of the plan
  int size_ = 0;
  // Seams: the texels under any seam point's reads, each once, their data weights w², and the
  // system over them.
  std::size_t seamPoints_ = 0;
  std::vector<std::uint64_t> seamTexel_;
  std::vector<double> dataWeight2_;
  std::shared_ptr<const SeamSystem> seams_;
  // Padding, ring by ring: ringStart_ into padded_; per padded texel its sources [fromStart_[i], fromStart_[i + 1]).
  std::vector<std::uint32_t> ringStart_;
  std::vector<std::uint64_t> padded_;
  std::vector<std::uint32_t> fromStart_;
  std::vector<std::uint64_t> from_;
};

}  // namespace lambert
