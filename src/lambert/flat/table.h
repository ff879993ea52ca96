#pragma once
// The master form-factor table: form factors between nodes of an adaptive mesh, keyed by
// the nodes' unique ids, computed the first time a pair is active together and found again every
// later time, never recomputed. matrix() assembles the dense matrix of the current active set.
//
// The table outlives a run: save() writes it to disk and load() reads it back in
// a later run, so cells activated before are not computed again. Ids are not stable across runs
// (they follow the order cells were refined in), so the file names each cell by its stable
// address (AdaptiveMesh::address) instead; the file format is documented at the top of table.cpp.
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/flat/form_factors.h"
#include "lambert/solve/row_contraction.h"
#include "lambert/flat/quadtree.h"
#include "lambert/scene/scene.h"

namespace lambert {

class FormFactorTable {
 public:
  // A patch's name that is the same in every run for the same cell (AdaptiveMesh::address); two
  // patches never share one.
  using AddressOf = std::function<std::uint64_t(std::uint32_t id)>;

  // patches: every node as a patch (patch id = node id); it may grow between calls. caster: any
  // mesh of the same geometry, for visibility. address: each patch's stable address; without
  // one, a patch's id is its address (fine for a table that is never saved).
  FormFactorTable(const Mesh& patches, const RayCaster& caster, FormFactorOptions options, AddressOf address = {});

  // F among the given patches: F(a, b) = F from patch ids[a] to patch ids[b]. Missing pairs are
  // taken from the loaded file when it has them, else estimated, in parallel, and stored; stored
  // ones are reused.
  FormFactorMatrix matrix(std::span<const std::uint32_t> ids);

  std::uint64_t pairsEstimated() const { return pairsEstimated_; }  // ever computed (rays traced)
  std::uint64_t pairsLoaded() const { return pairsLoaded_; }        // taken from the loaded file
  std::uint64_t pairsReused() const { return pairsReused_; }        // answered from the table
  std::size_t pairsStored() const { return table_.size(); }

  // What matrix() of `patches` patches allocates, in bytes, for the memory check before it
  // (core/memory.h): the dense matrix, and each pair it adds to the table (held in a working list
  // while it is estimated, then as a hash-table entry). Pairs already stored may be among them,
  // so at least n(n − 1)/2 − pairsStored() are new: a lower bound, which refuses only what
  // cannot fit.
  double assemblyBytes(std::size_t patches) const;

  // Writes every pair known (stored, and loaded but not used in this run) to path atomically, as
  // cache_file.h's writeFile does, and returns how many; the Error names the path.
  Result<std::size_t> save(const std::string& path, std::uint64_t key) const;
  // Reads a file written by save() with the same key, for matrix() to use before estimating;
  // returns how many pairs it holds, and replaces what an earlier load read. Any problem
  // (missing, truncated, damaged, another format or key, pairs out of order) is an Error
  // "<path>: <why>", and the table is left as it was.
  Result<std::size_t> load(const std::string& path, std::uint64_t key);

 private:
  static std::uint64_t key(std::uint32_t a, std::uint32_t b) { return (static_cast<std::uint64_t>(a) << 32) | b; }
  std::uint64_t address(std::uint32_t id) const { return address_ ? address_(id) : id; }
  // F from the patch at address low to the one at high (low < high), if the loaded file has it.
  bool findLoaded(std::uint64_t low, std::uint64_t high, float& value) const;

  const Mesh& patches_;
  const RayCaster& caster_;
  FormFactorOptions options_;
  AddressOf address_;
  // (lower id, higher id) → F from whichever of the two has the lower address to the other. The
  // direction follows addresses, not ids, so a value means the same in every run and goes to and
  // from the file as it is, with no reciprocity conversion (and no rounding) on the way.
  std::unordered_map<std::uint64_t, float> table_;
  // The loaded file's pairs, in its order: ascending by (lower address, higher address).
  // loadedRows_ maps a lower address to its run of entries, where the higher addresses ascend.
  struct Row {
    std::size_t begin = 0, end = 0;
  };
  std::unordered_map<std::uint64_t, Row> loadedRows_;
  std::vector<std::uint64_t> loadedLow_, loadedHigh_;
  std::vector<float> loadedValue_;
  std::uint64_t pairsEstimated_ = 0;
  std::uint64_t pairsLoaded_ = 0;
  std::uint64_t pairsReused_ = 0;
};

// Identifies an adaptive master table's file: a 64-bit hash (XXH64) of every input that changes
// its form factors: each surface's vertex count and positions (exact bits, in order: a surface's
// index is part of its cells' addresses), the quad-tree options, and the form-factor options
// method, samplePairs, nearFieldBoost and seed (not showProgress), with the file's format and the
// estimator's versions.
std::uint64_t formFactorTableKey(const Scene& scene, const QuadtreeOptions& quadtree, const FormFactorOptions& options);

// The file for a key inside a cache directory: <directory>/formfactor-table-<16 hex digits>.lft
std::string formFactorTablePath(const std::string& directory, std::uint64_t key);

// Row normalisation: each row divided by its sum, so every patch sends out exactly what it
// reflects. Rows that sum to zero are left alone. It hides estimation error in closed scenes, but
// breaks reciprocity and, where rows rightly sum to less than one (openings), adds energy.
void normalizeRows(FormFactorMatrix& F);

// Bounds what each patch i gathers so that B = E + ρFB is a contraction: a row summing to S
// with ρ_i·S above kRowContraction (ρ_i: the largest channel of the patch's albedo) is an
// estimate far above the truth (a patch gathers at most its whole hemisphere, S ≤ 1) and is
// scaled to sum 1; the others are left alone. Hemi-cube and hemisphere-ray rows sum to at most 1
// by construction; the point-to-point estimate (cos cos / π r² × A_j, unbounded close by) and pair
// estimates filled in by reciprocity (F_ji = F_ij A_i / A_j, a small patch close to large ones)
// do not, and a row with ρS ≥ 1 can make every solver diverge. Rows above 1 by less are
// estimation noise around a true sum of at most 1, balanced by rows below it: scaling them too
// would bias closed scenes dark. Returns how many rows it scaled.
std::size_t boundRowSums(FormFactorMatrix& F, std::span<const Rgb> albedo);

}  // namespace lambert
