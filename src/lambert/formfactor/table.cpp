#include "lambert/formfactor/table.h"

#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "lambert/core/parallel.h"

namespace lambert {

FormFactorTable::FormFactorTable(const Mesh& patches, const RayCaster& caster, FormFactorOptions options)
    : patches_(patches), caster_(caster), options_(options) {
  options_.showProgress = false;
}

FormFactorMatrix FormFactorTable::matrix(std::span<const std::uint32_t> ids) {
  const std::size_t n = ids.size();
  struct Missing {
    std::uint32_t low, high;
    float value;
  };
  std::vector<Missing> missing;
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b) {
      std::uint32_t low = std::min(ids[a], ids[b]), high = std::max(ids[a], ids[b]);
      if (table_.find(key(low, high)) == table_.end()) missing.push_back({low, high, 0});
    }

  tbb::enumerable_thread_specific<PairFormFactors> estimators([&] { return PairFormFactors(patches_, caster_, options_); });
  parallelFor(0, missing.size(), [&](std::size_t k) {
    PairFormFactors& estimator = estimators.local();
    Missing& m = missing[k];
    m.value = estimator.culled(m.low, m.high) ? 0.0f : static_cast<float>(estimator.estimate(m.low, m.high));
  }, 64);
  for (const Missing& m : missing) table_.emplace(key(m.low, m.high), m.value);
  pairsEstimated_ += missing.size();
  pairsReused_ += n * (n - 1) / 2 - missing.size();

  FormFactorMatrix F = FormFactorMatrix::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b) {
      std::uint32_t low = std::min(ids[a], ids[b]), high = std::max(ids[a], ids[b]);
      const double fLowHigh = table_.at(key(low, high));
      const double fHighLow = fLowHigh * patches_.patches[low].area / patches_.patches[high].area;
      const bool aIsLow = ids[a] == low;
      F(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) = static_cast<float>(aIsLow ? fLowHigh : fHighLow);
      F(static_cast<Eigen::Index>(b), static_cast<Eigen::Index>(a)) = static_cast<float>(aIsLow ? fHighLow : fLowHigh);
    }
  return F;
}

void normalizeRows(FormFactorMatrix& F) {
  for (Eigen::Index i = 0; i < F.rows(); ++i) {
    double sum = F.row(i).cast<double>().sum();
    if (sum > 0) F.row(i) /= static_cast<float>(sum);
  }
}

}  // namespace lambert
