#include "lambert/scene/scene_hash.h"

#include <memory>
#include <vector>

namespace lambert {

using cachefile::KeyHasher;

void hashRgb(KeyHasher& h, const Rgb& c) {
  h.f64(c.r);
  h.f64(c.g);
  h.f64(c.b);
}

namespace {

void hashTexture(KeyHasher& h, const std::shared_ptr<const Texture>& texture) {
  h.u32(texture ? 1 : 0);
  if (!texture) return;
  h.i64(texture->width);
  h.i64(texture->height);
  h.array(texture->pixels);
}

}  // namespace

void hashScene(KeyHasher& h, const Scene& scene) {
  h.f64(scene.metresPerUnit);
  h.u64(scene.materials.size());
  for (const Material& m : scene.materials) {
    hashRgb(h, m.albedo);
    h.u32(m.twoSided ? 1 : 0);
    hashTexture(h, m.texture);
    hashTexture(h, m.emissionTexture);
  }
  h.u64(scene.surfaces.size());
  for (const Surface& s : scene.surfaces) {
    h.array(s.vertices);
    h.i64(s.material);
    hashRgb(h, s.emittedRadiance);
    h.i64(s.twin);
    h.u64(s.faces.size());
    for (const std::vector<std::uint32_t>& face : s.faces) h.array(face);
    h.u64(s.faceUvs.size());
    for (const std::vector<Uv>& uvs : s.faceUvs) h.array(uvs);
  }
}


}  // namespace lambert
