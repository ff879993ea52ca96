// Radiosity against the truth: the default method at ~5,000 patches on the Cornell box agrees
// with the unbiased path tracer at every vertex (away from the light's rim and not inside the
// blocks) to a relative RMSE under 5%, and is much closer than seed 000's point-to-point method
// on the seed's own mesh size.
#include <gtest/gtest.h>

#include "lambert/pipeline/compare.h"
#include "lambert/pipeline/pipeline.h"
#include "lambert/reference/reference.h"
#include "lambert/scene/builtin.h"

namespace lambert {
namespace {

VertexComparison againstReference(const Scene& scene, const RadiositySolution& solution) {
  ReferenceOptions options;
  options.vertexSamples = 1024;
  options.showProgress = false;
  ReferenceRenderer reference(scene, subdivideScene(scene, 2 * sceneDiagonal(scene)), options);
  std::vector<VertexSample> truth = vertexSamples(solution.mesh, reference.vertexRadiance(solution.mesh));
  Result<VertexComparison> comparison = compareVertices(scene, vertexSamples(solution.mesh, solution.vertexRadiance()), truth);
  EXPECT_TRUE(comparison.ok());
  return *comparison;
}

TEST(AgreementTest, CornellBoxRadiosityMatchesThePathTracer) {
  Scene scene = cornellBox();
  PipelineOptions options;
  options.targetPatches = 5000;
  options.formFactors.showProgress = false;
  RadiositySolution solution = solveScene(scene, options);
  VertexComparison comparison = againstReference(scene, solution);
  EXPECT_GT(comparison.error.count, 3 * 2500u);
  EXPECT_GT(comparison.covered, 0u);  // the floor under the blocks is left out
  EXPECT_LT(comparison.error.relativeRmse, 0.05);
}

TEST(AgreementTest, SeedPointToPointIsFurtherFromTheTruth) {
  Scene scene = cornellBox();
  PipelineOptions options;
  options.targetPatches = 784;
  options.formFactors.showProgress = false;
  RadiositySolution mc = solveScene(scene, options);
  options.formFactors.method = FormFactorMethod::PointToPoint;
  RadiositySolution point = solveScene(scene, options);
  double mcError = againstReference(scene, mc).error.relativeRmse;
  double pointError = againstReference(scene, point).error.relativeRmse;
  EXPECT_GT(pointError, 1.3 * mcError) << "point " << pointError << " mc " << mcError;
}

}  // namespace
}  // namespace lambert
