#include <gtest/gtest.h>

#include "lambert/flat/form_factors.h"
#include "lambert/flat/hemicube.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

using testing::relativeError;
using testing::surfaceFormFactor;

FormFactorMatrix rows(const Mesh& mesh, FormFactorMethod method, int resolution = 256, int rays = 4096) {
  FormFactorOptions options;
  options.method = method;
  options.hemicubeResolution = resolution;
  options.hemisphereRays = rays;
  options.showProgress = false;
  auto caster = makeEmbreeRayCaster(mesh);
  return computeFormFactors(mesh, *caster, options);
}

TEST(HemicubeTest, DeltaFormFactorsSumToOne) {
  for (int resolution : {2, 16, 256}) EXPECT_NEAR(Hemicube(resolution).sum(), 1.0, 1e-6) << resolution;
  // Symmetric, largest at the zenith, and every delta positive.
  Hemicube cube(64);
  EXPECT_DOUBLE_EQ(cube.topDelta(0, 0), cube.topDelta(63, 63));
  EXPECT_GT(cube.topDelta(31, 31), cube.topDelta(0, 31));
  EXPECT_LT(cube.sideDelta(10, 0), cube.sideDelta(10, 31));  // grazing near the base plane, steeper at the rim
  EXPECT_GT(cube.sideDelta(0, 31), 0);
}

// Howell's cases at resolution 256, on meshes fine enough that sampling each patch at its centre
// (the hemi-cube's proximity error) is small.
TEST(HemicubeTest, HowellCasesWithinTwoPercent) {
  Mesh parallel = subdivideScene(testing::parallelSquares(), 0.2);
  EXPECT_LT(relativeError(surfaceFormFactor(parallel, rows(parallel, FormFactorMethod::Hemicube), 0, 1), 0.19982), 0.02);
  Mesh perpendicular = subdivideScene(testing::perpendicularSquares(), 0.2);
  EXPECT_LT(relativeError(surfaceFormFactor(perpendicular, rows(perpendicular, FormFactorMethod::Hemicube), 0, 1), 0.20004), 0.02);
}

TEST(HemicubeTest, ClosedBoxRowsSumToOne) {
  Mesh mesh = subdivideScene(testing::closedCube(), 0.3);
  FormFactorMatrix F = rows(mesh, FormFactorMethod::Hemicube, 128);
  for (Eigen::Index i = 0; i < F.rows(); ++i) EXPECT_NEAR(F.row(i).cast<double>().sum(), 1.0, 1e-3) << i;
}

// Occlusion: a blocker between the squares hides what it covers from the hemi-cube.
TEST(HemicubeTest, BlockersOcclude) {
  Scene scene = testing::parallelSquares();
  scene.surfaces.push_back({"blocker", {{-1, -1, 0.5}, {2, -1, 0.5}, {2, 2, 0.5}, {-1, 2, 0.5}}, 0, {}});
  Mesh mesh = subdivideScene(scene, 0.5);
  FormFactorMatrix F = rows(mesh, FormFactorMethod::Hemicube, 64);
  EXPECT_EQ(surfaceFormFactor(mesh, F, 0, 1), 0.0);  // its back faces the bottom square: hidden, and black
}

TEST(HemisphereTest, HowellCasesAndRowSums) {
  Mesh parallel = subdivideScene(testing::parallelSquares(), 0.5);
  EXPECT_LT(relativeError(surfaceFormFactor(parallel, rows(parallel, FormFactorMethod::HemisphereRays), 0, 1), 0.19982), 0.02);
  Mesh perpendicular = subdivideScene(testing::perpendicularSquares(), 0.5);
  EXPECT_LT(relativeError(surfaceFormFactor(perpendicular, rows(perpendicular, FormFactorMethod::HemisphereRays), 0, 1), 0.20004), 0.02);
  Mesh box = subdivideScene(testing::closedCube(), 0.5);
  FormFactorMatrix F = rows(box, FormFactorMethod::HemisphereRays, 0, 512);
  for (Eigen::Index i = 0; i < F.rows(); ++i) EXPECT_NEAR(F.row(i).cast<double>().sum(), 1.0, 1e-6) << "every ray lands";
}

}  // namespace
}  // namespace lambert
