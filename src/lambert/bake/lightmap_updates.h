#pragma once
// Lightmaps kept up to date while lights move, without baking again.
//
// A texel's irradiance is the light the surfaces bring, E_s, plus the lights' direct light, E_d.
// After a light moves, the engine's warm re-solve (Radiosity::setLights + solve) gives new leaf
// radiosities B and node means B̄; then, per texel,
//
//   E_s' = E_s + Σ_n w_n (B̄'_n − B̄_n) + Σ_c w_c (B'_c − B_c)
//
// with the final gather's weights recorded once at creation (method/point_gather.h: the links'
// sources as node means, the close leaf sources through their corner vertices) — one sparse
// product over the change, so the bake's own value stays exact where nothing changed and only the
// change is approximated: the gather's decisions (which sources it opened, whose visibility it
// resolved) are frozen. The corners' change is gathered the same way at those vertices,
// B'_c − B_c = ρ_c (Σ_n w_cn (B̄'_n − B̄_n) + Σ near + E'_d,c − E_d,c), their own close sources'
// corners taken from this same step where they are among them and from their leaves' change
// interpolated otherwise: a corner's light changes sharply where two surfaces meet (the floor
// under a wall the spot leaves), and the leaves' change interpolated there was 20–80% off. The surfaces' change is smooth (the
// indirect light; the lights' sharp shadows are in E_d), so it is gathered on a lattice of every
// `latticeStep`-th texel of each chart in x and y and interpolated bilinearly between four lattice
// texels of one surface and plane; a texel whose cell has no such four is gathered itself. The
// direct light is traced again per texel for the lights that changed, only where it can be
// non-zero before or after: a spot's texels inside its cone and facing it, and those it lit.
// Seams and padding are then filled as the bake fills them (bake/lightmap_fill.h).
//
// Cost per update: the weights of the gather points and corner vertices that some node whose
// change matters reaches (a node's change × its largest weight above 10⁻⁴ of the mean texel
// irradiance), multiply-adds (memory-bound: 8 bytes a weight); the node means' pull and the
// corners' interpolation (O(nodes + vertices)); a shadow ray per texel in each changed light's
// reach; and a pass over the texels and the padding. Memory: the weights, and per texel the
// baked value, each light's direct light and the interpolation (about 100 bytes).
#include <cstdint>
#include <vector>

#include "lambert/bake/lightmap_fill.h"
#include "lambert/bake/lightmaps.h"
#include "lambert/core/error.h"
#include "lambert/core/image.h"
#include "lambert/method/point_gather.h"
#include "lambert/method/solution.h"

namespace lambert {

struct LightmapUpdateOptions {
  // The surfaces' change is gathered at every latticeStep-th texel in x and y (1: every texel).
  int latticeStep = 4;
};

struct LightmapUpdateStats {
  std::size_t texels = 0;            // covered texels
  std::size_t gatherPoints = 0;      // where the surfaces' change is gathered
  std::size_t weights = 0;           // node and corner weights over the gather points
  std::size_t bytes = 0;             // what the updater holds
  double createSeconds = 0;          // the weights' gather and the texels' direct light
  std::size_t updates = 0;
  std::size_t directTexelsTraced = 0;  // in the last update
  std::size_t gatherPointsUpdated = 0;  // in the last update: those some change that matters reaches
  double lastUpdateSeconds = 0;
};

class LightmapUpdater {
 public:
  // From a solved view and the lightmaps baked from it (bakeLightmaps over the same view, before
  // any light moved). Fails where the view cannot gather at points (the flat methods).
  static Result<LightmapUpdater> create(const SolutionView& view, const BakedLightmaps& baked, const LightmapUpdateOptions& options = {});

  // Brings lightmaps() to the view's current solution (its lights moved and re-solved since).
  // The view must be the one the updater was created from (the same hierarchy and vertex mesh).
  Status update(const SolutionView& view);
  // Per atlas, as of the last update: BakedLightmaps::irradiance's layout, W/m² per texel.
  const std::vector<Image>& lightmaps() const { return lightmaps_; }

  const LightmapUpdateStats& stats() const { return stats_; }

 private:
  LightmapUpdater() = default;
  LightmapUvs uvs_;
  std::vector<std::vector<std::uint8_t>> covered_;
  int paddingRings_ = 0;
  // Per covered texel: where it is in the atlases, its site (shadow rays), the baked irradiance.
  std::vector<std::uint64_t> texel_;
  std::vector<VertexSite> site_;
  std::vector<Rgb> baked_;
  double rayEpsilon_ = 0;
  // Per light as baked, and per texel its direct light now.
  std::vector<Light> lights_;
  std::vector<std::vector<Rgb>> direct_;
  std::vector<Rgb> bakedDirect_;  // per texel: the sum at the bake
  // The solution at the bake: node means, leaf radiosities, and the vertices' (corners') values.
  std::vector<Rgb> bakedNodeMean_, bakedLeafRadiosity_;
  // Per gather point: its weights on the node means and on the close sources' corner vertices
  // (cornerWeights_.corner indexes cornerVertex_).
  GatherWeights nodeWeights_;
  NearFieldWeights cornerWeights_;
  // The corner vertices: their own gather's weights (near entries as vertex indices of the
  // vertex mesh, nearInSubset_ the same among cornerVertex_ or kNone), albedo, direct light per
  // light now and at the bake.
  std::vector<std::uint32_t> cornerVertex_;
  GatherWeights vertexNodeWeights_;
  NearFieldWeights vertexNearWeights_;
  std::vector<std::uint32_t> nearInSubset_;
  std::vector<VertexSite> vertexSite_;
  std::vector<Rgb> vertexAlbedo_, bakedVertexDirect_;
  std::vector<std::vector<Rgb>> vertexDirect_;
  // Per texel: the gather points it interpolates, [interpStart_[t], interpStart_[t + 1]).
  std::vector<std::uint32_t> interpStart_, interpPoint_;
  std::vector<float> interpWeight_;
  // Which gather points and corner vertices each node's weights reach, and each node's largest
  // weight there; which gather points each corner vertex reaches: an update reads only the
  // weights of nodes whose change can matter (a spot in one office changes that office's nodes).
  std::vector<float> nodeLargestWeight_;
  std::vector<std::uint32_t> pointsOfNodeStart_, pointsOfNode_, cornersOfNodeStart_, cornersOfNode_, pointsOfCornerStart_, pointsOfCorner_;
  double changeFloor_ = 0;  // W/m²: a node's change × its largest weight below this is not read
  std::vector<std::uint8_t> texelChanged_;  // per texel: the last update moved it off its bake
  std::vector<std::uint8_t> seamTexel_;     // per texel: the seams' stitching moves it (LightmapFill::seamTexels)
  LightmapFill fill_;
  std::vector<Image> lightmaps_;
  LightmapUpdateStats stats_;
};

}  // namespace lambert
