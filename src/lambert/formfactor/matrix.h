#pragma once
// The form-factor matrix F: F(i, j) is the fraction of the power leaving patch i that arrives at
// patch j. Its own header, so the solvers can read F without knowing how it was estimated.
#include <Eigen/Core>

namespace lambert {

// Row-major so that a gather over row i (Gauss–Seidel, shooting via reciprocity) reads contiguous
// memory; single precision halves the bandwidth those sweeps are bound by.
using FormFactorMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

}  // namespace lambert
