#pragma once
// Lightmap coordinates for a scene's own faces: each face corner's place in one of a few square
// atlases of texels, so that a baked lightmap can be drawn on the input's own mesh (glTF
// TEXCOORD_1) instead of vertex colours on re-meshed leaves.
//
// Where the file has them, its coordinates are used: glTF's TEXCOORD_1 or a scene file's
// `lightmapUvs` (Surface::faceLightmapUvs; surfaces that overlap one another, as objects with a
// lightmap each do, go to separate atlases), else its first set (Surface::faceUvs) when that set
// is inside [0, 1] and no two faces overlap in it (the overlap is detected on a grid and said in
// `note`). Either set is used only where every face of every surface has it. Otherwise charts
// are generated and packed here (no Debian package offers xatlas or UVAtlas): planar charts over
// the faces of a smooth region that lie in one plane (most of architecture), a least-squares
// conformal map (Lévy, Petitjean, Ray & Maillot 2002) for the rest of a curved region, split
// where it would fold or stretch, and a packing of the charts' texel rectangles with padding
// between them, into as many atlases as needed. docs/lightmaps.md has the measured figures. The scale is one texelSize (scene units per texel) over the whole scene, so that
// light detail does not depend on how a face happens to be cut.
#include <cstdint>
#include <string>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/scene/scene.h"

namespace lambert {

struct LightmapUvOptions {
  // Scene units per texel (`--texel-size`, converted from metres by the caller). 0: the scene's
  // lightmaps hold about one atlas of atlasSize's texels: the smallest texel size at which the
  // generated charts fit one atlas (defaultTexelSize for 1024), or for the file's coordinates
  // the largest power of two at which its atlases together hold no more.
  double texelSize = 0;
  // Texels per side of each atlas, at most (`--lightmap-size`): with a texel size given, the
  // atlas is the smallest power of two that holds every chart, or several of atlasSize.
  int atlasSize = 1024;
  // Empty texels between any two charts, and ⌈half⌉ of that between a chart and the atlas's
  // edges (dilation fills them; bilinear filtering reads one texel beyond a chart).
  int paddingTexels = 2;
  bool useFileUvs = true; // false: generate charts even where the file has usable coordinates
  // Without a texel size, whether a file's own sets share one atlas of atlasSize's texels among
  // their atlases (true) or get atlasSize each (false: a tool that packed its islands' margins
  // for that size asks for it, as the Blender add-on does with --lightmap-size).
  bool fileSetsShareAtlas = true;
};

struct LightmapUvs {
  enum class Origin { FileLightmapSet, FileFirstSet, Generated };
  Origin origin = Origin::Generated;
  int size = 0;        // texels per side of every atlas
  int numAtlases = 0;
  double texelSize = 0;  // scene units per texel (for file coordinates: the area-weighted mean)
  // Per surface, per face, per corner, parallel to surfaceFaces(surface): the corner's
  // coordinate in [0, 1]² of its atlas in glTF's convention, (0, 0) the top-left corner of the
  // first texel row. Texel (x, y) covers [x, x + 1] × [y, y + 1] / size.
  std::vector<std::vector<std::vector<Uv>>> uv;
  std::vector<std::vector<std::uint16_t>> atlas;  // per surface, per face: the atlas it is in
  std::size_t charts = 0;  // generated charts (0 for the file's coordinates)
  std::size_t conformalCharts = 0;  // of them, flattened by the conformal map (the rest are planar)
  double efficiency = 0;  // texels whose centre a face covers / all atlases' texels
  std::string note;       // what was used or why the file's coordinates were not (for the log)
};

// The default texel size, scene units per texel: the smallest at which the scene's generated
// charts, with the default padding, fit one 1024² atlas (so the scene fills it, 70–90% of its
// texels covered on the shipped scenes); what lightmapUvs takes with default options. It builds
// the charts to find it (milliseconds for thousands of faces).
double defaultTexelSize(const Scene& scene);

// Refuses (with the reason and how to proceed) only a scene whose charts cannot fit the atlases
// at any texel size the options allow.
Result<LightmapUvs> lightmapUvs(const Scene& scene, const LightmapUvOptions& options = {});

}  // namespace lambert
