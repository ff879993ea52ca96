#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <set>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "lambert/flat/form_factors.h"
#include "lambert/formfactor/kernels.h"
#include "lambert/geometry/ray_caster.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

using testing::relativeError;
using testing::surfaceFormFactor;

FormFactorMatrix formFactorsOf(const Mesh& mesh, FormFactorOptions options = {}) {
  options.showProgress = false;
  auto caster = makeEmbreeRayCaster(mesh);
  return computeFormFactors(mesh, *caster, options);
}

// Howell's catalogue, with the default estimator, from two triangles per square up to a fine mesh.
void expectSurfaceFormFactor(const Scene& scene, double expected) {
  for (double maxEdge : {2.0, 0.5, 0.2}) {
    Mesh mesh = subdivideScene(scene, maxEdge);
    double f = surfaceFormFactor(mesh, formFactorsOf(mesh), 0, 1);
    EXPECT_LT(relativeError(f, expected), 0.01) << "max edge " << maxEdge << ": F = " << f;
  }
}

TEST(FormFactorTest, ParallelSquaresMatchHowell) { expectSurfaceFormFactor(testing::parallelSquares(), 0.19982); }

TEST(FormFactorTest, PerpendicularSquaresMatchHowell) { expectSurfaceFormFactor(testing::perpendicularSquares(), 0.20004); }

// A small patch facing a coaxial disk of radius R at height H: F = R² / (H² + R²).
TEST(FormFactorTest, SmallPatchToCoaxialDisk) {
  for (auto [radius, height] : {std::pair{1.0, 1.0}, {1.0, 2.0}, {2.0, 1.0}}) {
    const int sides = 96;
    const double r = radius * std::sqrt(2 * kPi / (sides * std::sin(2 * kPi / sides)));  // equal area
    Surface disk{"disk", {}, 0, {}};
    for (int k = 0; k < sides; ++k) {
      double phi = -2 * kPi * k / sides;
      disk.vertices.push_back({r * std::cos(phi), r * std::sin(phi), height});
    }
    const double h = 1e-3;
    Surface element{"element", {{-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}}, 0, {}};
    Scene scene = testing::sceneOf({element, disk});
    Mesh mesh = subdivideScene(scene, 10 * radius);
    double f = surfaceFormFactor(mesh, formFactorsOf(mesh), 0, 1);
    double expected = radius * radius / (height * height + radius * radius);
    EXPECT_LT(relativeError(f, expected), 0.01) << "R " << radius << " H " << height << ": F = " << f;
  }
}

// The exact F_ij of two patches that see each other whole: 1/A_i ∫_{A_i} F(x → P_j) dA, with the
// point-to-polygon factor in closed form (Lambert's contour integral, checked against Howell's
// catalogue to 1e-12 in kernels_test) and the outer integral by the midpoint rule over 4^5
// sub-triangles of i (the integrand is smooth on i, so this is exact to well under 1e-4).
double exactFormFactor(const Mesh& mesh, std::size_t i, std::size_t j) {
  const PatchCorners target = mesh.corners(j);
  const std::vector<Vec3> polygon(target.begin(), target.end());
  std::vector<std::array<Vec3, 3>> triangles;
  const PatchCorners source = mesh.corners(i);
  for (std::size_t k = 1; k + 1 < source.size(); ++k) triangles.push_back({source[0], source[k], source[k + 1]});
  for (int level = 0; level < 5; ++level) {
    std::vector<std::array<Vec3, 3>> finer;
    for (const auto& t : triangles) {
      const Vec3 a = (t[0] + t[1]) * 0.5, b = (t[1] + t[2]) * 0.5, c = (t[2] + t[0]) * 0.5;
      finer.push_back({t[0], a, c});
      finer.push_back({a, t[1], b});
      finer.push_back({c, b, t[2]});
      finer.push_back({a, b, c});
    }
    triangles = std::move(finer);
  }
  double weighted = 0, area = 0;
  for (const auto& t : triangles) {
    const double a = 0.5 * length(cross(t[1] - t[0], t[2] - t[0]));
    weighted += a * pointToPolygonFormFactor((t[0] + t[1] + t[2]) / 3.0, mesh.patches[i].normal, polygon, mesh.patches[j].normal);
    area += a;
  }
  return weighted / area;
}

// Each unordered pair is estimated once and the other half of F filled by reciprocity; both halves
// must match the exact factors, each direction's computed on its own (a fill that took the area
// ratio upside down, or that scaled the estimate, misses the exact F_ji however good F_ij is). At
// 16 pairs (256 kernel points for near pairs) the unoccluded estimate is a quasi-Monte Carlo mean
// of the exact point-to-polygon factor: its error is a small fraction of the factor's variation
// over i, and over all pairs of the two squares the power-weighted error stays well under 1%.
TEST(FormFactorTest, BothHalvesOfTheMatrixMatchTheExactFactors) {
  // Howell's squares, and a 0.7 × 0.45 rectangle tilted over the unit square, whose triangles'
  // areas differ from the square's (so that A_i / A_j is not 1).
  Scene tilted = testing::sceneOf({testing::parallelSquares().surfaces[0],
                                   {"tilted", {{0.2, 0.1, 0.8}, {0.2, 0.55, 0.6}, {0.9, 0.55, 0.6}, {0.9, 0.1, 0.8}}, 0, {}}});
  for (const Scene& scene : {testing::parallelSquares(), testing::perpendicularSquares(), tilted}) {
    const Mesh mesh = subdivideScene(scene, 0.5);
    const FormFactorMatrix F = formFactorsOf(mesh);
    double estimatedError = 0, filledError = 0, exactSum = 0;
    int pairs = 0;
    for (std::size_t i = 0; i < mesh.numPatches(); ++i)
      for (std::size_t j = i + 1; j < mesh.numPatches(); ++j) {
        if (mesh.patches[i].surface == mesh.patches[j].surface) continue;
        const double forward = exactFormFactor(mesh, i, j), backward = exactFormFactor(mesh, j, i);
        ASSERT_GT(forward, 0);
        // Power-weighted (A_i F_ij), so every pair counts by what it carries.
        estimatedError += mesh.patches[i].area * std::fabs(F(i, j) - forward);
        filledError += mesh.patches[j].area * std::fabs(F(j, i) - backward);
        exactSum += mesh.patches[i].area * forward;
        ++pairs;
      }
    EXPECT_GT(pairs, 50);
    std::printf("%s: mean error of the estimated half %.3g%%, of the filled half %.3g%%\n", scene.surfaces[1].name.c_str(),
                100 * estimatedError / exactSum, 100 * filledError / exactSum);
    EXPECT_LT(estimatedError / exactSum, 0.01) << scene.surfaces[1].name;
    EXPECT_LT(filledError / exactSum, 0.01) << scene.surfaces[1].name;
    if (scene.surfaces[1].name == "tilted") continue;
    // And whole squares both ways against Howell's closed form (the two squares are equal).
    const double howell = scene.surfaces[1].name == "top" ? 0.19982 : 0.20004;
    EXPECT_LT(relativeError(surfaceFormFactor(mesh, F, 0, 1), howell), 0.01);
    EXPECT_LT(relativeError(surfaceFormFactor(mesh, F, 1, 0), howell), 0.01);
  }
}

// An empty closed box: what leaves a patch arrives somewhere, so every row sums to one.
TEST(FormFactorTest, ClosedBoxRowsSumToOne) {
  Mesh mesh = subdivideScene(testing::closedCube(), 0.3);
  FormFactorMatrix F = formFactorsOf(mesh);
  for (std::size_t i = 0; i < mesh.numPatches(); ++i)
    EXPECT_NEAR(F.row(static_cast<Eigen::Index>(i)).cast<double>().sum(), 1.0, 0.01) << "patch " << i;
}

// The Cornell box closed by a portal: occluders (the blocks) and adjacent patches at every
// corner, so the rows test visibility too. Floor patches under the blocks and ceiling patches
// behind the light see less than a hemisphere of the room, so those two surfaces are left out.
// What remains is the known bias of weighting the analytic kernel by a visible-area fraction
// under partial occlusion (≈0.5% at 256 samples) plus noise.
TEST(FormFactorTest, ClosedCornellBoxRowsSumToOne) {
  Scene scene = testing::closedCornellBox();
  Mesh mesh = subdivideScene(scene, edgeLengthForPatchCount(scene, 800));
  // The mean over rows at the default sample count; the worst row at 64 pairs, where the noise
  // that dominates single rows at 16 has fallen well below the bias.
  for (int samples : {16, 64}) {
    FormFactorOptions options;
    options.samplePairs = samples;
    FormFactorMatrix F = formFactorsOf(mesh, options);
    double worst = 0, meanError = 0;
    int rows = 0;
    for (std::size_t i = 0; i < mesh.numPatches(); ++i) {
      const std::string& surface = scene.surfaces[mesh.patches[i].surface].name;
      if (surface == "floor" || surface == "ceiling") continue;
      double error = std::fabs(F.row(static_cast<Eigen::Index>(i)).cast<double>().sum() - 1);
      worst = std::fmax(worst, error);
      meanError += error;
      ++rows;
    }
    meanError /= rows;
    EXPECT_GT(rows, 400);
    EXPECT_LT(meanError, 0.005) << samples << " samples";
    if (samples == 64) {
      EXPECT_LT(worst, 0.015);
    }
  }
}

// The estimate of a pair depends on (seed, i, j) alone: the same matrix, bit for bit, whether one
// thread computes it or eight share it (each in its own arena, so the work is really spread over
// eight threads, even on a machine with fewer cores), and another seed gives another matrix.
TEST(FormFactorTest, ResultsDoNotDependOnThreadsAndFollowTheSeed) {
  Mesh mesh = subdivideScene(cornellBox(), 150);
  FormFactorOptions options;
  auto withThreads = [&](int threads, std::set<int>* used) {
    tbb::global_control allow(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    tbb::task_arena arena(threads);
    FormFactorMatrix F;
    arena.execute([&] {
      F = formFactorsOf(mesh, options);
      // The arena does run that many threads: a parallel loop in it lands on several.
      std::mutex mutex;
      tbb::parallel_for(0, 4096, [&](int) {
        volatile double sink = 0;
        for (int k = 0; k < 2000; ++k) sink = sink + std::sqrt(static_cast<double>(k));
        const std::lock_guard<std::mutex> lock(mutex);
        used->insert(tbb::this_task_arena::current_thread_index());
      });
    });
    return F;
  };
  std::set<int> one, eight;
  FormFactorMatrix a = withThreads(1, &one);
  FormFactorMatrix b = withThreads(8, &eight);
  EXPECT_EQ(one.size(), 1u);
  EXPECT_GT(eight.size(), 1u);
  EXPECT_EQ((a - b).cwiseAbs().maxCoeff(), 0.0f);
  options.seed = 2;
  FormFactorMatrix c = withThreads(8, &eight);
  EXPECT_GT((a - c).cwiseAbs().maxCoeff(), 0.0f);
}

// The point-to-point estimator converges only as patches shrink, and overshoots between neighbours.
TEST(FormFactorTest, PointToPointIsTheSeedsCoarseEstimate) {
  Scene scene = testing::parallelSquares();
  FormFactorOptions point;
  point.method = FormFactorMethod::PointToPoint;
  Mesh fine = subdivideScene(scene, 0.1);
  EXPECT_LT(relativeError(surfaceFormFactor(fine, formFactorsOf(fine, point), 0, 1), 0.19982), 0.02);
  Mesh coarse = subdivideScene(scene, 2);
  EXPECT_GT(relativeError(surfaceFormFactor(coarse, formFactorsOf(coarse, point), 0, 1), 0.19982), 0.05);
}

}  // namespace
}  // namespace lambert
