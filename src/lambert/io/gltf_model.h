#pragma once
// What lambert's two glTF writers share (io/gltf_export.cpp: vertex colours on the solution's
// mesh; io/lightmap_export.cpp: lightmaps on the input's own faces): one buffer, 4-byte aligned
// views, float attributes, 32-bit indices, sRGB PNG textures, the scene's camera, and the encoding
// of the whole model as binary glTF. Internal to io/ (tinygltf stays out of the public headers).
#include <tiny_gltf.h>

#include <cstdint>
#include <string>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/scene/scene.h"

namespace lambert::gltf {

// Appends bytes to buffer 0 as a new, 4-byte aligned buffer view; returns its index.
int addView(tinygltf::Model& model, const void* data, std::size_t bytes, int target);
// A PNG (already encoded) as an image inside the buffer; returns the image's index.
int addPngImage(tinygltf::Model& model, const std::vector<std::uint8_t>& png, const std::string& name);
// A texture of an image with a sampler of its own; returns the texture's index.
int addTexture(tinygltf::Model& model, int image, int wrap, int minFilter);
// A colour texture (base colour, emission) as an 8-bit sRGB PNG, repeating as lambert samples it;
// returns the texture's index.
int addColourTexture(tinygltf::Model& model, const Texture& texture);
// Float VEC2 / VEC3 accessors (bounds: the min and max glTF requires of POSITION).
int addVec2(tinygltf::Model& model, const std::vector<float>& uv);
int addVec3(tinygltf::Model& model, const std::vector<float>& xyz, bool bounds);
// A 32-bit index accessor.
int addIndices(tinygltf::Model& model, const std::vector<std::uint32_t>& indices);
// The scene's camera (else the view `lambert render` draws without one), so that a viewer opens
// at lambert's view: a node at the eye whose −z looks at the target, in metres (added to
// model.cameras; the node is returned, not added).
tinygltf::Node cameraNode(tinygltf::Model& model, const Scene& scene);
// The default scene: a node holding mesh 0 (named after the scene) and the scene's camera node.
void addSceneWithCamera(tinygltf::Model& model, const Scene& scene);
// The model as the bytes of a .glb.
Result<std::vector<std::uint8_t>> encodeGlb(tinygltf::Model& model);

}  // namespace lambert::gltf
