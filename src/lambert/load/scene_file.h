#pragma once
// lambert's own scene file: a JSON document of materials, planar polygons, lights, a camera and a
// unit (docs/scene-format.md lists every field with its unit and default). Reading is strict,
// as pbrt's and Mitsuba's are: an unknown field, a wrong type or a value out of range is an
// error naming the file, the JSON path (/lights/2/coneAngleDegrees) and what is allowed; a
// syntax error names the file, line and column. Nothing is thrown out of these functions.
#include <optional>
#include <string>

#include "lambert/core/error.h"
#include "lambert/scene/scene.h"

namespace lambert {

// Reads a scene file. The scene's name is the file's "name", else the file's stem.
Result<Scene> readSceneFile(const std::string& path);
// The same from text already in memory; `path` only names it in errors.
Result<Scene> parseSceneFile(const std::string& text, const std::string& path);

// The scene as a scene file that readSceneFile reads back to the same scene, bit for bit (numbers
// are written in their shortest round-trip form). Materials carry the emission, so surfaces of
// one material that emit differently become materials of their own.
std::string sceneFileText(const Scene& scene);
// Writes sceneFileText atomically (a temporary file renamed over path).
Status writeSceneFile(const std::string& path, const Scene& scene);

// Whether a path names a mesh file (.obj, .ply, .gltf, .glb, .mgf), whose faces become smooth regions.
bool isMeshFile(const std::string& path);

// How to read files that do not say everything themselves.
struct LoadOptions {
  double metresPerUnit = 0;        // OBJ, PLY: the unit of their numbers (0: metres); others state theirs
  double creaseAngleDegrees = 20;  // mesh files: neighbours whose normals differ more are not smoothed
  // Mesh files: every material two-sided (true) or one-sided (false), whatever the file says.
  std::optional<bool> twoSided = std::nullopt;
  int mgfDivisions = 16;  // MGF: segments per full circle of its curved primitives
  std::string includeRoot = {};  // MGF: includes must resolve inside this folder (empty: anywhere)
};

// A built-in scene by name (scene/builtin.h), or a file by its extension (.json, .obj, .ply,
// .gltf, .glb); anything
// else is an error naming the choices. A unit for a file that states its own is an error.
Result<Scene> loadScene(const std::string& nameOrPath, const LoadOptions& options = {});

}  // namespace lambert
