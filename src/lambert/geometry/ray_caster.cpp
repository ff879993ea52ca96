#include "lambert/geometry/ray_caster.h"

#include <cmath>

namespace lambert {

void RayCaster::occluded(std::span<const Ray> rays, std::span<bool> out) const {
  for (std::size_t i = 0; i < rays.size(); ++i) out[i] = occluded(rays[i]);
}

double rayEpsilon(const Mesh& mesh) {
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const Vec3& p : mesh.positions) {
    lo = componentMin(lo, p);
    hi = componentMax(hi, p);
  }
  // Single-precision BVH coordinates carry ~1e-7 relative error; stay two orders above it.
  return 1e-5 * length(hi - lo);
}

}  // namespace lambert
