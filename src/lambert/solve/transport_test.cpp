#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "lambert/core/rng.h"
#include "lambert/solve/energy.h"
#include "lambert/solve/solver.h"
#include "lambert/solve/transport.h"

namespace lambert {
namespace {

// Every figure below is a sum of products of powers of two, so float F and double B hold them
// exactly and the expected values are exact.
std::shared_ptr<const FormFactorMatrix> threeByThree() {
  auto F = std::make_shared<FormFactorMatrix>(3, 3);
  *F << 0.0f, 0.5f, 0.25f,  //
      0.125f, 0.0f, 0.5f,   //
      0.25f, 0.25f, 0.0f;
  return F;
}

const std::vector<Rgb> kStart{{1, 2, 4}, {2, 0, 1}, {4, 1, 0}};
const std::vector<Rgb> kEmitted{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const std::vector<Rgb> kAlbedo(3, Rgb::gray(0.5));

void expectRgb(const Rgb& actual, const Rgb& expected, const char* what) {
  for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(actual[c], expected[c]) << what << " channel " << c;
}

TEST(TransportTest, DenseGatherIsTheMatrixTimesRadiosity) {
  DenseTransport transport(threeByThree());
  EXPECT_EQ(transport.size(), 3u);
  ASSERT_NE(transport.matrix(), nullptr);
  std::vector<Rgb> irradiance(7, Rgb::gray(-1));  // resized, and every entry overwritten
  transport.gather(kStart, irradiance);
  ASSERT_EQ(irradiance.size(), 3u);
  expectRgb(irradiance[0], {0.5 * 2 + 0.25 * 4, 0.5 * 0 + 0.25 * 1, 0.5 * 1 + 0.25 * 0}, "H0");  // (2, 0.25, 0.5)
  expectRgb(irradiance[1], {0.125 * 1 + 0.5 * 4, 0.125 * 2 + 0.5 * 1, 0.125 * 4 + 0.5 * 0}, "H1");  // (2.125, 0.75, 0.5)
  expectRgb(irradiance[2], {0.25 * 1 + 0.25 * 2, 0.25 * 2 + 0.25 * 0, 0.25 * 4 + 0.25 * 1}, "H2");  // (0.75, 0.5, 1.25)
}

// Jacobi: every row from the previous iterate, B'_i = E_i + ρ_i H_i(B) with H from the test above.
TEST(TransportTest, JacobiSweepUsesThePreviousIterate) {
  DenseTransport transport(threeByThree());
  std::vector<Rgb> radiosity = kStart;
  SweepChange step = transport.sweep(kEmitted, kAlbedo, radiosity, /*inPlace=*/false);
  ASSERT_EQ(radiosity.size(), 3u);
  expectRgb(radiosity[0], {1 + 0.5 * 2, 0 + 0.5 * 0.25, 0 + 0.5 * 0.5}, "B0");     // (2, 0.125, 0.25)
  expectRgb(radiosity[1], {0 + 0.5 * 2.125, 1 + 0.5 * 0.75, 0 + 0.5 * 0.5}, "B1");  // (1.0625, 1.375, 0.25)
  expectRgb(radiosity[2], {0 + 0.5 * 0.75, 0 + 0.5 * 0.5, 1 + 0.5 * 1.25}, "B2");   // (0.375, 0.25, 1.625)
  // |ΔB|: patch 0 (1, 1.875, 3.75), patch 1 (0.9375, 1.375, 0.75), patch 2 (3.625, 0.75, 1.625).
  EXPECT_DOUBLE_EQ(step.change, 3.75);
  EXPECT_DOUBLE_EQ(step.magnitude, 2);
}

// Gauss–Seidel: rows in order, each reading the rows above it already updated.
TEST(TransportTest, InPlaceSweepUsesEachNewValueAtOnce) {
  DenseTransport transport(threeByThree());
  std::vector<Rgb> radiosity = kStart;
  SweepChange step = transport.sweep(kEmitted, kAlbedo, radiosity, /*inPlace=*/true);
  // Row 0 sees only old values: as Jacobi, (2, 0.125, 0.25).
  expectRgb(radiosity[0], {2, 0.125, 0.25}, "B0");
  // Row 1: E1 + ½(⅛ B0_new + ½ B2_old) = (0,1,0) + ½((0.25, 0.015625, 0.03125) + (2, 0.5, 0)).
  expectRgb(radiosity[1], {0.5 * 2.25, 1 + 0.5 * 0.515625, 0.5 * 0.03125}, "B1");  // (1.125, 1.2578125, 0.015625)
  // Row 2: E2 + ½(¼ B0_new + ¼ B1_new) = (0,0,1) + ⅛((2, 0.125, 0.25) + (1.125, 1.2578125, 0.015625)).
  expectRgb(radiosity[2], {0.125 * 3.125, 0.125 * 1.3828125, 1 + 0.125 * 0.265625}, "B2");  // (0.390625, 0.1728515625, 1.033203125)
  // |ΔB|: patch 0 3.75 (blue), patch 1 1.2578125 (green), patch 2 3.609375 (red).
  EXPECT_DOUBLE_EQ(step.change, 3.75);
  EXPECT_DOUBLE_EQ(step.magnitude, 2);
}

// Past the parallel grain the rows run on several threads: gather and the Jacobi sweep still give
// what a plain loop over Eigen's product gives.
TEST(TransportTest, ParallelRowsMatchASerialProduct) {
  constexpr int n = 200;
  auto F = std::make_shared<FormFactorMatrix>(n, n);
  Pcg32 rng(5, 9);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) (*F)(i, j) = i == j ? 0.0f : static_cast<float>(rng.nextDouble() * 2.0 / n);
  std::vector<Rgb> radiosity(n), emitted(n), albedo(n);
  for (int i = 0; i < n; ++i) {
    radiosity[i] = {rng.nextDouble(), rng.nextDouble(), rng.nextDouble()};
    emitted[i] = {rng.nextDouble(), 0, rng.nextDouble()};
    albedo[i] = {0.5, 0.25, 0.75};
  }
  const Eigen::MatrixXd Fd = F->cast<double>();
  DenseTransport transport(F);
  std::vector<Rgb> irradiance;
  transport.gather(radiosity, irradiance);
  std::vector<Rgb> jacobi = radiosity;
  transport.sweep(emitted, albedo, jacobi, /*inPlace=*/false);
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd b(n);
    for (int i = 0; i < n; ++i) b[i] = radiosity[i][c];
    const Eigen::VectorXd h = Fd * b;
    for (int i = 0; i < n; ++i) {
      EXPECT_NEAR(irradiance[i][c], h[i], 1e-12) << "row " << i;
      EXPECT_NEAR(jacobi[i][c], emitted[i][c] + albedo[i][c] * h[i], 1e-12) << "row " << i;
    }
  }
}

// Two patches, A_0 = 1 and A_1 = 2 scene units² at 0.5 m a unit (0.25 and 0.5 m²), seeing each
// other reciprocally (A_0 F_01 = A_1 F_10) and nothing else: rows sum to ½ and ¼, the rest escapes.
RadiosityProblem twoPatches(float f01, float f10) {
  auto F = std::make_shared<FormFactorMatrix>(2, 2);
  *F << 0.0f, f01,  //
      f10, 0.0f;
  RadiosityProblem problem;
  problem.transport = std::make_shared<DenseTransport>(F);
  problem.emitted = {{31, 62, 0}, {0, 0, 0}};
  problem.albedo = {Rgb::gray(0.5), Rgb::gray(0.5)};
  problem.area = {1, 2};
  return problem;
}

TEST(TransportTest, EnergyBalanceOfTwoPatches) {
  RadiosityProblem problem = twoPatches(0.5f, 0.25f);
  // B_0 = E_0 + ½·½·B_1, B_1 = ½·¼·B_0, so B_0 = E_0 · 32/31 and B_1 = B_0 / 8.
  const std::vector<Rgb> radiosity{{32, 64, 0}, {4, 8, 0}};
  ASSERT_LT(relativeResidual(problem, radiosity), 1e-15);  // it is the solution
  EnergyBalance balance = energyBalance(problem, radiosity, 0.5);
  // H_0 = ½ B_1 = (2, 4, 0), H_1 = ¼ B_0 = (8, 16, 0); every figure in watts of luminance.
  auto Y = [](double r, double g, double b) { return Rgb{r, g, b}.luminance(); };
  EXPECT_NEAR(balance.emittedWatts, 0.25 * Y(31, 62, 0), 1e-12);
  EXPECT_NEAR(balance.absorbedWatts, 0.25 * 0.5 * Y(2, 4, 0) + 0.5 * 0.5 * Y(8, 16, 0), 1e-12);
  // Leaving Σ A B = 0.25·B_0 + 0.5·B_1, arriving Σ A H = 0.25·H_0 + 0.5·H_1; the same as
  // Σ A_i B_i (1 − Σ_j F_ij) = 0.25·B_0·½ + 0.5·B_1·¾ since F is reciprocal.
  EXPECT_NEAR(balance.escapedWatts, 0.25 * Y(32, 64, 0) * 0.5 + 0.5 * Y(4, 8, 0) * 0.75, 1e-12);
  EXPECT_NEAR(balance.absorbedWatts + balance.escapedWatts, balance.emittedWatts, 1e-12);
}

// Rows normalised to one break reciprocity (A_0 F_01 = 1 ≠ A_1 F_10 = 2): the large patch
// receives more than the small one sends. No row sum says so; leaving minus arriving does.
TEST(TransportTest, EnergyBalanceShowsPowerANonReciprocalMatrixMakes) {
  RadiosityProblem problem = twoPatches(1.0f, 1.0f);
  const std::vector<Rgb> radiosity{Rgb::gray(2), Rgb::gray(1)};  // any B, not a solution
  EnergyBalance balance = energyBalance(problem, radiosity, 0.5);
  // H_0 = B_1 = 1, H_1 = B_0 = 2 (grey: its luminance). Leaving 0.25·2 + 0.5·1 = 1, arriving
  // 0.25·1 + 0.5·2 = 1.25.
  EXPECT_NEAR(balance.escapedWatts, 1 - 1.25, 1e-12);
  EXPECT_NEAR(balance.absorbedWatts, 0.25 * 0.5 * 1 + 0.5 * 0.5 * 2, 1e-12);
}

}  // namespace
}  // namespace lambert
