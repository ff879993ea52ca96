#pragma once
// Seed 003's master form-factor table: form factors between nodes of an adaptive mesh, keyed by
// the nodes' unique ids, computed the first time a pair is active together and found again every
// later time, never recomputed. matrix() assembles the dense matrix of the current active set.
#include <cstdint>
#include <span>
#include <unordered_map>

#include "lambert/formfactor/form_factors.h"

namespace lambert {

class FormFactorTable {
 public:
  // patches: every node as a patch (patch id = node id); it may grow between calls. caster: any
  // mesh of the same geometry, for visibility.
  FormFactorTable(const Mesh& patches, const RayCaster& caster, FormFactorOptions options);

  // F among the given patches: F(a, b) = F from patch ids[a] to patch ids[b]. Missing pairs are
  // estimated in parallel and stored; stored ones are reused.
  FormFactorMatrix matrix(std::span<const std::uint32_t> ids);

  std::uint64_t pairsEstimated() const { return pairsEstimated_; }  // ever computed (rays traced)
  std::uint64_t pairsReused() const { return pairsReused_; }        // answered from the table
  std::size_t pairsStored() const { return table_.size(); }

 private:
  static std::uint64_t key(std::uint32_t a, std::uint32_t b) { return (static_cast<std::uint64_t>(a) << 32) | b; }

  const Mesh& patches_;
  const RayCaster& caster_;
  FormFactorOptions options_;
  std::unordered_map<std::uint64_t, float> table_;  // (lower id, higher id) → F from lower to higher
  std::uint64_t pairsEstimated_ = 0;
  std::uint64_t pairsReused_ = 0;
};

// Seed 003's normalisation: each row divided by its sum, so every patch sends out exactly what it
// reflects. Rows that sum to zero are left alone. It hides estimation error in closed scenes, but
// breaks reciprocity and, where rows rightly sum to less than one (openings), adds energy.
void normalizeRows(FormFactorMatrix& F);

}  // namespace lambert
