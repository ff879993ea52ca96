#pragma once
// glTF 2.0, .gltf and .glb (tinygltf), as lambert surfaces and lights. What is read:
//   the default scene's node hierarchy with its transforms (matrix or TRS; a mirroring transform
//   flips the winding back), triangle primitives (TRIANGLES, STRIP, FAN; indexed or not), each a
//   set of smooth regions (scene/regions.h);
//   materials: baseColorFactor × baseColorTexture (sRGB decoded to linear, through TEXCOORD_n,
//   averaged over each patch; wrap modes other than repeat and KHR_texture_transform are not
//   read, with a warning) → albedo ρ; emissiveFactor × KHR_materials_emissive_strength ×
//   emissiveTexture (sRGB decoded and averaged per patch as the base colour's, through the same
//   TEXCOORD_n) → emitted radiance L_e in W/(m²·sr); doubleSided → two-sided (Material::twoSided);
//   KHR_lights_punctual point, spot and directional lights, photometric → radiometric at
//   683 lm/W: I [W/sr] = intensity [cd] / 683 × colour, E⊥ [W/m²] = intensity [lx] / 683 × colour;
//   a spot's outerConeAngle is lambert's cone, outer − inner its falloff;
//   the first perspective camera (yfov).
// Units: metres, as glTF requires. Points and lines are skipped with a warning. Files exported by Blender load as they are.
#include <string>

#include "lambert/core/error.h"
#include "lambert/core/photometric.h"  // kLumensPerWatt
#include "lambert/scene/regions.h"
#include "lambert/scene/scene.h"

namespace lambert {

Result<Scene> readGltf(const std::string& path, const RegionOptions& regions = {});

}  // namespace lambert
