// Master-table files (.lft), in cache_file.h's container (header, payload, XXH64 checksum, all
// little-endian):
//
//   offset  size      field
//   0       8         magic "LMBRTFT\0"
//   8       4         u32 format version (1)
//   12      4         u32 reserved, 0
//   16      8         u64 key: formFactorTableKey of the scene and options the pairs were computed for
//   24      8         u64 m, the number of pairs
//   32      20·m      m entries of 20 bytes, no padding:
//                       u64 address p, u64 address q (AdaptiveMesh::address, p < q),
//                       float32 F from the cell at p to the cell at q
//                     in ascending (p, q) order, each pair once
//   32+20m  8         u64 checksum: XXH64 (seed 0) of every byte before it
//
// F runs from the lower address to the higher, whatever the cells' ids were in the run that wrote
// it; F the other way is F · A_p / A_q (reciprocity), as matrix() derives it. The order makes a
// file's bytes depend only on its pairs, and lets a reader find a pair by binary search.
#include "lambert/flat/table.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "lambert/core/parallel.h"
#include "lambert/core/cache_file.h"

namespace lambert {
namespace {

constexpr cachefile::Format kFormat{{'L', 'M', 'B', 'R', 'T', 'F', 'T', '\0'}, 1, "form-factor table file"};
// Part of the key: bump when what an address means changes (AdaptiveMesh's grid or bit layout),
// as well as with the file format, so that old files stop matching.
constexpr std::uint32_t kAddressVersion = 1;
constexpr std::size_t kEntryBytes = 20;

struct Entry {
  std::uint64_t low, high;
  float value;
};

unsigned char* putEntry(unsigned char* b, const Entry& e) {
  cachefile::storeLe64(b, e.low);
  cachefile::storeLe64(b + 8, e.high);
  std::memcpy(b + 16, &e.value, 4);  // the host is little-endian IEEE (cache_file.h asserts it)
  return b + kEntryBytes;
}

}  // namespace

FormFactorTable::FormFactorTable(const Mesh& patches, const RayCaster& caster, FormFactorOptions options, AddressOf address)
    : patches_(patches), caster_(caster), options_(options), address_(std::move(address)) {
  LAMBERT_CHECK(isPairMethod(options.method));
  options_.showProgress = false;
}

bool FormFactorTable::findLoaded(std::uint64_t low, std::uint64_t high, float& value) const {
  auto row = loadedRows_.find(low);
  if (row == loadedRows_.end()) return false;
  const auto first = loadedHigh_.begin() + static_cast<std::ptrdiff_t>(row->second.begin);
  const auto last = loadedHigh_.begin() + static_cast<std::ptrdiff_t>(row->second.end);
  auto it = std::lower_bound(first, last, high);
  if (it == last || *it != high) return false;
  value = loadedValue_[static_cast<std::size_t>(it - loadedHigh_.begin())];
  return true;
}

namespace {

// A pair matrix() must add: estimated (or found in the loaded file), then stored.
struct MissingPair {
  std::uint32_t from, to;  // positions in ids; from: the one with the lower address
  float value;
  bool loaded;
};

// One std::unordered_map<std::uint64_t, float> entry: its node (next pointer, key, value, the
// allocator's header) and its bucket pointer at load factor 1.
constexpr double kTableEntryBytes = 8 + 8 + 4 + 4 + 8 + 8;

}  // namespace

double FormFactorTable::assemblyBytes(std::size_t patches) const {
  const double n = static_cast<double>(patches), pairs = n * (n - 1) / 2;
  const double newPairs = std::max(0.0, pairs - static_cast<double>(table_.size()));
  return n * n * sizeof(float) + newPairs * (sizeof(MissingPair) + kTableEntryBytes);
}

FormFactorMatrix FormFactorTable::matrix(std::span<const std::uint32_t> ids) {
  const std::size_t n = ids.size();
  // Once per call, not per pair: every pair's direction in the table follows its addresses.
  std::vector<std::uint64_t> addresses(n);
  for (std::size_t a = 0; a < n; ++a) addresses[a] = address(ids[a]);
  std::vector<MissingPair> missing;
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b) {
      if (table_.find(key(std::min(ids[a], ids[b]), std::max(ids[a], ids[b]))) != table_.end()) continue;
      LAMBERT_CHECK(addresses[a] != addresses[b]);
      const bool aFirst = addresses[a] < addresses[b];
      missing.push_back({static_cast<std::uint32_t>(aFirst ? a : b), static_cast<std::uint32_t>(aFirst ? b : a), 0, false});
    }

  // The loaded file first: a pair found there costs a lookup, not rays.
  tbb::enumerable_thread_specific<PairFormFactors> estimators([&] { return PairFormFactors(patches_, caster_, options_); });
  const bool anyLoaded = !loadedRows_.empty();
  parallelFor(0, missing.size(), [&](std::size_t k) {
    MissingPair& m = missing[k];
    if (anyLoaded && findLoaded(addresses[m.from], addresses[m.to], m.value)) {
      m.loaded = true;
      return;
    }
    PairFormFactors& estimator = estimators.local();
    const std::uint32_t from = ids[m.from], to = ids[m.to];
    m.value = estimator.culled(from, to) ? 0.0f : static_cast<float>(estimator.estimate(from, to));
  }, 64);
  std::uint64_t loaded = 0;
  for (const MissingPair& m : missing) {
    table_.emplace(key(std::min(ids[m.from], ids[m.to]), std::max(ids[m.from], ids[m.to])), m.value);
    loaded += m.loaded;
  }
  pairsLoaded_ += loaded;
  pairsEstimated_ += missing.size() - loaded;
  pairsReused_ += n * (n - 1) / 2 - missing.size();

  FormFactorMatrix F = FormFactorMatrix::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b) {
      const bool aFirst = addresses[a] < addresses[b];
      const std::size_t from = aFirst ? a : b, to = aFirst ? b : a;
      const double forward = table_.at(key(std::min(ids[a], ids[b]), std::max(ids[a], ids[b])));
      const double reverse = forward * patches_.patches[ids[from]].area / patches_.patches[ids[to]].area;
      F(static_cast<Eigen::Index>(from), static_cast<Eigen::Index>(to)) = static_cast<float>(forward);
      F(static_cast<Eigen::Index>(to), static_cast<Eigen::Index>(from)) = static_cast<float>(reverse);
    }
  return F;
}

Result<std::size_t> FormFactorTable::save(const std::string& path, std::uint64_t key) const {
  // The stored pairs in address order. Each patch's address is ranked once; the pairs are then
  // bucketed by the rank of their lower address (a counting sort) and each bucket is ordered by
  // the higher: much cheaper than sorting all pairs by two 64-bit addresses.
  const std::size_t n = patches_.numPatches();
  std::vector<std::uint64_t> addresses(n);
  for (std::size_t id = 0; id < n; ++id) addresses[id] = address(static_cast<std::uint32_t>(id));
  std::vector<std::uint32_t> byAddress(n);
  std::iota(byAddress.begin(), byAddress.end(), 0u);
  std::sort(byAddress.begin(), byAddress.end(), [&](std::uint32_t x, std::uint32_t y) { return addresses[x] < addresses[y]; });
  std::vector<std::uint32_t> rank(n);
  for (std::uint32_t r = 0; r < n; ++r) rank[byAddress[r]] = r;

  struct Ranked {
    std::uint32_t low, high;
    float value;
  };
  std::vector<Ranked> ranked;
  ranked.reserve(table_.size());
  std::vector<std::size_t> rowStart(n + 1, 0);
  for (const auto& [pair, value] : table_) {
    const std::uint32_t x = rank[pair >> 32], y = rank[pair & 0xffffffffu];
    ranked.push_back({std::min(x, y), std::max(x, y), value});
    ++rowStart[std::min(x, y) + 1];
  }
  for (std::size_t r = 0; r < n; ++r) rowStart[r + 1] += rowStart[r];
  struct Cell {
    std::uint32_t high;
    float value;
  };
  std::vector<Cell> rows(ranked.size());
  std::vector<std::size_t> next(rowStart.begin(), rowStart.end() - 1);
  for (const Ranked& e : ranked) rows[next[e.low]++] = {e.high, e.value};
  parallelFor(0, n, [&](std::size_t r) {
    std::sort(rows.begin() + static_cast<std::ptrdiff_t>(rowStart[r]), rows.begin() + static_cast<std::ptrdiff_t>(rowStart[r + 1]),
              [](const Cell& x, const Cell& y) { return x.high < y.high; });
  });

  // Merged with the loaded pairs (in order already), each pair once: a pair taken from the file is
  // among the stored ones too, with the same value.
  std::vector<unsigned char> bytes((rows.size() + loadedLow_.size()) * kEntryBytes);
  unsigned char* out = bytes.data();
  std::size_t l = 0;
  auto loadedUpTo = [&](std::uint64_t low, std::uint64_t high) {
    for (; l < loadedLow_.size() && (loadedLow_[l] < low || (loadedLow_[l] == low && loadedHigh_[l] < high)); ++l)
      out = putEntry(out, {loadedLow_[l], loadedHigh_[l], loadedValue_[l]});
    if (l < loadedLow_.size() && loadedLow_[l] == low && loadedHigh_[l] == high) ++l;
  };
  for (std::size_t r = 0; r < n; ++r) {
    const std::uint64_t low = addresses[byAddress[r]];
    for (std::size_t k = rowStart[r]; k < rowStart[r + 1]; ++k) {
      const std::uint64_t high = addresses[byAddress[rows[k].high]];
      loadedUpTo(low, high);
      out = putEntry(out, {low, high, rows[k].value});
    }
  }
  for (; l < loadedLow_.size(); ++l) out = putEntry(out, {loadedLow_[l], loadedHigh_[l], loadedValue_[l]});
  bytes.resize(static_cast<std::size_t>(out - bytes.data()));
  const std::size_t count = bytes.size() / kEntryBytes;
  if (Status written = cachefile::writeFile(path, kFormat, key, count, bytes); !written) return written.error();
  return count;
}

Result<std::size_t> FormFactorTable::load(const std::string& path, std::uint64_t key) {
  Result<cachefile::Reader> opened = cachefile::Reader::open(path, kFormat, key);
  if (!opened) return opened.error();
  cachefile::Reader& reader = *opened;
  // The count is checked against the file's size before anything is allocated for it.
  const std::uint64_t m = reader.count();
  constexpr std::uint64_t kMaxPairs =
      (std::numeric_limits<std::size_t>::max() - cachefile::kHeaderBytes - cachefile::kChecksumBytes) / kEntryBytes;
  if (m > kMaxPairs) return Error{path + ": " + std::to_string(m) + " pairs are too many to load"};
  const auto count = static_cast<std::size_t>(m);
  if (Status sized = reader.checkSize(count * kEntryBytes, std::to_string(m) + " pairs"); !sized) return sized.error();
  std::vector<unsigned char> bytes(count * kEntryBytes);
  if (Status read = reader.readPayload(bytes.data()); !read) return read.error();

  // The checksum proves the bytes are what some writer wrote, not that the writer was right: the
  // order and values are checked too, since lookups depend on the one and solutions on the other.
  std::vector<std::uint64_t> lows(count), highs(count);
  std::vector<float> values(count);
  std::unordered_map<std::uint64_t, Row> rows;
  std::size_t rowBegin = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const unsigned char* e = bytes.data() + k * kEntryBytes;
    lows[k] = cachefile::loadLe64(e);
    highs[k] = cachefile::loadLe64(e + 8);
    std::memcpy(&values[k], e + 16, 4);
    if (lows[k] >= highs[k])
      return Error{path + ": pair " + std::to_string(k) + " is not in address order (" + cachefile::hex(lows[k]) +
                   " before " + cachefile::hex(highs[k]) + ")"};
    if (k > 0 && (lows[k] < lows[k - 1] || (lows[k] == lows[k - 1] && highs[k] <= highs[k - 1])))
      return Error{path + ": pair " + std::to_string(k) + " is out of order or repeated"};
    if (!std::isfinite(values[k]) || values[k] < 0)
      return Error{path + ": pair " + std::to_string(k) + " has form factor " + std::to_string(values[k])};
    if (k > 0 && lows[k] != lows[k - 1]) {
      rows.emplace(lows[k - 1], Row{rowBegin, k});
      rowBegin = k;
    }
  }
  if (count > 0) rows.emplace(lows[count - 1], Row{rowBegin, count});
  loadedLow_ = std::move(lows);
  loadedHigh_ = std::move(highs);
  loadedValue_ = std::move(values);
  loadedRows_ = std::move(rows);
  return count;
}

std::uint64_t formFactorTableKey(const Scene& scene, const QuadtreeOptions& quadtree, const FormFactorOptions& options) {
  cachefile::KeyHasher h;
  h.text("lambert form-factor table");
  h.u32(kFormat.version);
  h.u32(kAddressVersion);
  h.u32(cachefile::kEstimatorVersion);
  // The method's name, not its enum value, so that reordering the enum does not alias old files.
  h.text(formFactorMethodName(options.method));
  h.i64(options.samplePairs);
  h.i64(options.nearFieldBoost);
  h.u64(options.seed);
  h.f64(quadtree.baseEdgeLength);
  h.i64(quadtree.maxLevel);
  h.u64(scene.surfaces.size());
  for (const Surface& surface : scene.surfaces) {
    h.u64(surface.vertices.size());
    for (const Vec3& v : surface.vertices) h.vec3(v);
  }
  // The quad-tree takes single-quad surfaces only (Surface::faces empty or one face of all four
  // vertices in order), so faces add nothing that the vertices do not already fix.
  return h.digest();
}

std::string formFactorTablePath(const std::string& directory, std::uint64_t key) {
  return cachefile::keyedPath(directory, "formfactor-table-", key, ".lft");
}

void normalizeRows(FormFactorMatrix& F) {
  for (Eigen::Index i = 0; i < F.rows(); ++i) {
    double sum = F.row(i).cast<double>().sum();
    if (sum > 0) F.row(i) /= static_cast<float>(sum);
  }
}

std::size_t boundRowSums(FormFactorMatrix& F, std::span<const Rgb> albedo) {
  LAMBERT_CHECK(albedo.size() == static_cast<std::size_t>(F.rows()));
  std::size_t scaled = 0;
  for (Eigen::Index i = 0; i < F.rows(); ++i) {
    const double sum = F.row(i).cast<double>().sum();
    const double rho = albedo[static_cast<std::size_t>(i)].maxComponent();
    if (!(rho * sum > rowContractionBound(rho))) continue;
    // Rounded down, so that the float row sums to at most 1.
    F.row(i) *= std::nextafter(static_cast<float>(1 / sum), 0.0f);
    ++scaled;
  }
  return scaled;
}

}  // namespace lambert
