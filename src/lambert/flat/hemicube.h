#pragma once
// Row-at-a-time form factors from a point at each patch's centroid.
//
// Hemi-cube (Cohen & Greenberg, "The Hemi-Cube: A Radiosity Solution for Complex Environments",
// SIGGRAPH 1985): every other patch is rasterised with a z-buffer onto the five faces of
// a unit half-cube over the patch, and F_ij is the sum of the delta form factors of the pixels
// where patch j is the nearest front face. Each pixel's delta form factor here is the exact
// form factor of its square (Lambert's contour integral) rather than the usual midpoint
// approximation, so the deltas sum to one to rounding.
//   Cost: 3·res² pixels and every patch drawn five times, per row.
//   Failure modes: aliasing (a patch smaller than a pixel's solid angle is missed or counted
//   whole: stripes and noise on small or distant patches); the proximity error of sampling at
//   one point (adjacent patches, whose factor varies across patch i); and visibility judged from
//   the centre only.
//
// Hemisphere ray casting: cosine-distributed rays from low-discrepancy points over patch i;
// F_ij is the fraction that reaches patch j's front. Unbiased for the area-averaged factor, with
// noise √(F(1−F)/N) per entry and no proximity error.
#include <cstdint>
#include <vector>

#include "lambert/geometry/ray_caster.h"
#include "lambert/mesh/mesh.h"

namespace lambert {

class Hemicube {
 public:
  // resolution: pixels along the top face (even, ≥ 2); side faces are resolution × resolution/2.
  explicit Hemicube(int resolution);

  int resolution() const { return resolution_; }
  // Delta form factor of top-face pixel (x, y) and of side-face pixel (x, z), z counted up from
  // the base plane; all four side faces share one table by symmetry.
  double topDelta(int x, int y) const { return top_[static_cast<std::size_t>(y) * resolution_ + x]; }
  double sideDelta(int x, int z) const { return side_[static_cast<std::size_t>(z) * resolution_ + x]; }
  // Σ of every delta form factor on the five faces: one, to rounding.
  double sum() const;

  // Row i of F: fills row[0 … n) (row[i] = 0). scratch is reused between calls by one thread.
  struct Scratch {
    std::vector<float> depth;
    std::vector<std::int32_t> item;
  };
  void row(const Mesh& mesh, std::size_t i, Scratch& scratch, float* row) const;

 private:
  int resolution_;
  std::vector<double> top_, side_;
};

// Row i of F by `rays` cosine-distributed rays from points spread over patch i.
void hemisphereRow(const Mesh& mesh, const RayCaster& caster, std::size_t i, int rays, std::uint64_t seed, float* row);

}  // namespace lambert
