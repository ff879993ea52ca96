#include <vector>

#include "lambert/geometry/ray_caster.h"

namespace lambert {
namespace {

class BruteForceRayCaster final : public RayCaster {
 public:
  // Copies the patches it needs: the caster holds no reference to a mesh that could move away.
  explicit BruteForceRayCaster(const Mesh& mesh) : mesh_(mesh) {}

  bool occluded(const Ray& ray) const override {
    countRays(1);
    for (std::size_t i = 0; i < mesh_.numPatches(); ++i)
      if (hitPatch(ray, i)) return true;
    return false;
  }

  std::optional<RayHit> intersect(const Ray& ray) const override {
    countRays(1);
    std::optional<RayHit> nearest;
    Ray shrinking = ray;
    for (std::size_t i = 0; i < mesh_.numPatches(); ++i) {
      if (auto t = hitPatch(shrinking, i)) {
        bool front = dot(ray.direction, mesh_.patches[i].normal) < 0;
        if (!front && mesh_.patches[i].twinned) continue;  // its twin, lying on it, is the hit
        nearest = RayHit{*t, static_cast<std::uint32_t>(i), front};
        shrinking.tMax = *t;
      }
    }
    return nearest;
  }

 private:
  // The nearest hit on the patch's fan triangles.
  std::optional<double> hitPatch(const Ray& ray, std::size_t patch) const {
    PatchCorners c = mesh_.corners(patch);
    std::optional<double> nearest;
    for (std::size_t k = 1; k + 1 < c.size(); ++k)
      if (auto t = hitTriangle(ray, c[0], c[k], c[k + 1]); t && (!nearest || *t < *nearest)) nearest = t;
    return nearest;
  }

  // Möller–Trumbore, double precision, both sides.
  static std::optional<double> hitTriangle(const Ray& ray, const Vec3& a, const Vec3& b, const Vec3& c) {
    Vec3 e1 = b - a, e2 = c - a;
    Vec3 p = cross(ray.direction, e2);
    double det = dot(e1, p);
    if (std::abs(det) < 1e-300) return std::nullopt;
    double inv = 1 / det;
    Vec3 s = ray.origin - a;
    double u = dot(s, p) * inv;
    if (u < 0 || u > 1) return std::nullopt;
    Vec3 q = cross(s, e1);
    double v = dot(ray.direction, q) * inv;
    if (v < 0 || u + v > 1) return std::nullopt;
    double t = dot(e2, q) * inv;
    if (t < ray.tMin || t > ray.tMax) return std::nullopt;
    return t;
  }

  const Mesh mesh_;
};

}  // namespace

std::unique_ptr<RayCaster> makeBruteForceRayCaster(const Mesh& mesh) {
  return std::make_unique<BruteForceRayCaster>(mesh);
}

}  // namespace lambert
