#pragma once
// Baked lightmaps (bake/lightmaps.h) written for engines and the web: the input's own mesh as a
// binary glTF whose materials carry their lightmap through lambert's LAMBERT_lightmap extension
// as 8-bit RGBM, and beside it, per atlas, the lightmap as linear HDR (EXR, half float).
//
// What a texel holds. Every file holds the irradiance E in W/m² arriving at the texel's point
// (bake/lightmaps.h), never a tone-mapped or exposed value; per atlas k one range S_k in W/m²
// (lightmapScale: the atlas's largest channel) maps the glb's bytes onto it:
//   OUT.glb, atlas k image   RGBM (Karis 2009), an RGBA PNG: E = S_k · (t / 255) · (a / 255) per
//                            channel, t a colour byte and a the alpha byte (the multiplier
//                            M = a / 255), S_k the extension's "range". Each texel keeps about 8
//                            significant bits down to S_k / 255² (linear 8-bit bytes kept 8 bits
//                            at S_k and none below S_k / 510: on RenderPark's office2, 99.6% of
//                            the texels fell under 16/255 of the lamp-lit ceiling's S_k and
//                            banded).
//   OUT-lightmap-k.exr       E itself, half float (11 significant bits; E above 65504 is written
//                            as 65504, with a warning).
// The extension, on each material: "LAMBERT_lightmap": {"index": texture, "texCoord": 1,
// "encoding": "RGBM", "range": S_k}. A client decodes the four texels around a point and filters
// the decoded values (examples/web/lambert-lightmap.js, a GLTFLoader plugin): filtering the bytes
// first would multiply two interpolated factors, up to 7% off across a shadow's edge.
// A renderer turns a texel into the outgoing radiance of the diffuse surface under it as
// L = ρ/π · E (+ the surface's own emission L_e), ρ the base colour (factor × texture). This is
// what current three.js draws for a lightmap (the plugin hands it E, decoded, as the lightmap
// texel with lightMapIntensity 1): lights_fragment_maps adds texel × lightMapIntensity
// to the irradiance that RE_IndirectDiffuse multiplies by BRDF_Lambert = diffuseColor/π, and
// MeshBasicMaterial multiplies texel × lightMapIntensity by RECIPROCAL_PI and the diffuse colour;
// so a page with no lights and no environment shows lambert's radiance, to which it applies its
// exposure (2^stops) and the sRGB transfer as lambert's render does.
//
// The glb (docs/lightmaps.md "Output"): the scene's own surfaces' faces, fanned into triangles
// (not the solution's re-meshed leaves), positions in metres, per-vertex normals (area-weighted
// over each surface's faces), TEXCOORD_0 the file's texture coordinates where a texture draws
// through them (else the lightmap coordinates again: glTF numbers the sets from 0 without gaps),
// // TEXCOORD_1 the lightmap coordinates; vertices are split wherever a corner's coordinates
// differ. One primitive, with one glTF material, per (scene material, atlas, emission) group: a
// material names one lightmap texture, so a material whose faces lie in two atlases becomes two
// glTF materials. Materials are lit (metallic 0, roughness 1), not KHR_materials_unlit, which
// some clients draw with a lightmap π times brighter (Mozilla Hubs, for content made when
// three.js did not divide there by π). Emitting surfaces carry L_e as emissiveFactor ×
// emissiveStrength (KHR_materials_emissive_strength where L_e exceeds 1). Lightmap samplers clamp to the edge and
// do not mip-map (a mip level would average neighbouring charts across their padding).
//
// Cost: one pass over the faces and one over the texels per file, the bulk being PNG's and EXR's
// compression. Memory: a copy of the lightmaps (24 bytes per texel) and every file's bytes until
// they are written.
#include <cstdint>
#include <string>
#include <vector>

#include "lambert/bake/lightmaps.h"
#include "lambert/core/error.h"
#include "lambert/core/image.h"
#include "lambert/core/stats.h"
#include "lambert/scene/scene.h"

namespace lambert {

// S: the largest channel of any texel of the image, in W/m² (1 where the image is black), so that
// E / S lies in [0, 1]. Non-finite and negative channels are not counted.
double lightmapScale(const Image& irradiance);

// RGBM, interleaved RGBA bytes. Per texel, with c = clamp(E / scale, 0, 1) and m its largest
// channel: a = ceil(255 · m), t = round(255 · c / (a / 255)); a black texel is (0, 0, 0, 0).
// Decoding E' = scale · (t / 255) · (a / 255) differs from E by at most
// 0.5/255 · (maxChannel(E) + scale/255) per channel (the rounding of t, with M = a/255 at most
// 1/255 above m).
std::vector<std::uint8_t> encodeRgbm(const Image& irradiance, double scale);
// The decode of one RGBM texel (four bytes), W/m².
Rgb decodeRgbm(const std::uint8_t* rgba, double scale);

// The lightmaps as the glb carries them: each atlas's irradiance through RGBM at its range S_k and
// back (unusable channels as 0), what a client of the glb draws. `solve --image` draws these.
BakedLightmaps asCarriedByGlb(const BakedLightmaps& baked);

struct LightmapExportOptions {
  bool exr = true;  // OUT-lightmap-k.exr per atlas
};

// "dir/OUT.glb", atlas k: "dir/OUT-lightmap-k.exr".
std::string lightmapExrPath(const std::string& glbPath, std::size_t atlas);

struct LightmapAtlasFiles {
  std::string exr;           // empty where not asked for
  double scale = 0;          // S_k, W/m²: the LAMBERT_lightmap range
  std::size_t coveredTexels = 0;
};

struct LightmapExport {
  std::string glb;
  std::vector<LightmapAtlasFiles> atlases;
  std::size_t vertices = 0, triangles = 0, primitives = 0;
  std::size_t repairedTexels = 0;  // non-finite or negative channels written as 0 (with a warning)
  std::size_t clampedTexels = 0;   // channels above half float's 65504 in the EXR (with a warning)
};

// Writes the glb and, per atlas, the files the options ask for, all encoded before any is written
// and each written atomically; where a write fails, the files this call had written are removed
// again, so a failed export leaves none of its files (and no temporaries). Refuses lightmaps
// baked for another scene (their coordinates do not match its faces). Errors name the path.
Result<LightmapExport> writeLightmaps(const std::string& glbPath, const Scene& scene, const BakedLightmaps& baked,
                                      const LightmapExportOptions& options = {});

// The bake's and the export's figures, for a command's table and --json: the atlases (count,
// texels per side, texel size in metres, packing efficiency, charts, where the coordinates came
// from), the bake's texels and time, the glb's vertices, triangles and primitives, and per atlas
// k its EXR and range (lightmap_k_exr, lightmap_k_scale in W/m²).
Stats lightmapStats(const Scene& scene, const BakedLightmaps& baked, const LightmapExport& files);

}  // namespace lambert
