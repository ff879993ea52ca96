// Radiosity against the truth: the default method at ~5,000 patches on the Cornell box agrees
// with the unbiased path tracer at every vertex (away from the light's rim and not inside the
// blocks) to a relative RMSE under 5%, and is much closer than seed 000's point-to-point method
// on the seed's own mesh size.
#include <gtest/gtest.h>

#include "lambert/engine/radiosity.h"
#include "lambert/io/vertices.h"
#include "lambert/reference/compare.h"
#include "lambert/reference/reference.h"
#include "lambert/scene/builtin.h"

namespace lambert {
namespace {

std::unique_ptr<Radiosity> solved(const Scene& scene, std::size_t patches, FormFactorMethod method) {
  RadiosityOptions options;
  options.meshing = MeshStrategy::Uniform;
  options.uniform.targetPatches = patches;
  options.formFactors.method = method;
  options.formFactors.showProgress = false;
  auto engine = Radiosity::create(scene, options);
  EXPECT_TRUE(engine.ok());
  EXPECT_TRUE((*engine)->solve().ok());
  return std::move(*engine);
}

VertexComparison againstReference(const Scene& scene, const SolutionView& solution) {
  ReferenceOptions options;
  options.vertexSamples = 1024;
  options.showProgress = false;
  ReferenceRenderer reference(scene, subdivideScene(scene, 2 * sceneDiagonal(scene)), options);
  std::vector<VertexSample> truth = vertexSamples(solution.vertexMesh(), reference.vertexRadiance(solution.vertexMesh()));
  Result<VertexComparison> comparison = compareVertices(scene, vertexSamples(solution), truth);
  EXPECT_TRUE(comparison.ok());
  return *comparison;
}

TEST(AgreementTest, CornellBoxRadiosityMatchesThePathTracer) {
  Scene scene = cornellBox();
  VertexComparison comparison = againstReference(scene, solved(scene, 5000, FormFactorMethod::AreaMonteCarlo)->solution());
  EXPECT_GT(comparison.error.count, 3 * 2500u);
  EXPECT_GT(comparison.covered, 0u);  // the floor under the blocks is left out
  EXPECT_LT(comparison.error.relativeRmse, 0.05);
}

TEST(AgreementTest, SeedPointToPointIsFurtherFromTheTruth) {
  Scene scene = cornellBox();
  double mcError = againstReference(scene, solved(scene, 784, FormFactorMethod::AreaMonteCarlo)->solution()).error.relativeRmse;
  double pointError = againstReference(scene, solved(scene, 784, FormFactorMethod::PointToPoint)->solution()).error.relativeRmse;
  EXPECT_GT(pointError, 1.3 * mcError) << "point " << pointError << " mc " << mcError;
}

}  // namespace
}  // namespace lambert
