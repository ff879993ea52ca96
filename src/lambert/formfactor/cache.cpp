// Form-factor cache files (.lff). All fields are little-endian.
//
//   offset  size      field
//   0       8         magic "LMBRTFF\0"
//   8       4         u32 format version (kFormatVersion, 1)
//   12      4         u32 reserved, 0
//   16      8         u64 key: formFactorCacheKey of the mesh and options the matrix was computed for
//   24      8         u64 n, the number of patches
//   32      4·n·n     float32 F(i, j), row-major (row i is contiguous)
//   32+4n²  8         u64 checksum: XXH64 (seed 0) of every byte before it, header and payload
//
// A file is accepted only when every field checks out and its size is exactly 32 + 4n² + 8, so a
// truncated or extended file is caught before its checksum is even computed. XXH64 is the
// published xxHash algorithm (any xxh64sum of the first 32 + 4n² bytes reproduces the checksum); it
// hashes at several GB/s, so validating a large matrix costs about as much as reading it.
#include "lambert/formfactor/cache.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <system_error>

#include "lambert/core/timer.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;

// The payload is written from and read into the matrix's memory as it is; that is the file's
// little-endian IEEE layout only on such a machine (every target Embree supports is one).
static_assert(std::endian::native == std::endian::little, "cache payload assumes a little-endian host");
static_assert(sizeof(float) == 4 && std::numeric_limits<float>::is_iec559, "cache payload assumes IEEE binary32");

constexpr std::array<char, 8> kMagic = {'L', 'M', 'B', 'R', 'T', 'F', 'F', '\0'};
constexpr std::uint32_t kFormatVersion = 1;
// Part of the key, not the file: bump whenever computeFormFactors gives different results for
// the same mesh and options, so that files written by the old estimator stop matching.
constexpr std::uint32_t kEstimatorVersion = 2;
constexpr std::size_t kHeaderBytes = 32;
constexpr std::size_t kChecksumBytes = 8;

// Plain loads: the host is little-endian (asserted above), and a byte-by-byte assembly is not
// always folded into one load, which would make hashing, not reading, the cost of a cache hit.
std::uint64_t loadLe64(const unsigned char* p) {
  std::uint64_t v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

std::uint32_t loadLe32(const unsigned char* p) {
  std::uint32_t v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

void storeLe64(unsigned char* p, std::uint64_t v) {
  for (int k = 0; k < 8; ++k) p[k] = static_cast<unsigned char>(v >> (8 * k));
}

void storeLe32(unsigned char* p, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) p[k] = static_cast<unsigned char>(v >> (8 * k));
}

// XXH64 (Yann Collet's xxHash, 64-bit variant), fed incrementally so the header and the payload
// need not be copied into one buffer.
class Xxh64 {
 public:
  explicit Xxh64(std::uint64_t seed = 0)
      : acc_{seed + kP1 + kP2, seed + kP2, seed, seed - kP1}, seed_(seed) {}

  void update(const void* data, std::size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    total_ += size;
    if (buffered_ > 0) {
      std::size_t take = std::min(size, kStripe - buffered_);
      std::memcpy(buffer_.data() + buffered_, p, take);
      buffered_ += take;
      p += take;
      size -= take;
      if (buffered_ < kStripe) return;
      consumeStripe(buffer_.data());
      buffered_ = 0;
    }
    for (; size >= kStripe; p += kStripe, size -= kStripe) consumeStripe(p);
    if (size > 0) std::memcpy(buffer_.data(), p, size);
    buffered_ = size;
  }

  std::uint64_t digest() const {
    std::uint64_t h;
    if (total_ >= kStripe) {
      h = std::rotl(acc_[0], 1) + std::rotl(acc_[1], 7) + std::rotl(acc_[2], 12) + std::rotl(acc_[3], 18);
      for (std::uint64_t a : acc_) h = mergeRound(h, a);
    } else {
      h = seed_ + kP5;
    }
    h += total_;
    const unsigned char* p = buffer_.data();
    std::size_t left = buffered_;
    for (; left >= 8; p += 8, left -= 8) {
      h ^= round(0, loadLe64(p));
      h = std::rotl(h, 27) * kP1 + kP4;
    }
    if (left >= 4) {
      h ^= static_cast<std::uint64_t>(loadLe32(p)) * kP1;
      h = std::rotl(h, 23) * kP2 + kP3;
      p += 4;
      left -= 4;
    }
    for (; left > 0; ++p, --left) {
      h ^= *p * kP5;
      h = std::rotl(h, 11) * kP1;
    }
    h ^= h >> 33;
    h *= kP2;
    h ^= h >> 29;
    h *= kP3;
    h ^= h >> 32;
    return h;
  }

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
  std::uint64_t digest() const { return hash_.digest(); }

 private:
  Xxh64 hash_;
};

std::string hex(std::uint64_t v) {
  char text[19];
  std::snprintf(text, sizeof text, "0x%016" PRIx64, v);
  return text;
}

std::string errnoText(int error) { return std::generic_category().message(error); }

// Reads exactly size bytes unless the file ends first; returns the count read, or -1 with errno.
long long readFully(int fd, void* data, std::size_t size) {
  auto* p = static_cast<unsigned char*>(data);
  std::size_t done = 0;
  while (done < size) {
    ssize_t n = ::read(fd, p + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return -1;
    if (n == 0) break;
    done += static_cast<std::size_t>(n);
  }
  return static_cast<long long>(done);
}

// Writes all of size bytes; an empty string on success, else why not.
std::string writeFully(int fd, const void* data, std::size_t size) {
  const auto* p = static_cast<const unsigned char*>(data);
  std::size_t done = 0;
  while (done < size) {
    ssize_t n = ::write(fd, p + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return errnoText(errno);
    if (n == 0) return "nothing written";
    done += static_cast<std::size_t>(n);
  }
  return {};
}

class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }
  // close() is where some file systems (NFS) report a failed write, so a writer must see it.
  int close() {
    int rc = ::close(fd_);
    fd_ = -1;
    return rc;
  }

 private:
  int fd_;
};

// A name beside path that no other writer (thread or process) uses at the same time.
std::string temporaryPath(const std::string& path) {
  static std::atomic<std::uint64_t> counter{0};
  return path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
}

// The payload size of an n-patch matrix in bytes, or 0 when it would not fit in a size_t.
std::size_t payloadBytes(std::uint64_t n) {
  constexpr std::uint64_t kMax = std::numeric_limits<std::size_t>::max() - kHeaderBytes - kChecksumBytes;
  if (n != 0 && n > kMax / 4 / n) return 0;
  return static_cast<std::size_t>(n * n * 4);
}

}  // namespace

std::uint64_t formFactorCacheKey(const Mesh& mesh, const FormFactorOptions& options) {
  KeyHasher h;
  h.text("lambert form factors");
  h.u32(kFormatVersion);
  h.u32(kEstimatorVersion);
  // The method's name, not its enum value, so that reordering the enum does not alias old files.
  h.text(formFactorMethodName(options.method));
  h.u64(static_cast<std::uint64_t>(static_cast<std::int64_t>(options.samplePairs)));
  h.u64(static_cast<std::uint64_t>(static_cast<std::int64_t>(options.nearFieldBoost)));
  h.u64(options.seed);
  h.u64(mesh.positions.size());
  for (const Vec3& p : mesh.positions) h.vec3(p);
  h.u64(mesh.patches.size());
  for (const Patch& patch : mesh.patches) {
    h.u32(patch.numCorners);
    for (std::uint32_t k = 0; k < std::min<std::uint32_t>(patch.numCorners, 4); ++k) h.u32(patch.vertices[k]);
    h.u32(patch.surface);
    // Derived from the positions by makePatch, but computeFormFactors reads them as given.
    h.vec3(patch.normal);
    h.vec3(patch.centroid);
    h.f64(patch.area);
  }
  return h.digest();
}

std::string formFactorCachePath(const std::string& directory, std::uint64_t key) {
  char name[40];
  std::snprintf(name, sizeof name, "formfactors-%016" PRIx64 ".lff", key);
  return (fs::path(directory) / name).string();
}

Status saveFormFactors(const std::string& path, std::uint64_t key, const FormFactorMatrix& F) {
  if (path.empty()) return Error{"saveFormFactors: empty path"};
  if (F.rows() != F.cols())
    return Error{path + ": form-factor matrix is " + std::to_string(F.rows()) + "x" + std::to_string(F.cols()) +
                 ", not square"};
  const auto n = static_cast<std::uint64_t>(F.rows());
  const std::size_t payload = payloadBytes(n);
  if (payload == 0 && n != 0) return Error{path + ": " + std::to_string(n) + " patches are too many to store"};

  unsigned char header[kHeaderBytes] = {};
  std::memcpy(header, kMagic.data(), kMagic.size());
  storeLe32(header + 8, kFormatVersion);
  storeLe32(header + 12, 0);
  storeLe64(header + 16, key);
  storeLe64(header + 24, n);
  Xxh64 checksum;
  checksum.update(header, sizeof header);
  if (payload > 0) checksum.update(F.data(), payload);
  unsigned char trailer[kChecksumBytes];
  storeLe64(trailer, checksum.digest());

  std::error_code ec;
  fs::path parent = fs::path(path).parent_path();
  if (!parent.empty()) {
    fs::create_directories(parent, ec);
    if (ec) return Error{path + ": cannot create directory " + parent.string() + ": " + ec.message()};
  }

  const std::string temp = temporaryPath(path);
  // O_EXCL: never write into a file some other writer has open.
  FileDescriptor fd(::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666));
  if (fd.get() < 0) return Error{path + ": cannot create " + temp + ": " + errnoText(errno)};
  std::string why = writeFully(fd.get(), header, sizeof header);
  if (why.empty() && payload > 0) why = writeFully(fd.get(), F.data(), payload);
  if (why.empty()) why = writeFully(fd.get(), trailer, sizeof trailer);
  if (fd.close() != 0 && why.empty()) why = errnoText(errno);
  // No fsync: a file torn by a crash fails its size or checksum check and is recomputed, which is
  // cheaper than syncing every write.
  if (!why.empty()) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    return Error{path + ": cannot write " + temp + ": " + why};
  }
  fs::rename(temp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    return Error{path + ": cannot rename " + temp + " over it: " + ec.message()};
  }
  return Ok{};
}

Result<FormFactorMatrix> loadFormFactors(const std::string& path, std::uint64_t key, std::size_t expectedPatches) {
  FileDescriptor fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (fd.get() < 0) return Error{path + ": cannot open: " + errnoText(errno)};
  struct stat info {};
  if (::fstat(fd.get(), &info) != 0) return Error{path + ": cannot stat: " + errnoText(errno)};
  if (!S_ISREG(info.st_mode)) return Error{path + ": not a regular file"};
  const auto fileBytes = static_cast<std::uint64_t>(info.st_size);

  unsigned char header[kHeaderBytes] = {};
  const std::size_t headerRead = static_cast<std::size_t>(std::min<std::uint64_t>(fileBytes, kHeaderBytes));
  long long got = readFully(fd.get(), header, headerRead);
  if (got < 0) return Error{path + ": cannot read: " + errnoText(errno)};
  const auto have = static_cast<std::size_t>(got);
  // What there is of the magic must match, so that some other short file is not called truncated.
  if (std::memcmp(header, kMagic.data(), std::min(have, kMagic.size())) != 0)
    return Error{path + ": not a form-factor cache file (bad magic)"};
  if (have < kHeaderBytes)
    return Error{path + ": truncated: " + std::to_string(have) + " bytes, shorter than the " +
                 std::to_string(kHeaderBytes) + "-byte header"};
  const std::uint32_t version = loadLe32(header + 8);
  if (version != kFormatVersion)
    return Error{path + ": format version " + std::to_string(version) + ", expected " + std::to_string(kFormatVersion)};
  const std::uint32_t reserved = loadLe32(header + 12);
  if (reserved != 0) return Error{path + ": reserved header field is " + std::to_string(reserved) + ", expected 0"};
  const std::uint64_t storedKey = loadLe64(header + 16);
  if (storedKey != key)
    return Error{path + ": key mismatch: file is for " + hex(storedKey) + ", expected " + hex(key) +
                 " (written for another mesh or options)"};
  // Checked before anything is allocated: n comes from the file, expectedPatches from the caller.
  const std::uint64_t n = loadLe64(header + 24);
  if (n != expectedPatches)
    return Error{path + ": holds " + std::to_string(n) + " patches, expected " + std::to_string(expectedPatches)};
  const std::size_t payload = payloadBytes(n);
  if (payload == 0 && n != 0) return Error{path + ": " + std::to_string(n) + " patches are too many to load"};
  const std::uint64_t expectedBytes = kHeaderBytes + static_cast<std::uint64_t>(payload) + kChecksumBytes;
  if (fileBytes < expectedBytes)
    return Error{path + ": truncated: " + std::to_string(fileBytes) + " bytes, expected " +
                 std::to_string(expectedBytes) + " for " + std::to_string(n) + " patches"};
  if (fileBytes > expectedBytes)
    return Error{path + ": " + std::to_string(fileBytes - expectedBytes) + " trailing bytes after the checksum (" +
                 std::to_string(fileBytes) + " bytes, expected " + std::to_string(expectedBytes) + ")"};

  const auto size = static_cast<Eigen::Index>(n);
  FormFactorMatrix F(size, size);
  unsigned char trailer[kChecksumBytes];
  long long payloadRead = payload > 0 ? readFully(fd.get(), F.data(), payload) : 0;
  long long trailerRead = payloadRead == static_cast<long long>(payload) ? readFully(fd.get(), trailer, sizeof trailer) : 0;
  if (payloadRead < 0 || trailerRead < 0) return Error{path + ": cannot read: " + errnoText(errno)};
  // The size was right a moment ago; a short read now means the file shrank while being read.
  if (payloadRead != static_cast<long long>(payload) || trailerRead != static_cast<long long>(sizeof trailer))
    return Error{path + ": truncated while reading"};

  Xxh64 checksum;
  checksum.update(header, sizeof header);
  if (payload > 0) checksum.update(F.data(), payload);
  const std::uint64_t computed = checksum.digest(), stored = loadLe64(trailer);
  if (computed != stored)
    return Error{path + ": checksum mismatch (stored " + hex(stored) + ", computed " + hex(computed) +
                 "): the file is damaged"};
  return F;
}

CachedFormFactors cachedFormFactors(const Mesh& mesh, const RayCaster& caster, const FormFactorOptions& options,
                                    const std::string& cacheDirectory, FormFactorStats* stats) {
  CachedFormFactors result;
  if (cacheDirectory.empty()) {
    result.matrix = computeFormFactors(mesh, caster, options, stats);
    return result;
  }
  auto warn = [&](const std::string& line) {
    std::fprintf(stderr, "lambert: warning: %s\n", line.c_str());
    if (!result.warning.empty()) result.warning += '\n';
    result.warning += line;
  };

  const std::uint64_t key = formFactorCacheKey(mesh, options);
  result.path = formFactorCachePath(cacheDirectory, key);
  Timer timer;
  Result<FormFactorMatrix> loaded = loadFormFactors(result.path, key, mesh.numPatches());
  if (loaded) {
    result.matrix = std::move(*loaded);
    result.fromCache = true;
    if (stats) {
      *stats = FormFactorStats{};
      stats->seconds = timer.seconds();
    }
    return result;
  }
  // No file is the ordinary cache miss; anything else (unreadable, damaged, stale) is reported.
  std::error_code ec;
  const bool missing = fs::symlink_status(result.path, ec).type() == fs::file_type::not_found;
  if (!missing) warn(loaded.error().message + "; recomputing");

  result.matrix = computeFormFactors(mesh, caster, options, stats);
  if (Status saved = saveFormFactors(result.path, key, result.matrix); !saved)
    warn(saved.error().message + "; form factors not cached");
  return result;
}

}  // namespace lambert
