#pragma once
// Stanford PLY polygon meshes (ascii, binary_little_endian, binary_big_endian), as lambert
// surfaces: `element vertex` with x, y, z (any numeric type) and `element face` with a
// `vertex_indices` (or `vertex_index`) list; other elements and properties are skipped. PLY has
// no materials: every face is a grey of albedo 0.5, and nothing emits (light the scene with a
// scene file's lights, or place the mesh in one). Faces become smooth regions (scene/regions.h).
// Counts are checked against the file's size before anything is allocated, so a header that
// claims 10⁷ vertices in a 100-byte file is an error, not a crash; errors name the file and line
// (ascii) or byte offset (binary).
#include <string>

#include "lambert/core/error.h"
#include "lambert/scene/regions.h"
#include "lambert/scene/scene.h"

namespace lambert {

Result<Scene> readPly(const std::string& path, double metresPerUnit = 1, const RegionOptions& regions = {});

}  // namespace lambert
