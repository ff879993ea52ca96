#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "lambert/core/rng.h"
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

}  // namespace
}  // namespace lambert
