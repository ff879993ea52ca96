#pragma once
// A scene's part of a cache file's key (core/cache_file.h): everything of it that meshing, emission,
// albedo or the lights' direct light read; not names, the camera, exposure or solve defaults (the
// options carry what those choose), nor its lights (each cache hashes the lights it reads).
#include "lambert/core/cache_file.h"
#include "lambert/scene/scene.h"

namespace lambert {

void hashScene(cachefile::KeyHasher& h, const Scene& scene);
void hashRgb(cachefile::KeyHasher& h, const Rgb& c);

}  // namespace lambert
