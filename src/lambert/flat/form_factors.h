#pragma once
// The form-factor matrix F of a mesh: F(i, j) is the fraction of the power leaving patch i that
// arrives at patch j. Each unordered pair is estimated once; reciprocity A_i F_ij = A_j F_ji
// fills the other half.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "lambert/formfactor/matrix.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/mesh/mesh.h"
#include "lambert/method/flat_options.h"

namespace lambert {


// Whether a method estimates one pair at a time (and so fills F by reciprocity, and can serve
// PairFormFactors); the hemi-cube and hemisphere methods estimate whole rows.
bool isPairMethod(FormFactorMethod method);



struct FormFactorStats {
  std::uint64_t pairsEvaluated = 0;  // unordered pairs that could see each other (rows: n − 1 each)
  std::uint64_t pairsCulled = 0;     // unordered pairs facing away (coplanar, behind): F = 0
  std::uint64_t visibilityRays = 0;
  double seconds = 0;
};

// F for one pair of a mesh's patches at a time: what computeFormFactors does for every pair, for
// callers that need only some (the quad-tree's master table). Not thread-safe: one per thread.
// The mesh may grow between calls; results depend only on the pair's geometry, (i, j) and the seed.
class PairFormFactors {
 public:
  PairFormFactors(const Mesh& mesh, const RayCaster& caster, const FormFactorOptions& options);

  // Whether i and j cannot exchange light (same surface, or one wholly behind the other): F = 0
  // both ways, and no rays are needed.
  bool culled(std::size_t i, std::size_t j) const;
  // F_ij for a pair that is not culled; reciprocity gives F_ji = F_ij A_i / A_j.
  double estimate(std::size_t i, std::size_t j);

 private:
  Ray segment(const Vec3& x, const Vec3& xNormal, const Vec3& y, const Vec3& yNormal) const;
  bool nearField(std::size_t i, std::size_t j) const;
  Vec3 seedSamplePoint(std::size_t patch) const;
  double pointToPoint(std::size_t i, std::size_t j);
  double areaMonteCarlo(std::size_t i, std::size_t j);

  const Mesh& mesh_;
  const RayCaster& caster_;
  FormFactorOptions options_;
  double epsilon_;
  // Scratch, reused across pairs.
  std::vector<double> kernels_;
  std::vector<Ray> rays_;
  std::unique_ptr<bool[]> occluded_;  // not vector<bool>: the caster writes plain bools
  std::size_t occludedCapacity_ = 0;
};

FormFactorMatrix computeFormFactors(const Mesh& mesh, const RayCaster& caster, const FormFactorOptions& options,
                                    FormFactorStats* stats = nullptr);

}  // namespace lambert
