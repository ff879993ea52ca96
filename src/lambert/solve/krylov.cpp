#include "lambert/solve/krylov.h"

#include <cmath>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

namespace lambert {
namespace {

// I − M as Eigen's iterative solvers ask of a matrix-free operator (a type with rows(), cols()
// and a product, declared to Eigen below).
class IdentityMinus;

}  // namespace
}  // namespace lambert

namespace Eigen::internal {
template <>
struct traits<lambert::IdentityMinus> : public traits<Eigen::SparseMatrix<double>> {};
}  // namespace Eigen::internal

namespace lambert {
namespace {

class IdentityMinus : public Eigen::EigenBase<IdentityMinus> {
 public:
  using Scalar = double;
  using RealScalar = double;
  using StorageIndex = int;
  enum { ColsAtCompileTime = Eigen::Dynamic, MaxColsAtCompileTime = Eigen::Dynamic, IsRowMajor = false };

  IdentityMinus(const std::function<void(const double*, double*)>& applyM, Eigen::Index size) : applyM_(applyM), size_(size) {}
  Eigen::Index rows() const { return size_; }
  Eigen::Index cols() const { return size_; }
  template <typename Rhs>
  Eigen::Product<IdentityMinus, Rhs, Eigen::AliasFreeProduct> operator*(const Eigen::MatrixBase<Rhs>& x) const {
    return Eigen::Product<IdentityMinus, Rhs, Eigen::AliasFreeProduct>(*this, x.derived());
  }
  // dst += alpha (I − M) x
  template <typename Dest, typename Rhs>
  void addProduct(Dest& dst, const Rhs& rhs, double alpha) const {
    const Eigen::VectorXd x = rhs;  // contiguous
    Eigen::VectorXd mx(size_);
    applyM_(x.data(), mx.data());
    dst += alpha * (x - mx);
  }

 private:
  const std::function<void(const double*, double*)>& applyM_;
  Eigen::Index size_;
};

}  // namespace
}  // namespace lambert

namespace Eigen::internal {
template <typename Rhs>
struct generic_product_impl<lambert::IdentityMinus, Rhs, SparseShape, DenseShape, GemvProduct>
    : generic_product_impl_base<lambert::IdentityMinus, Rhs, generic_product_impl<lambert::IdentityMinus, Rhs>> {
  template <typename Dest>
  static void scaleAndAddTo(Dest& dst, const lambert::IdentityMinus& lhs, const Rhs& rhs, const double& alpha) {
    lhs.addProduct(dst, rhs, alpha);
  }
};
}  // namespace Eigen::internal

namespace lambert {

KrylovReport solveIdentityMinus(const std::function<void(const double* x, double* y)>& applyM, const Eigen::VectorXd& b,
                                Eigen::VectorXd& x, double tolerance, int maxIterations) {
  KrylovReport report;
  if (!b.allFinite() || !x.allFinite()) return report;
  const double rhsNorm = b.norm();
  if (!(rhsNorm > 0)) {
    x.setZero();
    report.converged = true;
    return report;
  }
  const IdentityMinus system(applyM, b.size());
  Eigen::BiCGSTAB<IdentityMinus, Eigen::IdentityPreconditioner> solver;
  solver.compute(system);
  solver.setMaxIterations(maxIterations);
  solver.setTolerance(tolerance / rhsNorm);  // Eigen's is relative to ‖b‖₂
  x = solver.solveWithGuess(b, x);
  report.iterations = static_cast<int>(solver.iterations());
  report.converged = solver.info() == Eigen::Success && x.allFinite();
  return report;
}

}  // namespace lambert
