#pragma once
// Internal to the caches, not part of the library's interface: what the uniform mesh's matrix
// cache (cache.cpp, .lff) and the adaptive master table's file (table.cpp, .lft; opened by
// flat/adaptive_method.cpp) share, so both make the same promises with one piece of code: a key hashed with XXH64 from a fixed little-endian encoding of its inputs, and files made
// of a 32-byte header, a payload and a checksum, written atomically and trusted only once every
// check has passed.
//
// Every such file, all fields little-endian:
//
//   offset  size      field
//   0       8         magic (which kind of file)
//   8       4         u32 format version
//   12      4         u32 reserved, 0
//   16      8         u64 key: a hash of everything the payload was computed from
//   24      8         u64 count: what the payload holds (patches, pairs); its size follows from it
//   32      P         payload
//   32+P    8         u64 checksum: XXH64 (seed 0) of every byte before it, header and payload
//
// XXH64 is the published xxHash algorithm (any xxh64sum of the first 32 + P bytes reproduces the
// checksum); it hashes at several GB/s, so validating a file costs about as much as reading it.
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/vec3.h"

namespace lambert::cachefile {

// Payloads are written from and read into memory as it is; that is the files' little-endian IEEE
// layout only on such a machine (every target Embree supports is one).
static_assert(std::endian::native == std::endian::little, "cache files assume a little-endian host");
static_assert(sizeof(float) == 4 && std::numeric_limits<float>::is_iec559, "cache files assume IEEE binary32");

// Part of every key, not of the files: bump whenever PairFormFactors / computeFormFactors give
// different results for the same mesh and options, so that files written by the old estimator
// stop matching.
inline constexpr std::uint32_t kEstimatorVersion = 3;

inline constexpr std::size_t kHeaderBytes = 32;
inline constexpr std::size_t kChecksumBytes = 8;

// Plain loads: the host is little-endian (asserted above), and a byte-by-byte assembly is not
// always folded into one load, which would make hashing, not reading, the cost of a cache hit.
inline std::uint64_t loadLe64(const unsigned char* p) {
  std::uint64_t v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

inline std::uint32_t loadLe32(const unsigned char* p) {
  std::uint32_t v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

inline void storeLe64(unsigned char* p, std::uint64_t v) {
  for (int k = 0; k < 8; ++k) p[k] = static_cast<unsigned char>(v >> (8 * k));
}

inline void storeLe32(unsigned char* p, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) p[k] = static_cast<unsigned char>(v >> (8 * k));
}

// XXH64 (Yann Collet's xxHash, 64-bit variant), fed incrementally so a header and a payload need
// not be copied into one buffer.
class Xxh64 {
 public:
  explicit Xxh64(std::uint64_t seed = 0) : acc_{seed + kP1 + kP2, seed + kP2, seed, seed - kP1}, seed_(seed) {}

  void update(const void* data, std::size_t size);
  std::uint64_t digest() const;

 private:
  static constexpr std::uint64_t kP1 = 0x9E3779B185EBCA87ULL;
  static constexpr std::uint64_t kP2 = 0xC2B2AE3D27D4EB4FULL;
  static constexpr std::uint64_t kP3 = 0x165667B19E3779F9ULL;
  static constexpr std::uint64_t kP4 = 0x85EBCA77C2B2AE63ULL;
  static constexpr std::uint64_t kP5 = 0x27D4EB2F165667C5ULL;
  static constexpr std::size_t kStripe = 32;

  static std::uint64_t round(std::uint64_t acc, std::uint64_t input) {
    acc += input * kP2;
    return std::rotl(acc, 31) * kP1;
  }
  static std::uint64_t mergeRound(std::uint64_t h, std::uint64_t acc) {
    h ^= round(0, acc);
    return h * kP1 + kP4;
  }
  void consumeStripe(const unsigned char* p) {
    for (int lane = 0; lane < 4; ++lane) acc_[lane] = round(acc_[lane], loadLe64(p + 8 * lane));
  }

  std::array<std::uint64_t, 4> acc_;
  std::uint64_t seed_;
  std::uint64_t total_ = 0;
  std::array<unsigned char, kStripe> buffer_{};
  std::size_t buffered_ = 0;
};

// Feeds values to a hash in a fixed little-endian encoding, so a key does not depend on how the
// machine lays out structs (padding, field order).
class KeyHasher {
 public:
  void u32(std::uint32_t v) {
    unsigned char b[4];
    storeLe32(b, v);
    hash_.update(b, 4);
  }
  void u64(std::uint64_t v) {
    unsigned char b[8];
    storeLe64(b, v);
    hash_.update(b, 8);
  }
  void i64(std::int64_t v) { u64(static_cast<std::uint64_t>(v)); }
  void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
  void vec3(const Vec3& v) {
    f64(v.x);
    f64(v.y);
    f64(v.z);
  }
  void text(const std::string& s) {
    u64(s.size());
    hash_.update(s.data(), s.size());
  }
  // An array's bytes as one value: its length and the XXH64 of its memory (exact bits).
  template <typename T>
  void array(const std::vector<T>& values) {
    Xxh64 digest;
    if (!values.empty()) digest.update(values.data(), values.size() * sizeof(T));
    u64(values.size());
    u64(digest.digest());
  }
  std::uint64_t digest() const { return hash_.digest(); }

 private:
  Xxh64 hash_;
};

// "0x" and 16 hex digits, for messages.
std::string hex(std::uint64_t v);
// "<directory>/<prefix><16 hex digits><suffix>": a cache file's name for a key.
std::string keyedPath(const std::string& directory, const char* prefix, std::uint64_t key, const char* suffix);
// Whether nothing at all is at path: the ordinary cache miss, not worth a warning.
bool isMissing(const std::string& path);

// One kind of file.
struct Format {
  std::array<char, 8> magic;
  std::uint32_t version;
  const char* name;  // what it is, for "not a <name> (bad magic)"
};

// Writes the header (format, key, count), payload and checksum to path atomically: into a
// temporary file in the same directory, renamed over path only once complete, so readers see the
// old file or the new one, never a partial one. Creates the directory; on failure leaves nothing
// behind and the Error names the path.
Status writeFile(const std::string& path, const Format& format, std::uint64_t key, std::uint64_t count,
                 std::span<const unsigned char> payload);

// A file being read. Every problem is an Error of the form "<path>: <what is wrong>". The reading
// goes in three steps so that nothing is allocated for a size the file does not back up:
//   open()       checks the magic (what there is of it, so another short file is not called
//                truncated), the header's length, version, reserved field and key;
//   checkSize()  the caller has checked count() and turned it into a payload size; the file must
//                be exactly header + payload + checksum long;
//   readPayload() reads it into the caller's memory and verifies the checksum.
class Reader {
 public:
  static Result<Reader> open(const std::string& path, const Format& format, std::uint64_t key);

  Reader(Reader&& other) noexcept;
  Reader& operator=(Reader&&) = delete;
  Reader(const Reader&) = delete;
  ~Reader();

  std::uint64_t count() const { return loadLe64(header_.data() + 24); }
  // counted names count() in messages, e.g. "12 patches".
  Status checkSize(std::size_t payloadBytes, const std::string& counted);
  Status readPayload(void* data);

 private:
  Reader(std::string path, int fd, std::uint64_t fileBytes) : path_(std::move(path)), fd_(fd), fileBytes_(fileBytes) {}

  std::string path_;
  int fd_ = -1;
  std::uint64_t fileBytes_ = 0;
  std::array<unsigned char, kHeaderBytes> header_{};
  std::size_t payloadBytes_ = 0;
  bool sized_ = false;
};

}  // namespace lambert::cachefile
